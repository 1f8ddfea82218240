#include "hw/varying_layout.h"

#include <stdexcept>
#include <string>

namespace gpusim {

unsigned VaryingLayout::append(unsigned components) {
  if (components > kMaxVaryings - count) {
    throw std::length_error("varying layout: " + std::to_string(count) + " + " +
                            std::to_string(components) + " components exceed the capacity of " +
                            std::to_string(kMaxVaryings));
  }
  const unsigned first = count;
  count = static_cast<uint8_t>(count + components);
  return first;
}

std::ostream& operator<<(std::ostream& os, const VaryingLayout& l) {
  os << "VaryingLayout{" << unsigned{l.count} << " components, colour at " << unsigned{l.color};
  if (l.per_pixel_lighting())
    os << ", normal at " << unsigned{l.normal} << ", eye position at " << unsigned{l.eye};
  if (l.textured()) os << ", texture coordinate at " << unsigned{l.texcoord};
  return os << "}";
}

}  // namespace gpusim
