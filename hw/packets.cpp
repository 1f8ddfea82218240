#include "hw/packets.h"

#include <stdexcept>
#include <string>

namespace gpusim {

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

std::ostream& operator<<(std::ostream& os, LineRule r) {
  switch (r) {
    case LineRule::none:
      return os << "none";
    case LineRule::diamond_exit:
      return os << "diamond_exit";
    case LineRule::bresenham:
      return os << "bresenham";
    case LineRule::rectangle:
      return os << "rectangle";
  }
  return os << "invalid";
}

int log2_side(unsigned side) {
  if (side == 0 || (side & (side - 1)) != 0) {
    throw std::invalid_argument("side " + std::to_string(side) + " is not a power of two");
  }
  int n = 0;
  while ((1u << n) < side) ++n;
  return n;
}

}  // namespace gpusim
