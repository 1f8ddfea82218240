#include "hw/vertex_packets.h"

namespace gpusim {

std::ostream& operator<<(std::ostream& os, SlotKind k) {
  switch (k) {
    case SlotKind::fetched:
      return os << "fetched";
    case SlotKind::cached:
      return os << "cached";
    case SlotKind::invalid:
      return os << "invalid";
  }
  return os << "?";
}

}  // namespace gpusim
