#include "hw/packets.h"

#include <stdexcept>
#include <string>
#include <tuple>

namespace gpusim {
namespace {

bool same_triangle(const std::shared_ptr<const RasterPrimitive>& a,
                   const std::shared_ptr<const RasterPrimitive>& b) {
  if (a == b) return true;
  return a && b && *a == *b;
}

std::ostream& print_vec(std::ostream& os, const glm::vec4& v) {
  return os << "(" << v.x << ", " << v.y << ", " << v.z << ", " << v.w << ")";
}

}  // namespace

std::ostream& operator<<(std::ostream& os, PacketKind k) {
  switch (k) {
    case PacketKind::work:
      return os << "work";
    case PacketKind::clear:
      return os << "clear";
    case PacketKind::end_of_frame:
      return os << "end_of_frame";
  }
  return os << "invalid";
}

std::ostream& operator<<(std::ostream& os, const Command& c) {
  os << "Command{" << c.kind;
  if (c.kind == PacketKind::work) os << " draw " << c.draw_id;
  return os << "}";
}

std::ostream& operator<<(std::ostream& os, const ClippedPrimitive& t) {
  os << "ClippedPrimitive{" << t.kind;
  if (t.kind != PacketKind::work) return os << "}";
  os << " draw " << t.draw_id << " prim " << t.primitive_id;
  for (const ClippedVertex& v : t.v) {
    os << " [" << v.x << ", " << v.y << ", " << v.z << ", 1/w " << v.inv_w << "]";
  }
  return os << "}";
}

int log2_side(unsigned side) {
  if (side == 0 || (side & (side - 1)) != 0) {
    throw std::invalid_argument("side " + std::to_string(side) + " is not a power of two");
  }
  int n = 0;
  while ((1u << n) < side) ++n;
  return n;
}

bool RasterPrimitive::operator==(const RasterPrimitive& o) const {
  auto tie = [](const RasterPrimitive& t) {
    return std::tie(t.draw_id, t.primitive_id, t.x, t.y, t.area2, t.edge, t.x0, t.y0, t.x1, t.y1,
                    t.z, t.inv_w, t.color_over_w, t.flat_color, t.has_depth_offset, t.depth_offset);
  };
  return tie(*this) == tie(o);
}

std::ostream& operator<<(std::ostream& os, const RasterPrimitive& t) {
  os << "RasterPrimitive{draw " << t.draw_id << " prim " << t.primitive_id;
  for (int i = 0; i < 3; ++i) os << " (" << t.x[i] << ", " << t.y[i] << ", z " << t.z[i] << ")";
  os << " area2 " << t.area2 << " box [" << t.x0 << ".." << t.x1 << "] x [" << t.y0 << ".." << t.y1
     << "] flat ";
  print_vec(os, t.flat_color);
  if (t.has_depth_offset) os << " offset " << t.depth_offset;
  return os << "}";
}

bool SetupPacket::operator==(const SetupPacket& o) const {
  return kind == o.kind && same_triangle(triangle, o.triangle);
}

std::ostream& operator<<(std::ostream& os, const SetupPacket& p) {
  os << "SetupPacket{" << p.kind;
  if (p.triangle) os << " " << *p.triangle;
  return os << "}";
}

bool StampBatch::operator==(const StampBatch& o) const {
  return kind == o.kind && same_triangle(triangle, o.triangle) && stamps == o.stamps &&
         depth == o.depth;
}

std::ostream& operator<<(std::ostream& os, const StampBatch& b) {
  os << "StampBatch{" << b.kind;
  if (b.triangle) os << " prim " << b.triangle->primitive_id;
  os << " " << b.stamps.size() << " stamps";
  for (const Stamp& s : b.stamps)
    os << " (" << s.x << ", " << s.y << ": " << std::hex << s.mask << std::dec << ")";
  return os << "}";
}

bool ShadedStampBatch::operator==(const ShadedStampBatch& o) const {
  return kind == o.kind && same_triangle(triangle, o.triangle) && stamps == o.stamps &&
         colors == o.colors;
}

std::ostream& operator<<(std::ostream& os, const ShadedStampBatch& b) {
  os << "ShadedStampBatch{" << b.kind;
  if (b.triangle) os << " prim " << b.triangle->primitive_id;
  return os << " " << b.stamps.size() << " stamps, " << b.colors.size() << " colours}";
}

}  // namespace gpusim
