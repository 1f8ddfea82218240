// The lossless tile encoding of the tile caches' compression
// (compression.depth / compression.colour; docs/architecture.md, "Memory").
// Base + delta: a tile's values are `channels` unsigned little-endian
// integers of channel_bytes bytes each (depth: 1 channel of 2 or 4 bytes,
// unorm24 and float32 bit patterns alike; colour: 4 channels of 1 byte, or 2
// bytes of half bits), every sample of every pixel inside the surface. The
// block holds
//   header      4 bytes  (encoding, delta width)
//   base        channels * channel_bytes bytes: each channel's minimum
//   deltas      value - base of every channel of every value, packed at one
//               width d, the smallest of {0, 1, 2, 4, 8, 12, 16, 24, 32} bits
//               that holds the largest delta
// so a constant tile (every depth, or every colour, equal: d = 0) is header
// + base only. The block moves rounded up to the bus granularity; when that
// is not smaller than the raw tile the tile is stored raw. Only the size is
// computed: the memory keeps the decoded bytes (function and timing split,
// hw/memory.h), so the model never packs or unpacks bits.
#pragma once

#include <cstddef>
#include <cstdint>

namespace gpusim {

constexpr uint32_t kTileHeaderBytes = 4;

// The smallest delta width (bits) of the set above that holds every value's
// distance from its channel's minimum. channel_bytes is 1, 2 or 4;
// `bytes` a multiple of channels * channel_bytes.
unsigned tile_delta_bits(const uint8_t* data, size_t bytes, unsigned channels,
                         unsigned channel_bytes);

// Bytes the encoded block moves: header + base + packed deltas, rounded up to
// a multiple of `granule`; 0 when that is not less than `bytes` (stored raw).
uint32_t encoded_tile_bytes(const uint8_t* data, size_t bytes, unsigned channels,
                            unsigned channel_bytes, unsigned granule);

}  // namespace gpusim
