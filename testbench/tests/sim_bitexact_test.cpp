// The cycle model's frame (colour and depth) and pipeline counters equal the
// golden model's bit for bit, for every test scene under a pairwise covering
// set of configurations: every value of units {1,2,3,4,8,16}, FIFO depth
// {1,2,16}, tile size {8,16,64}, stamp {2x2,4x4,8x8} and hierarchical Z
// {off, on}, and every pair of values of any two of them. Each case runs in
// its own process (ctest), since a SystemC model elaborates once per process.
// Memory channels (timing only, so they must not move a pixel) vary with the
// FIFO depth's index: 1 channel, 4 channels, and 3 channels interleaved every
// 32 bytes (a 64-byte tile row split over two channels).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <set>
#include <sstream>
#include <string>
#include <tuple>

#include "testbench/driver/painter_sort.h"
#include "testbench/golden/golden_model.h"
#include "testbench/sim/gpu_run.h"

namespace gpusim {
namespace {

constexpr std::array<unsigned, 6> kUnits{1, 2, 3, 4, 8, 16};
constexpr std::array<unsigned, 3> kFifoDepths{1, 2, 16};
constexpr std::array<unsigned, 3> kTileSizes{8, 16, 64};
constexpr std::array<unsigned, 3> kStamps{2, 4, 8};

// Row (i, j) of the covering array: units i, FIFO depth j, tile (i + j) mod 3,
// stamp (i + 2j) mod 3, hierarchical Z on iff i + j is odd. Over the 18 rows, (tile, stamp) runs
// through all 9 pairs because (i, j) -> (i + j, i + 2j) is invertible mod 3; every other pair of
// factors is covered since one index runs over all values while the other is fixed. Hierarchical
// Z's parity of i + j = i - j (mod 2) takes both values with i fixed, with j fixed, and among the
// rows of one tile (i + j in {t, t + 3, ...}) or one stamp (i - j in {s, s + 3, s - 3}).
constexpr std::array<unsigned, 3> kChannels{1, 4, 3};
constexpr std::array<unsigned, 3> kInterleave{256, 256, 32};

struct MatrixRow {
  unsigned units, fifo_depth, tile_size, stamp, channels, interleave;
  bool hz;
};
MatrixRow matrix_row(int row) {
  const int i = row / 3, j = row % 3;
  return {kUnits[i],    kFifoDepths[j], kTileSizes[(i + j) % 3], kStamps[(i + 2 * j) % 3],
          kChannels[j], kInterleave[j], (i + j) % 2 == 1};
}

GpuConfig config_for(const MatrixRow& r) {
  GpuConfig c;
  c.units = r.units;
  c.fifo_depth = r.fifo_depth;
  c.tile_size = r.tile_size;
  c.stamp = {r.stamp, r.stamp};
  c.memory.channels = r.channels;
  c.memory.interleave_bytes = r.interleave;
  c.hierarchical_z.enabled = r.hz;
  return c;
}

// The output frames (width x height) must agree; the last-writer vectors
// are per render-target pixel (k * width x k * height with supersample k),
// so a difference at output pixel (x, y) reports render pixel (k x, k y).
void expect_same_frame(const Framebuffer& got, const Framebuffer& want, int supersample,
                       const std::vector<int64_t>& got_writer,
                       const std::vector<int64_t>& want_writer) {
  ASSERT_EQ(got.width, want.width);
  ASSERT_EQ(got.height, want.height);
  const int k = supersample;
  const size_t render_pixels = static_cast<size_t>(k * got.width) * (k * got.height);
  ASSERT_EQ(got_writer.size(), render_pixels);
  ASSERT_EQ(want_writer.size(), render_pixels);
  long long differing = 0;
  std::ostringstream first;
  for (int y = 0; y < got.height; ++y) {
    for (int x = 0; x < got.width; ++x) {
      const size_t p = got.pixel_index(x, y);
      const bool same =
          std::equal(got.color_at(x, y), got.color_at(x, y) + 4, want.color_at(x, y)) &&
          got.depth[p] == want.depth[p];
      if (same) continue;
      if (differing++ == 0) {
        const size_t w = static_cast<size_t>(k * y) * (k * got.width) + static_cast<size_t>(k * x);
        first << "first at x=" << x << " y=" << y << ": cycle model colour "
              << got.color_at(x, y)[0] << "," << got.color_at(x, y)[1] << ","
              << got.color_at(x, y)[2] << "," << got.color_at(x, y)[3] << " depth " << got.depth[p]
              << " (render pixel (" << k * x << ", " << k * y << ") last written by primitive "
              << got_writer[w] << "), golden " << want.color_at(x, y)[0] << ","
              << want.color_at(x, y)[1] << "," << want.color_at(x, y)[2] << ","
              << want.color_at(x, y)[3] << " depth " << want.depth[p] << " (primitive "
              << want_writer[w] << ")";
      }
    }
  }
  EXPECT_EQ(differing, 0) << first.str();
}

TEST(CoveringArray, CoversEveryValueAndEveryPair) {
  std::set<std::pair<int, int>> pairs[10];  // (factor a, factor b) value pairs per factor pair
  for (int row = 0; row < 18; ++row) {
    const MatrixRow r = matrix_row(row);
    const int v[5] = {static_cast<int>(r.units), static_cast<int>(r.fifo_depth),
                      static_cast<int>(r.tile_size), static_cast<int>(r.stamp),
                      static_cast<int>(r.hz)};
    int k = 0;
    for (int a = 0; a < 5; ++a) {
      for (int b = a + 1; b < 5; ++b) pairs[k++].insert({v[a], v[b]});
    }
  }
  const size_t sizes[5] = {kUnits.size(), kFifoDepths.size(), kTileSizes.size(), kStamps.size(), 2};
  int k = 0;
  for (int a = 0; a < 5; ++a) {
    for (int b = a + 1; b < 5; ++b)
      EXPECT_EQ(pairs[k++].size(), sizes[a] * sizes[b]) << a << "," << b;
  }
}

// A test scene as the driver hands it to both models.
Scene test_scene(const std::string& scene_name) {
  Scene scene =
      load_scene(std::string(GPUSIM_SOURCE_DIR) + "/testbench/scenes/" + scene_name + ".json");
  painter::apply_visibility(scene);  // the driver, before both models
  return scene;
}

// Runs the cycle model recording last writers; its frame, counters and last
// writers must be the golden model's.
void expect_recorded_run_equals_golden(const Scene& scene, const GpuConfig& config) {
  GpuRunOptions options;
  options.record_last_writer = true;
  const GpuRunResult got = run_gpu(scene, config, options);
  ASSERT_TRUE(got.completed) << "stopped at cycle " << got.cycles;
  const golden::Result want = golden::render(scene);
  expect_same_frame(got.framebuffer, want.framebuffer,
                    static_cast<int>(scene.framebuffer.supersample), got.last_writer,
                    want.last_writer);
  EXPECT_EQ(got.counts, want.stats);
  // The same pixels are written by the same primitives.
  EXPECT_EQ(got.last_writer, want.last_writer);
}

using Case = std::tuple<std::string, int>;

class BitExact : public ::testing::TestWithParam<Case> {};

TEST_P(BitExact, FrameAndCountersEqualGolden) {
  const auto& [scene_name, row] = GetParam();
  expect_recorded_run_equals_golden(test_scene(scene_name), config_for(matrix_row(row)));
}

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  const MatrixRow r = matrix_row(std::get<1>(info.param));
  std::ostringstream os;
  // Test names take letters, digits and '_': "lessons/needle_diagonal" ->
  // "lessons_needle_diagonal".
  std::string scene = std::get<0>(info.param);
  std::replace(scene.begin(), scene.end(), '/', '_');
  os << scene << "_u" << r.units << "_f" << r.fifo_depth << "_t" << r.tile_size << "_s" << r.stamp
     << "x" << r.stamp;
  if (r.channels > 1) os << "_c" << r.channels << "i" << r.interleave;
  if (r.hz) os << "_hz";
  return os.str();
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, BitExact,
    ::testing::Combine(
        ::testing::Values("default", "spider", "quad_clipspace", "tiny_triangles", "shared_edges",
                          "clipping", "zfight_offset", "states", "lines_random", "points_wireframe",
                          "lines_points", "aa_samples2", "aa_samples8", "aa_samples16",
                          "aa_super3_samples4", "aa_super2", "clears", "clears_samples4",
                          "clears_super2", "viewport_scissor", "viewport_scissor_aa", "phong",
                          "aa_phong_samples4", "painter_default", "painter_cycle",
                          "painter_interpenetrate", "painter_features", "provoking_interpolation",
                          "hiz_funcs", "hiz_funcs_samples4", "textured", "textured_samples4"),
        ::testing::Range(0, 18)),
    case_name);

// The texture unit's cache and fragment FIFO change only the timing: the
// textured scenes under three rows of the covering array and three texture
// configurations: 0 one 16-byte line, no prefetch (every texel a miss, a
// 3-byte texel straddling two lines); 1 two ways of 32-byte lines in 8 sets,
// 4 fragments ahead; 2 the default cache with 1024-byte lines.
using TextureCase = std::tuple<std::string, int, int>;

class BitExactTexture : public ::testing::TestWithParam<TextureCase> {};

TEST_P(BitExactTexture, FrameAndCountersEqualGolden) {
  const auto& [scene_name, row, mode] = GetParam();
  GpuConfig config = config_for(matrix_row(row));
  const std::array<TextureConfig, 3> textures{
      TextureConfig{1, 1, 16, 1}, TextureConfig{8, 2, 32, 4}, TextureConfig{32, 4, 1024, 64}};
  config.texture = textures[static_cast<size_t>(mode)];
  expect_recorded_run_equals_golden(test_scene(scene_name), config);
}

INSTANTIATE_TEST_SUITE_P(Scenes, BitExactTexture,
                         ::testing::Combine(::testing::Values("textured", "textured_samples4"),
                                            ::testing::Values(1, 5, 16), ::testing::Range(0, 3)),
                         [](const ::testing::TestParamInfo<TextureCase>& info) {
                           return std::get<0>(info.param) + "_row" +
                                  std::to_string(std::get<1>(info.param)) + "_texture" +
                                  std::to_string(std::get<2>(info.param));
                         });

// Tiled surfaces, bursts, compression and the no-fill path
// (docs/architecture.md, "Tiled surfaces and compression") change only the
// traffic: every scene (1, 2, 4, 8 and 16 samples, supersampling, clears)
// under three rows of the covering array (2 units and tiles of 64; 4 units
// and tiles of 8, 16) and three
// surface settings: 0 tiled; 1 tiled with depth and colour compression, the
// no-fill path and 100-byte bursts (not a multiple of the bus width); 2 the
// no-fill path on linear surfaces.
using SurfaceCase = std::tuple<std::string, int, int>;

class BitExactSurfaces : public ::testing::TestWithParam<SurfaceCase> {};

TEST_P(BitExactSurfaces, FrameAndCountersEqualGolden) {
  const auto& [scene_name, row, mode] = GetParam();
  GpuConfig config = config_for(matrix_row(row));
  config.surfaces.tiled = mode != 2;
  config.surfaces.skip_overwritten_fill = mode != 0;
  if (mode == 1) {
    config.surfaces.max_burst_bytes = 100;
    config.compression.depth = true;
    config.compression.colour = true;
  }
  expect_recorded_run_equals_golden(test_scene(scene_name), config);
}

std::string surface_case_name(const ::testing::TestParamInfo<SurfaceCase>& info) {
  const MatrixRow r = matrix_row(std::get<1>(info.param));
  const std::string modes[] = {"tiled", "compressed", "nofill"};
  return std::get<0>(info.param) + "_u" + std::to_string(r.units) + "_t" +
         std::to_string(r.tile_size) + "_" + modes[std::get<2>(info.param)];
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, BitExactSurfaces,
    ::testing::Combine(::testing::Values("default", "spider", "tiny_triangles", "shared_edges",
                                         "clipping", "zfight_offset", "states", "lines_points",
                                         "aa_samples2", "aa_samples8", "aa_samples16",
                                         "aa_super3_samples4", "aa_super2", "clears",
                                         "clears_samples4", "clears_super2", "viewport_scissor",
                                         "viewport_scissor_aa", "aa_phong_samples4",
                                         "painter_cycle", "painter_features"),
                       ::testing::Values(4, 9, 10), ::testing::Range(0, 3)),
    surface_case_name);

// The scenes of docs/lessons.md (testbench/scenes/lessons/; scripts/lessons
// renders them with the golden model, the needles and Phong against Gouraud
// with the cycle model).
INSTANTIATE_TEST_SUITE_P(
    Lessons, BitExact,
    ::testing::Combine(
        ::testing::Values("lessons/depth_nonlinear", "lessons/depth_precision_unorm16",
                          "lessons/depth_precision_unorm24", "lessons/cull_cube_depth",
                          "lessons/cull_cube_culled", "lessons/needle_horizontal",
                          "lessons/needle_diagonal", "lessons/shared_edges", "lessons/antialias_1x",
                          "lessons/antialias_4x", "lessons/offset_none", "lessons/offset_pulled",
                          "lessons/provoking_first", "lessons/provoking_last",
                          "lessons/phong_gouraud_phong", "lessons/phong_gouraud_gouraud",
                          "lessons/interp_perspective", "lessons/interp_screen",
                          "lessons/painter_stack_painter", "lessons/painter_stack_zbuffer",
                          "lessons/painter_cycle_painter", "lessons/painter_cycle_zbuffer",
                          "lessons/partition_single", "lessons/partition_partitioned",
                          "lessons/partition_farpass", "lessons/partition_expected"),
        ::testing::Range(0, 18)),
    case_name);

// A run that records no last writers (`gpusim run` without --check): the
// ROP then takes its per-stamp path without per-pixel bookkeeping, which the
// runs above never do. Its frame and counters must equal the golden model's
// too. Single-sampled scenes covering both blend paths, colour masks, polygon
// offset, the three depth formats and functions, clears and scissored edges.
class BitExactUnrecorded : public ::testing::TestWithParam<Case> {};

TEST_P(BitExactUnrecorded, FrameAndCountersEqualGolden) {
  const auto& [scene_name, row] = GetParam();
  const Scene scene = test_scene(scene_name);
  const GpuRunResult got = run_gpu(scene, config_for(matrix_row(row)), GpuRunOptions{});
  ASSERT_TRUE(got.completed) << "stopped at cycle " << got.cycles;
  ASSERT_TRUE(got.last_writer.empty());
  const golden::Result want = golden::render(scene);
  ASSERT_EQ(got.framebuffer.color.size(), want.framebuffer.color.size());
  ASSERT_EQ(got.framebuffer.depth.size(), want.framebuffer.depth.size());
  size_t colors = 0, depths = 0;  // differing channels and depth values
  for (size_t i = 0; i < got.framebuffer.color.size(); ++i)
    colors += got.framebuffer.color[i] != want.framebuffer.color[i];
  for (size_t i = 0; i < got.framebuffer.depth.size(); ++i)
    depths += got.framebuffer.depth[i] != want.framebuffer.depth[i];
  EXPECT_EQ(colors, 0u);
  EXPECT_EQ(depths, 0u);
  EXPECT_EQ(got.counts, want.stats);
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, BitExactUnrecorded,
    ::testing::Combine(::testing::Values("default", "spider", "states", "zfight_offset",
                                         "quad_clipspace", "tiny_triangles", "clipping", "clears",
                                         "viewport_scissor", "points_wireframe", "phong",
                                         "painter_features", "lessons/depth_precision_unorm16",
                                         "lessons/depth_nonlinear"),
                       ::testing::Range(0, 18)),
    case_name);

}  // namespace
}  // namespace gpusim
