#include "hw/packets.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <tuple>

namespace gpusim {
namespace {

bool same_primitive(const std::shared_ptr<const RasterPrimitive>& a,
                    const std::shared_ptr<const RasterPrimitive>& b) {
  if (a == b) return true;
  return a && b && *a == *b;
}

// The layout, which knows how many components are in use, is per draw; the
// components after the last non-zero one (0 in every unused component) are
// left out.
std::ostream& print_varyings(std::ostream& os, const Varyings& v) {
  size_t n = v.size();
  while (n > 0 && v[n - 1] == 0.0f) --n;
  os << "(";
  for (size_t i = 0; i < n; ++i) os << (i ? ", " : "") << v[i];
  return os << ")";
}

std::ostream& print_primitive(std::ostream& os, PrimitiveKind kind, uint8_t vertex_count) {
  return os << kind << "/" << unsigned{vertex_count};
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

std::ostream& operator<<(std::ostream& os, PrimitiveKind k) {
  switch (k) {
    case PrimitiveKind::point:
      return os << "point";
    case PrimitiveKind::line:
      return os << "line";
    case PrimitiveKind::triangle:
      return os << "triangle";
  }
  return os << "invalid";
}

bool ClippedPrimitive::operator==(const ClippedPrimitive& o) const {
  // Vertices from vertex_count on are unused and not compared.
  const size_t n = std::min<size_t>(vertex_count, kMaxPrimitiveVertices);
  return kind == o.kind && primitive_kind == o.primitive_kind && vertex_count == o.vertex_count &&
         draw_id == o.draw_id && primitive_id == o.primitive_id &&
         std::equal(v.begin(), v.begin() + n, o.v.begin()) && flat_varyings == o.flat_varyings &&
         draw_first == o.draw_first && draw_last == o.draw_last;
}

std::ostream& operator<<(std::ostream& os, const ClippedPrimitive& t) {
  os << "ClippedPrimitive{" << t.kind;
  if (t.kind != PacketKind::work) return os << "}";
  os << " ";
  print_primitive(os, t.primitive_kind, t.vertex_count);
  os << " draw " << t.draw_id << " prim " << t.primitive_id;
  for (size_t i = 0; i < t.vertex_count && i < kMaxPrimitiveVertices; ++i) {
    const ClippedVertex& v = t.v[i];
    os << " [" << v.x << ", " << v.y << ", " << v.z << ", 1/w " << v.inv_w << "]";
  }
  os << " flat ";
  print_varyings(os, t.flat_varyings);
  if (t.primitive_kind == PrimitiveKind::line) {
    os << " ends " << (t.draw_first ? "drawn" : "skipped") << "/"
       << (t.draw_last ? "drawn" : "skipped");
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
    return std::tie(t.primitive_kind, t.vertex_count, t.draw_id, t.primitive_id, t.x, t.y, t.area2,
                    t.edge, t.coverage, t.coverage_count, t.x0, t.y0, t.x1, t.y1, t.z, t.inv_w,
                    t.varyings_over_w, t.flat_varyings, t.has_depth_offset, t.depth_offset,
                    t.line_rule, t.width, t.ia_x, t.ia_y, t.ib_x, t.ib_y, t.draw_first,
                    t.draw_last);
  };
  return tie(*this) == tie(o);
}

std::ostream& operator<<(std::ostream& os, const RasterPrimitive& t) {
  os << "RasterPrimitive{";
  print_primitive(os, t.primitive_kind, t.vertex_count);
  os << " draw " << t.draw_id << " prim " << t.primitive_id;
  for (size_t i = 0; i < t.vertex_count && i < 3; ++i)
    os << " (" << t.x[i] << ", " << t.y[i] << ", z " << t.z[i] << ")";
  os << " area2 " << t.area2 << " box [" << t.x0 << ".." << t.x1 << "] x [" << t.y0 << ".." << t.y1
     << "] flat ";
  print_varyings(os, t.flat_varyings);
  if (t.has_depth_offset) os << " offset " << t.depth_offset;
  if (t.line_rule != LineRule::none) {
    os << (t.line_rule == LineRule::bresenham   ? " bresenham"
           : t.line_rule == LineRule::rectangle ? " rectangle"
                                                : " diamond_exit")
       << " width " << t.width;
  }
  if (t.line_rule == LineRule::bresenham) {
    os << " pixels (" << t.ia_x << ", " << t.ia_y << ")-(" << t.ib_x << ", " << t.ib_y << ") ends "
       << (t.draw_first ? "drawn" : "skipped") << "/" << (t.draw_last ? "drawn" : "skipped");
  }
  return os << "}";
}

bool SetupPacket::operator==(const SetupPacket& o) const {
  return kind == o.kind && same_primitive(primitive, o.primitive);
}

std::ostream& operator<<(std::ostream& os, const SetupPacket& p) {
  os << "SetupPacket{" << p.kind;
  if (p.primitive) os << " " << *p.primitive;
  return os << "}";
}

bool StampBatch::operator==(const StampBatch& o) const {
  return kind == o.kind && same_primitive(primitive, o.primitive) && stamps == o.stamps &&
         samples == o.samples && hz_seq == o.hz_seq;
}

std::ostream& operator<<(std::ostream& os, const StampBatch& b) {
  os << "StampBatch{" << b.kind;
  if (b.primitive) os << " prim " << b.primitive->primitive_id;
  os << " " << b.stamps.size() << " stamps";
  for (const Stamp& s : b.stamps)
    os << " (" << s.x << ", " << s.y << ": " << std::hex << s.mask << std::dec << ")";
  if (!b.samples.empty()) os << " " << b.samples.size() << " sample masks";
  if (b.hz_seq != 0) os << " hz_seq " << b.hz_seq;
  return os << "}";
}

bool ShadedStampBatch::operator==(const ShadedStampBatch& o) const {
  return kind == o.kind && same_primitive(primitive, o.primitive) && stamps == o.stamps &&
         colors == o.colors && samples == o.samples;
}

std::ostream& operator<<(std::ostream& os, const ShadedStampBatch& b) {
  os << "ShadedStampBatch{" << b.kind;
  if (b.primitive) os << " prim " << b.primitive->primitive_id;
  os << " " << b.stamps.size() << " stamps, " << b.colors.size() << " colours";
  if (!b.samples.empty()) os << ", " << b.samples.size() << " sample masks";
  return os << "}";
}

std::ostream& operator<<(std::ostream& os, const ControlToken& t) {
  return os << "ControlToken{" << t.kind << "}";
}

}  // namespace gpusim
