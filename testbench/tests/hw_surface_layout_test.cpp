// The tiled surface layout (hw/surface_layout.h) and the tile encoding's
// sizes (hw/tile_codec.h), against offsets and sizes worked out by hand.
#include <gtest/gtest.h>

#include <cstring>
#include <set>
#include <vector>

#include "hw/surface_layout.h"
#include "hw/tile_codec.h"

namespace gpusim {
namespace {

TEST(SurfaceLayout, LinearIsRowMajor) {
  const SurfaceLayout l(false, 40, 24, 4, 16, 2);
  EXPECT_EQ(l.size(), 40u * 24 * 4);
  EXPECT_EQ(l.pixel_offset(0, 0), 0u);
  EXPECT_EQ(l.pixel_offset(39, 0), 39u * 4);
  EXPECT_EQ(l.pixel_offset(3, 2), (2u * 40 + 3) * 4);
}

// 40 x 24 pixels, tiles of 16, 2 units, 4 bytes: tiles (0,0) and (1,0) are
// full (owners 0 and 1), then the partial tiles in raster order:
// (2,0) 8x16, (0,1) 16x8, (1,1) 16x8, (2,1) 8x8.
TEST(SurfaceLayout, TiledFullTilesUnitInterleavedThenEdgesPacked) {
  const SurfaceLayout l(true, 40, 24, 4, 16, 2);
  EXPECT_EQ(l.tile_offset(0, 0), 0u);
  EXPECT_EQ(l.tile_offset(1, 0), 1024u);
  EXPECT_EQ(l.tile_offset(2, 0), 2048u);
  EXPECT_EQ(l.tile_offset(0, 1), 2048u + 512);
  EXPECT_EQ(l.tile_offset(1, 1), 2048u + 1024);
  EXPECT_EQ(l.tile_offset(2, 1), 2048u + 1536);
  EXPECT_EQ(l.size(), 2048u + 1536 + 256);
  // Inside a partial tile rows are its width apart: (33, 2) is row 2, column 1 of (2,0).
  EXPECT_EQ(l.pixel_offset(33, 2), 2048u + (2 * 8 + 1) * 4);
  // Every pixel has its own 4 bytes inside the buffer.
  std::set<uint64_t> seen;
  for (int y = 0; y < 24; ++y) {
    for (int x = 0; x < 40; ++x) {
      const uint64_t o = l.pixel_offset(x, y);
      EXPECT_EQ(o % 4, 0u);
      EXPECT_LT(o, l.size());
      seen.insert(o);
    }
  }
  EXPECT_EQ(seen.size(), 40u * 24);
}

// 64 x 64, 4 units: the k-th block holds unit (k mod 4)'s (k / 4)-th tile, so
// with 4 channels interleaved by a tile each unit stays on one channel.
TEST(SurfaceLayout, FourUnitsDealtRoundRobin) {
  const SurfaceLayout l(true, 64, 64, 4, 16, 4);
  for (int ty = 0; ty < 4; ++ty) {
    for (int tx = 0; tx < 4; ++tx) {
      const uint64_t block = l.tile_offset(tx, ty) / 1024;
      EXPECT_EQ(block % 4, static_cast<uint64_t>((tx + ty) % 4)) << tx << ", " << ty;
    }
  }
}

std::vector<uint8_t> words(const std::vector<uint32_t>& v) {
  std::vector<uint8_t> b(v.size() * 4);
  std::memcpy(b.data(), v.data(), b.size());
  return b;
}

TEST(TileCodec, DeltaWidthsAndEncodedSizes) {
  // 256 unorm24 depths.
  std::vector<uint32_t> z(256, 8388608);
  EXPECT_EQ(tile_delta_bits(words(z).data(), 1024, 1, 4), 0u);
  // Constant: header 4 + base 4 = 8 bytes, moved as one 32-byte bus beat.
  EXPECT_EQ(encoded_tile_bytes(words(z).data(), 1024, 1, 4, 32), 32u);
  z[7] = 8388608 + 15;  // deltas 0..15: 4 bits, 4 + 4 + 128 = 136 -> 160
  EXPECT_EQ(tile_delta_bits(words(z).data(), 1024, 1, 4), 4u);
  EXPECT_EQ(encoded_tile_bytes(words(z).data(), 1024, 1, 4, 32), 160u);
  z[9] = 8388608 + 16;  // 5 bits needed: 8 in the set, 4 + 4 + 256 = 264 -> 288
  EXPECT_EQ(tile_delta_bits(words(z).data(), 1024, 1, 4), 8u);
  EXPECT_EQ(encoded_tile_bytes(words(z).data(), 1024, 1, 4, 32), 288u);
  z[0] = 0;  // 24 bits: 4 + 4 + 768 = 776 -> 800
  EXPECT_EQ(encoded_tile_bytes(words(z).data(), 1024, 1, 4, 32), 800u);
  z[1] = 0xFFFFFFFFu;  // 32 bits: larger than raw, stored raw
  EXPECT_EQ(tile_delta_bits(words(z).data(), 1024, 1, 4), 32u);
  EXPECT_EQ(encoded_tile_bytes(words(z).data(), 1024, 1, 4, 32), 0u);

  // rgba8, per channel bases: every pixel (10, 200, 30, 255) is constant
  // even though the channels differ: 4 + 4 = 8 -> 32.
  std::vector<uint8_t> c(1024);
  for (size_t p = 0; p < 256; ++p) {
    c[4 * p] = 10, c[4 * p + 1] = 200, c[4 * p + 2] = 30, c[4 * p + 3] = 255;
  }
  EXPECT_EQ(encoded_tile_bytes(c.data(), c.size(), 4, 1, 32), 32u);
  c[4 * 5 + 1] = 203;  // green 200..203: 2 bits for all 1024 channels: 4 + 4 + 256 -> 288
  EXPECT_EQ(encoded_tile_bytes(c.data(), c.size(), 4, 1, 32), 288u);

  // A partial tile of 5 x 5 unorm16 depths (50 bytes: three 16-byte chunks
  // and one value): the largest delta in the last value counts too.
  std::vector<uint16_t> d(25, 1000);
  std::vector<uint8_t> db(50);
  std::memcpy(db.data(), d.data(), 50);
  EXPECT_EQ(tile_delta_bits(db.data(), 50, 1, 2), 0u);
  d[24] = 1000 + 200;
  std::memcpy(db.data(), d.data(), 50);
  EXPECT_EQ(tile_delta_bits(db.data(), 50, 1, 2), 8u);
  // 4 + 2 + 25 bytes = 31 -> 32, smaller than 50.
  EXPECT_EQ(encoded_tile_bytes(db.data(), 50, 1, 2, 32), 32u);
  d[0] = 0;  // 1200 needs 12 bits: 4 + 2 + 38 = 44 -> 64, not smaller than 50: raw
  std::memcpy(db.data(), d.data(), 50);
  EXPECT_EQ(tile_delta_bits(db.data(), 50, 1, 2), 12u);
  EXPECT_EQ(encoded_tile_bytes(db.data(), 50, 1, 2, 32), 0u);
}

}  // namespace
}  // namespace gpusim
