#include "hw/tile_codec.h"

#include <algorithm>
#include <cstring>

namespace gpusim {

namespace {

// Each channel's minimum and maximum, over 16-byte chunks: lane l of a
// chunk is channel l mod channels (16 / sizeof(T) is a multiple of it), so
// the loop keeps one min and max per lane, which the compiler vectorises
// (this runs once per write-back over the whole tile), and folds the lanes
// into channels at the end; a tail shorter than a chunk goes value by value.
template <typename T>
uint32_t largest_delta(const uint8_t* data, size_t bytes, unsigned channels) {
  constexpr size_t kLanes = 16 / sizeof(T);
  T lo[kLanes], hi[kLanes];
  for (size_t l = 0; l < kLanes; ++l) {
    lo[l] = static_cast<T>(~T{0});
    hi[l] = 0;
  }
  size_t p = 0;
  for (; p + 16 <= bytes; p += 16) {
    T v[kLanes];
    std::memcpy(v, data + p, 16);
    for (size_t l = 0; l < kLanes; ++l) {
      lo[l] = std::min(lo[l], v[l]);
      hi[l] = std::max(hi[l], v[l]);
    }
  }
  for (size_t l = 0; p + sizeof(T) <= bytes; p += sizeof(T), ++l) {
    T v;
    std::memcpy(&v, data + p, sizeof(T));
    lo[l] = std::min(lo[l], v);  // l < kLanes: the tail is shorter than a chunk
    hi[l] = std::max(hi[l], v);
  }
  uint32_t delta = 0;
  for (unsigned c = 0; c < channels; ++c) {
    T cl = static_cast<T>(~T{0}), ch = 0;
    for (size_t l = c; l < kLanes; l += channels) {
      cl = std::min(cl, lo[l]);
      ch = std::max(ch, hi[l]);
    }
    if (ch >= cl) delta = std::max<uint32_t>(delta, static_cast<uint32_t>(ch - cl));
  }
  return delta;
}

}  // namespace

unsigned tile_delta_bits(const uint8_t* data, size_t bytes, unsigned channels,
                         unsigned channel_bytes) {
  const uint32_t delta = channel_bytes == 1   ? largest_delta<uint8_t>(data, bytes, channels)
                         : channel_bytes == 2 ? largest_delta<uint16_t>(data, bytes, channels)
                                              : largest_delta<uint32_t>(data, bytes, channels);
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
