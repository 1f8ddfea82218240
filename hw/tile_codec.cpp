#include "hw/tile_codec.h"

#include <algorithm>
#include <array>

namespace gpusim {

unsigned tile_delta_bits(const uint8_t* data, size_t bytes, unsigned channels,
                         unsigned channel_bytes) {
  std::array<uint32_t, 4> lo, hi;
  lo.fill(UINT32_MAX);
  hi.fill(0);
  const size_t value_bytes = static_cast<size_t>(channels) * channel_bytes;
  for (size_t p = 0; p + value_bytes <= bytes; p += value_bytes) {
    for (unsigned c = 0; c < channels; ++c) {
      const uint8_t* b = data + p + static_cast<size_t>(c) * channel_bytes;
      uint32_t v = 0;
      for (unsigned i = 0; i < channel_bytes; ++i) v |= uint32_t{b[i]} << (8 * i);
      lo[c] = std::min(lo[c], v);
      hi[c] = std::max(hi[c], v);
    }
  }
  uint32_t delta = 0;
  for (unsigned c = 0; c < channels; ++c) {
    if (hi[c] >= lo[c]) delta = std::max(delta, hi[c] - lo[c]);
  }
  for (const unsigned bits : {0u, 1u, 2u, 4u, 8u, 12u, 16u, 24u}) {
    if (uint64_t{delta} < (uint64_t{1} << bits)) return bits;
  }
  return 32;
}

uint32_t encoded_tile_bytes(const uint8_t* data, size_t bytes, unsigned channels,
                            unsigned channel_bytes, unsigned granule) {
  const unsigned bits = tile_delta_bits(data, bytes, channels, channel_bytes);
  const uint64_t deltas = bytes / channel_bytes;  // one per channel of every value
  const uint64_t size =
      kTileHeaderBytes + uint64_t{channels} * channel_bytes + (deltas * bits + 7) / 8;
  const uint64_t moved = (size + granule - 1) / granule * granule;
  return moved < bytes ? static_cast<uint32_t>(moved) : 0;
}

}  // namespace gpusim
