// Cycle counts of whole frames against answers derived by hand from the
// documented costs (docs/architecture.md). Where a whole-frame figure would
// depend on fill and drain constants, the tests compare two runs that differ
// in one thing, so the constants cancel and the difference is exact.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "testbench/golden/golden_model.h"
#include "testbench/sim/gpu_run.h"

namespace gpusim {
namespace {

// A 256x256 scene in clip space (no camera), colour rgba8, depth unorm24.
Scene clip_space_scene(int width = 256, int height = 256) {
  Scene s;
  s.path = "cycles_test";
  s.framebuffer.width = width;
  s.framebuffer.height = height;
  return s;
}

Draw triangles(std::vector<glm::vec4> positions, bool depth_test = false) {
  Draw d;
  d.name = "test";
  d.primitive = PrimitiveType::triangles;
  d.positions = std::move(positions);
  d.state.depth_test = depth_test;
  return d;
}

// One triangle whose interior holds the whole 256x256 screen: (-1,-1),
// (3,-1), (-1,3) in NDC reach window (0,0), (512,0), (0,512), within the
// guard band. Every tile is trivially accepted.
Draw giant_triangle(bool depth_test = false) {
  return triangles({{-1, -1, 0.5f, 1}, {3, -1, 0.5f, 1}, {-1, 3, 0.5f, 1}}, depth_test);
}

// A fill-bound configuration: a memory that never holds anything up during
// the frame (64 KiB per cycle, no latency) and tile caches that hold every
// tile, so the only memory traffic is the final write-back.
GpuConfig fill_bound(unsigned units) {
  GpuConfig c = GpuConfig::baseline();
  c.units = units;
  c.tile_size = 16;
  c.stamp = {4, 4};
  c.memory.latency = 0;
  c.memory.bytes_per_cycle = 65536;
  c.tile_cache_entries = 1024;
  return c;
}

GpuRunResult run(const Scene& scene, const GpuConfig& config) {
  GpuRunResult r = run_gpu(scene, config, {});
  EXPECT_TRUE(r.completed);
  EXPECT_EQ(r.framebuffer, golden::render(scene).framebuffer);
  return r;
}

uint64_t stage_counter(const GpuRunResult& r, const std::string& stage, const char* name) {
  return r.timing.at("stages").at(stage).at(name).get<uint64_t>();
}

int64_t cycles(const GpuRunResult& r) {
  return static_cast<int64_t>(r.cycles);
}

TEST(Cycles, FullScreenQuadOnOneUnit) {
  // Two triangles splitting the 256x256 screen along its diagonal. With 16x16
  // tiles and 4x4 stamps: 256 tiles; each triangle trivially accepts the 120
  // tiles wholly on its side (16 stamps each), rejects the 120 on the other
  // side, and evaluates the 16 diagonal tiles stamp by stamp (16 each). So
  // each triangle costs 256 tile tests + (120 + 16) * 16 stamp cycles =
  // 2432; both 4864, plus 1 cycle for each of the two control tokens (clear,
  // end of frame). The diagonal runs through pixel centres, so the 64
  // stamps it crosses are emitted by both triangles: 4096 + 64 stamps, and
  // every one of the 65536 pixels exactly once.
  Scene s = clip_space_scene();
  s.draws.push_back(triangles(
      {{-1, -1, 0, 1}, {1, -1, 0, 1}, {1, 1, 0, 1}, {-1, -1, 0, 1}, {1, 1, 0, 1}, {-1, 1, 0, 1}}));
  const GpuRunResult r = run(s, fill_bound(1));
  EXPECT_EQ(stage_counter(r, "tile_rasterizer_0", "busy_cycles"), 4864u + 2u);
  EXPECT_EQ(stage_counter(r, "tile_rasterizer_0", "stamps_emitted"), 4096u + 64u);
  EXPECT_EQ(stage_counter(r, "tile_rasterizer_0", "fragments"), 65536u);
  // The frame takes the rasterizer's cycles plus the pipeline's fill and
  // drain and the final write-back of 256 tiles x 16 rows at one bus cycle
  // per row.
  EXPECT_GT(cycles(r), 4864 + 4096);
}

TEST(Cycles, UnitsDivideTheRasterizerCycles) {
  // The giant triangle: 256 accepted tiles x (1 test + 16 stamps) = 4352
  // cycles on one unit. Tile (tx, ty) belongs to unit (tx + ty) mod N, so on
  // a 16x16 tile grid each of N in {2, 4, 8, 16} units owns 256 / N tiles:
  // 4352 / N cycles each (+2 for the control tokens).
  //
  // The whole frame: the distributor spends ii = 1 cycle per unit it sends
  // the triangle to (N), the units rasterize in parallel (4352 / N), and the
  // fill and drain do not depend on N. The final write-back is bus-serial:
  // 4096 depth rows (the cleared depth buffer) then 4096 colour rows, one
  // cycle each. The depth test issues its rows at end of frame and forwards
  // the token when they are done; the ROP issues its rows ii(interpolator) +
  // latency(interpolator) + latency(rop) = 1 + 6 + 4 = 11 cycles after that.
  // With one unit the bus idles for those 11 cycles; with N >= 2 the other
  // units' depth rows still occupy it, so it never idles. So
  // frame(1) - frame(N) = (1 + 4352) - (N + 4352 / N) + 11.
  Scene s = clip_space_scene();
  s.draws.push_back(giant_triangle());
  const GpuRunResult one = run(s, fill_bound(1));
  EXPECT_EQ(stage_counter(one, "tile_rasterizer_0", "busy_cycles"), 4352u + 2u);
  for (const unsigned n : {2u, 4u, 8u, 16u}) {
    const GpuRunResult r = run(s, fill_bound(n));
    for (unsigned u = 0; u < n; ++u) {
      EXPECT_EQ(stage_counter(r, "tile_rasterizer_" + std::to_string(u), "busy_cycles"),
                4352u / n + 2u)
          << n << " units, unit " << u;
    }
    const GpuConfig& c = fill_bound(n);
    const int64_t gap =
        c.stage("interpolator").ii + c.stage("interpolator").latency + c.stage("rop").latency;
    ASSERT_EQ(gap, 11);
    EXPECT_EQ(cycles(one) - cycles(r), (1 + 4352) - static_cast<int64_t>(n + 4352 / n) + gap)
        << n << " units";
  }
}

// The scissor in the raster path (spec section 8d; cost model in
// stages/tile_rasterizer.h and stages/tile_distributor.h): setup clamps the
// pixel box to the draw rectangle, so only the tiles inside the scissor are
// sent and visited, and a rejected tile costs nothing anywhere.
TEST(Cycles, ScissorOfKTilesVisitsExactlyThoseTiles) {
  // Scissor [16, 32, 48, 16] on 16x16 tiles: pixels x 16..63, y 32..47, the
  // K = 3 tiles (1, 2), (2, 2), (3, 2). The giant triangle accepts each of
  // them: 3 tile tests + 3 x 16 stamps + 2 control tokens = 53 cycles on one
  // unit (4354 without the scissor), 768 fragments.
  Scene s = clip_space_scene();
  s.draws.push_back(giant_triangle());
  s.draws.back().state.scissor = PixelRect{16, 32, 48, 16};
  const GpuRunResult one = run(s, fill_bound(1));
  EXPECT_EQ(stage_counter(one, "tile_rasterizer_0", "tiles_visited"), 3u);
  EXPECT_EQ(stage_counter(one, "tile_rasterizer_0", "tiles_accepted"), 3u);
  EXPECT_EQ(stage_counter(one, "tile_rasterizer_0", "stamps_accepted"), 48u);
  EXPECT_EQ(stage_counter(one, "tile_rasterizer_0", "busy_cycles"), 3u + 48u + 2u);
  EXPECT_EQ(stage_counter(one, "tile_rasterizer_0", "fragments"), 768u);
  EXPECT_EQ(stage_counter(one, "tile_distributor", "triangles_sent"), 1u);

  // Four units: tile (tx, ty) belongs to unit (tx + ty) mod 4, so units 3,
  // 0 and 1 get one tile each and the distributor sends the triangle to
  // those three only (3 cycles); unit 2 never sees it.
  const GpuRunResult four = run(s, fill_bound(4));
  const unsigned want_tiles[4] = {1, 1, 0, 1};
  for (unsigned u = 0; u < 4; ++u) {
    const std::string unit = "tile_rasterizer_" + std::to_string(u);
    EXPECT_EQ(stage_counter(four, unit, "tiles_visited"), want_tiles[u]) << unit;
    EXPECT_EQ(stage_counter(four, unit, "busy_cycles"), want_tiles[u] * 17u + 2u) << unit;
  }
  EXPECT_EQ(stage_counter(four, "tile_distributor", "triangles_sent"), 3u);
  EXPECT_EQ(stage_counter(four, "tile_distributor", "busy_cycles"), 3u + 2u);
}

TEST(Cycles, ScissorCuttingTilesMasksTheirStamps) {
  // Scissor [20, 36, 40, 10]: pixels x 20..59, y 36..45, inside tiles
  // (1..3, 2): K = 3 tiles visited, each accepted; the 4x4 stamps meeting
  // the box are columns 5..14 and rows 9..11, 30 stamps, partial ones
  // masked to the box: 400 fragments. 3 + 30 + 2 cycles.
  Scene s = clip_space_scene();
  s.draws.push_back(giant_triangle());
  s.draws.back().state.scissor = PixelRect{20, 36, 40, 10};
  const GpuRunResult r = run(s, fill_bound(1));
  EXPECT_EQ(stage_counter(r, "tile_rasterizer_0", "tiles_visited"), 3u);
  EXPECT_EQ(stage_counter(r, "tile_rasterizer_0", "stamps_emitted"), 30u);
  EXPECT_EQ(stage_counter(r, "tile_rasterizer_0", "busy_cycles"), 3u + 30u + 2u);
  EXPECT_EQ(stage_counter(r, "tile_rasterizer_0", "fragments"), 400u);
  EXPECT_EQ(r.counts.fragments_generated, 400u);
}

TEST(Cycles, ViewportSubRectangleBoundsTheTilesVisited) {
  // Viewport [32, 64, 64, 32] (tiles 2..5 x 4..5, 8 tiles): the giant
  // triangle maps to window (32, 64), (160, 64), (32, 160), covering the
  // viewport, and the draw rectangle is the viewport: 8 accepted tiles,
  // 8 + 8 x 16 + 2 cycles, 2048 fragments.
  Scene s = clip_space_scene();
  s.draws.push_back(giant_triangle());
  s.draws.back().state.viewport = PixelRect{32, 64, 64, 32};
  const GpuRunResult r = run(s, fill_bound(1));
  EXPECT_EQ(stage_counter(r, "tile_rasterizer_0", "tiles_visited"), 8u);
  EXPECT_EQ(stage_counter(r, "tile_rasterizer_0", "tiles_accepted"), 8u);
  EXPECT_EQ(stage_counter(r, "tile_rasterizer_0", "busy_cycles"), 8u + 128u + 2u);
  EXPECT_EQ(stage_counter(r, "tile_rasterizer_0", "fragments"), 2048u);
}

TEST(Cycles, SamplesMultiplyTheStampCostsAndTheTileBytes) {
  // The giant triangle over a 256x256 render target with the depth test on,
  // on one unit, fill-bound (memory latency 0, 64 KiB per cycle, every tile
  // cached), samples_per_pass = 4 (the default). Spec section 14 and the
  // cost model (hw/gpu_config.h, stages/*.h): a stamp of N samples costs
  // ii * ceil(N / 4) in the rasterizer, depth test and ROP, so with ii = 1
  // and 256 accepted tiles of 16 stamps the rasterizer is busy
  // 256 * (1 + 16 * ceil(N / 4)) + 2 (control tokens):
  //   N = 1: 4354,  N = 4: 4354,  N = 8: 256 * 33 + 2 = 8450.
  // The depth and colour tiles hold N samples per pixel (4 bytes each for
  // unorm24 and rgba8): with fast clears and every tile cached nothing is
  // read and the end-of-frame write-back writes 65536 * 4 * N bytes each.
  // The run at (N = 4, supersample 2) renders a 128x128 frame into the same
  // 256x256 render target, so its raster figures equal N = 4's.
  struct Case {
    unsigned samples, supersample;
    uint64_t raster_busy;
  };
  for (const Case c : {Case{1, 1, 4354}, Case{4, 1, 4354}, Case{8, 1, 8450}, Case{4, 2, 4354}}) {
    const int k = static_cast<int>(c.supersample);
    Scene s = clip_space_scene(256 / k, 256 / k);
    s.framebuffer.samples = c.samples;
    s.framebuffer.supersample = c.supersample;
    s.draws.push_back(giant_triangle(true));
    const GpuConfig config = fill_bound(1);
    ASSERT_EQ(config.samples_per_pass, 4u);
    ASSERT_EQ(config.stage("tile_rasterizer").ii, 1u);
    ASSERT_EQ(config.stage("depth_test").ii, 1u);
    ASSERT_EQ(config.stage("rop").ii, 1u);
    ASSERT_EQ(config.stage("resolve").ii, 1u);
    const GpuRunResult r = run(s, config);
    const std::string what =
        std::to_string(c.samples) + " samples, supersample " + std::to_string(c.supersample);
    EXPECT_EQ(stage_counter(r, "tile_rasterizer_0", "busy_cycles"), c.raster_busy) << what;
    EXPECT_EQ(stage_counter(r, "tile_rasterizer_0", "tiles_accepted"), 256u) << what;
    EXPECT_EQ(stage_counter(r, "tile_rasterizer_0", "stamps_emitted"), 4096u) << what;
    const uint64_t bytes = 65536u * 4u * c.samples;
    for (const char* stage : {"depth_test_0", "rop_0"}) {
      EXPECT_EQ(stage_counter(r, stage, "bytes_read"), 0u) << what << " " << stage;
      EXPECT_EQ(stage_counter(r, stage, "bytes_written"), bytes) << what << " " << stage;
    }
    EXPECT_EQ(stage_counter(r, "rop_0", "samples_written"), 65536u * c.samples) << what;
    if (c.samples == 1 && c.supersample == 1) {
      // No resolve stage in a single-sample frame.
      EXPECT_FALSE(r.timing.at("stages").contains("resolve")) << what;
      continue;
    }
    // The resolve: output W x H = 256/k square in 16x16 tiles of 16 4x4
    // stamps, n = k^2 N samples per output pixel, ceil(n / 4) passes.
    const uint64_t side = 256u / c.supersample, tiles = (side / 16) * (side / 16);
    const uint64_t n = c.supersample * c.supersample * c.samples;
    EXPECT_EQ(stage_counter(r, "resolve", "tiles"), tiles) << what;
    EXPECT_EQ(stage_counter(r, "resolve", "pixels"), side * side) << what;
    EXPECT_EQ(stage_counter(r, "resolve", "samples"), side * side * n) << what;
    // Its cycles. The memory cannot hold it up beyond the bus itself: every
    // request (at most 2 * 16 * 4 * 4 = 512 bytes) takes exactly one bus cycle
    // (hw/memory.h), latency 0. The ROPs' write-backs are complete when
    // the resolve gets end_of_frame, so the bus is free. Per tile the
    // resolve reads R = 16 k render-target rows (one request each) and
    // waits for them; the first tile's reads take R cycles. It then filters
    // for 16 stamps * passes cycles and posts its 16 output rows to arrive
    // when it finishes, i.e. when the next tile's reads are issued: those
    // reads queue behind the 16 writes reserved in an earlier round, so
    // every later tile waits 16 + R. After the last tile it waits for its
    // 16 writes. Plus ii = 1 for the clear token:
    //   busy = 1 + R + (tiles - 1) (16 + R) + tiles * 16 * passes + 16.
    //   N = 4:        1 + 16 + 255 * 32 + 256 * 16 + 16  = 12289
    //   N = 8:        1 + 16 + 255 * 32 + 256 * 32 + 16  = 16385
    //   N = 4, k = 2: 1 + 32 + 63 * 48  + 64 * 16 * 4 + 16 = 7169
    const uint64_t rows = 16u * c.supersample, passes = (n + 3) / 4;
    const uint64_t stall = rows + (tiles - 1) * (16 + rows) + 16;
    EXPECT_EQ(stage_counter(r, "resolve", "memory_stall_cycles"), stall) << what;
    EXPECT_EQ(stage_counter(r, "resolve", "busy_cycles"), 1 + stall + tiles * 16 * passes) << what;
    const uint64_t expected[] = {12289, 16385, 7169};
    const int index = c.supersample == 2 ? 2 : c.samples == 8 ? 1 : 0;
    EXPECT_EQ(stage_counter(r, "resolve", "busy_cycles"), expected[index]) << what;
  }
}

// `count` copies of a triangle inside pixel (8, 8) of a 256x256 screen.
Scene tiny_triangles(int count) {
  Scene s = clip_space_scene();
  std::vector<glm::vec4> p;
  const auto clip = [](float wx, float wy) {
    return glm::vec4(wx / 128.0f - 1.0f, wy / 128.0f - 1.0f, 0.5f, 1.0f);
  };
  for (int i = 0; i < count; ++i) {
    p.push_back(clip(8.2f, 8.2f));
    p.push_back(clip(8.9f, 8.3f));
    p.push_back(clip(8.4f, 8.9f));
  }
  s.draws.push_back(triangles(p));
  return s;
}

// Every stage but primitive setup (ii 4 per triangle) keeps up with one tiny
// triangle per 4 cycles: fetch 3 slots x 1, the shader (set to ii 1 here)
// 3 vertices x 1, the clipper 2, the distributor 1, the rasterizer 1 tile
// test + 1 stamp, the back end 1 stamp each; 3 vertices of fetch traffic are
// 48 bytes, 2 bus cycles at 32 bytes per cycle.
GpuConfig setup_bound(unsigned fifo_depth) {
  GpuConfig c = GpuConfig::baseline();
  c.units = 1;
  c.fifo_depth = fifo_depth;
  c.stages["vertex_shader"] = {1, 24};
  return c;
}

TEST(Cycles, TinyTrianglesRunAtSetupInitiationInterval) {
  // 320 and 960 triangles: slots are multiples of the 32-slot fetch batch.
  // Setup always has a backlog, so each extra triangle adds exactly its ii.
  const GpuConfig c = setup_bound(16);
  const int64_t ii = c.stage("primitive_setup").ii;
  const GpuRunResult a = run(tiny_triangles(320), c);
  const GpuRunResult b = run(tiny_triangles(960), c);
  EXPECT_EQ(cycles(b) - cycles(a), 640 * ii);
  EXPECT_EQ(stage_counter(b, "primitive_setup", "busy_cycles") -
                stage_counter(a, "primitive_setup", "busy_cycles"),
            static_cast<uint64_t>(640 * ii));
}

TEST(Cycles, FifoDepthOneExposesSetupLatency) {
  // With one-entry FIFOs, setup's result holds the FIFO slot from its write
  // until the distributor can read it, latency(setup) = 16 cycles later; the
  // next result cannot be written before then. So each triangle costs
  // max(ii, latency) = 16 cycles instead of ii = 4 with deep FIFOs (depth
  // 16 holds the 16 / 4 results in flight).
  const GpuConfig c = setup_bound(1);
  const int64_t latency = c.stage("primitive_setup").latency;
  ASSERT_GT(latency, c.stage("primitive_setup").ii);
  const GpuRunResult a = run(tiny_triangles(320), c);
  const GpuRunResult b = run(tiny_triangles(960), c);
  EXPECT_EQ(cycles(b) - cycles(a), 640 * latency);
}

// `count` copies of a short line or a point in pixel (8, 8) of a 256x256
// screen: the line runs from window (8.1, 8.5) to (9.1, 8.5), so it leaves
// pixel (8, 8)'s diamond and ends outside pixel (9, 8)'s (spec 8b): one
// fragment; the point (size 1) covers pixel (8, 8).
Scene tiny_primitives(PrimitiveType type, int count) {
  Scene s = clip_space_scene();
  const auto clip = [](float wx, float wy) {
    return glm::vec4(wx / 128.0f - 1.0f, wy / 128.0f - 1.0f, 0.5f, 1.0f);
  };
  Draw d = triangles({});
  d.primitive = type;
  for (int i = 0; i < count; ++i) {
    if (type == PrimitiveType::lines) {
      d.positions.push_back(clip(8.1f, 8.5f));
      d.positions.push_back(clip(9.1f, 8.5f));
    } else {
      d.positions.push_back(clip(8.5f, 8.5f));
    }
  }
  s.draws.push_back(d);
  return s;
}

TEST(Cycles, TinyLinesAndPointsRunAtSetupInitiationInterval) {
  // Per line the other stages need fewer cycles than setup's ii = 4: fetch
  // 2 slots x 1, the shader (ii 1 here) 2 vertices, the clipper 2, the
  // distributor 1, the rasterizer 1 tile test + 1 stamp, the back end 1
  // stamp each; 2 vertices are 32 bytes, one bus cycle. A point needs half
  // the front end's. So each extra line or point adds exactly setup's ii.
  // 640 and 1920 lines are multiples of the 32-slot fetch batch; so are the
  // points. The clipper writes a batch's primitives after working on the
  // whole batch: 32 points are more than a 16-deep FIFO holds, so with 16
  // setup would drain the FIFO while the clipper works on the next batch and
  // wait once per batch (4 cycles, measured); 32, a batch's worth, keeps
  // setup fed.
  for (const PrimitiveType type : {PrimitiveType::lines, PrimitiveType::points}) {
    const GpuConfig c = setup_bound(type == PrimitiveType::lines ? 16 : 32);
    const int64_t ii = c.stage("primitive_setup").ii;
    const GpuRunResult a = run(tiny_primitives(type, 640), c);
    const GpuRunResult b = run(tiny_primitives(type, 1920), c);
    EXPECT_EQ(cycles(b) - cycles(a), 1280 * ii) << to_string(type);
    EXPECT_EQ(b.counts.fragments_generated, 1920u) << to_string(type);
  }
}

TEST(Cycles, MemoryBandwidthCapSlowsTheWriteBackAsPredicted) {
  // The giant triangle with the depth test on: fast clears mean no memory
  // reads, and the tile caches hold every tile, so the frame's memory traffic
  // is the 3 vertices (48 bytes) and the final write-back of 256 tiles x 16
  // rows x 2 buffers (colour rgba8 and depth unorm24: 64 bytes a row), which
  // keeps the shared bus busy without a gap from the first write-back to the
  // last. A row takes ceil(64 / bytes_per_cycle) bus cycles: 1 at 64 bytes
  // per cycle, 4 at 16. The vertex fetch takes ceil(48 / 64) = 1 or
  // ceil(48 / 16) = 3 cycles, shifting the whole frame by 2.
  Scene s = clip_space_scene();
  s.draws.push_back(giant_triangle(true));
  GpuConfig wide = fill_bound(1);
  wide.memory.latency = 20;
  wide.memory.bytes_per_cycle = 64;
  GpuConfig narrow = wide;
  narrow.memory.bytes_per_cycle = 16;
  const GpuRunResult a = run(s, wide);
  const GpuRunResult b = run(s, narrow);
  EXPECT_EQ(cycles(b) - cycles(a), 8192 * (4 - 1) + 2);
}

TEST(Cycles, RandomStallsAtEveryFifoLeaveTheFrameUnchanged) {
  for (const char* name : {"default", "states", "clipping", "shared_edges", "clears_samples4"}) {
    const Scene s =
        load_scene(std::string(GPUSIM_SOURCE_DIR) + "/testbench/scenes/" + name + ".json");
    GpuConfig c = GpuConfig::baseline();
    c.units = 3;
    c.fifo_depth = 2;
    GpuRunOptions stalled;
    stalled.stall_probability = 0.3;
    stalled.stall_max_cycles = 7;
    stalled.stall_seed = 42;
    const GpuRunResult calm = run_gpu(s, c, {});
    const GpuRunResult r = run_gpu(s, c, stalled);
    ASSERT_TRUE(r.completed) << name;
    EXPECT_GT(r.cycles, calm.cycles) << name << ": the stalls must cost time";
    EXPECT_EQ(r.framebuffer, golden::render(s).framebuffer) << name;
    EXPECT_EQ(r.counts, calm.counts) << name;
  }
}

// Two giant triangles at window depth 0.75 (depth_func lequal, so the second
// passes with or without a depth clear between them and the back end does
// the same work either way), with or without a clear between the draws.
Scene two_giant_triangles(const ClearState* between) {
  Scene s = clip_space_scene();
  for (int i = 0; i < 2; ++i) {
    s.draws.push_back(giant_triangle(true));
    s.draws.back().state.depth_func = CompareFunc::lequal;
  }
  if (between) s.clears.push_back(*between);
  return s;
}

ClearState clear_between(bool color, bool depth) {
  ClearState c;
  c.color = color;
  c.depth = depth;
  c.color_value = {0.25f, 0.5f, 0.75f, 1.0f};
  c.depth_value = 1.0f;
  c.before_draw = 1;
  return c;
}

TEST(Cycles, AMidFrameClearCostsOneTokenAndNoMemoryWhenTilesStayCached) {
  // Fill-bound, one unit, every tile cached (fill_bound). The clear is a
  // control token: ii = 1 in every stage it passes (docs/architecture.md,
  // "Clears"), and the tile rasterizer, the bottleneck (17 cycles per tile
  // against the back end's 16), meets it between the two triangles, so the
  // frame is exactly that 1 cycle longer: every other stage absorbs its
  // cycle while it waits for the rasterizer. A fast clear writes nothing: it
  // drops the cached tiles (the second triangle overwrites them anyway) and
  // marks them cleared, so the second triangle fills its 256 tiles from the
  // clear value (cache_clear_fills 256 -> 512) instead of hitting, nothing
  // is read, and the end-of-frame write-back is the same 256 tiles.
  const GpuConfig config = fill_bound(1);
  ASSERT_EQ(config.stage("tile_rasterizer").ii, 1u);
  const Scene plain = two_giant_triangles(nullptr);
  const GpuRunResult a = run(plain, config);
  for (const bool color : {false, true}) {
    const ClearState c = clear_between(color, !color);
    const GpuRunResult b = run(two_giant_triangles(&c), config);
    const char* what = color ? "colour clear" : "depth clear";
    const char* cleared = color ? "rop_0" : "depth_test_0";
    const char* other = color ? "depth_test_0" : "rop_0";
    EXPECT_EQ(cycles(b) - cycles(a), 1) << what;
    for (const char* stage :
         {"command_processor", "tile_rasterizer_0", "depth_test_0", "interpolator_0", "rop_0"}) {
      EXPECT_EQ(stage_counter(b, stage, "busy_cycles") - stage_counter(a, stage, "busy_cycles"), 1u)
          << what << " " << stage;
    }
    EXPECT_EQ(stage_counter(a, cleared, "cache_clear_fills"), 256u) << what;
    EXPECT_EQ(stage_counter(b, cleared, "cache_clear_fills"), 512u) << what;
    EXPECT_EQ(stage_counter(b, other, "cache_clear_fills"), 256u) << what;
    for (const char* stage : {"depth_test_0", "rop_0"}) {
      EXPECT_EQ(stage_counter(b, stage, "bytes_read"), 0u) << what << " " << stage;
      EXPECT_EQ(stage_counter(b, stage, "bytes_written"), 65536u * 4u) << what << " " << stage;
    }
    EXPECT_EQ((color ? b.counts.color_clears : b.counts.depth_clears), 2u) << what;
    EXPECT_EQ((color ? b.counts.depth_clears : b.counts.color_clears), 1u) << what;
  }
}

TEST(Cycles, AMidFrameFastClearSavesTheReadsAndTheCachedWriteBacks) {
  // The same frames with 16-entry tile caches: the two triangles walk the
  // 256 tiles in the same order, so under LRU the second triangle misses
  // every tile. Without a clear it reads all 256 back (1 KiB each: 16 x 16
  // pixels x 4 bytes), and 256 (first triangle) - 16 + 256 (second) dirty
  // evictions plus 16 at the end write 512 tiles. With the clear the second
  // triangle reads nothing (its tiles are cleared), and the 16 dirty tiles
  // cached at the clear are dropped, not written: 496 tiles.
  GpuConfig config = fill_bound(1);
  config.tile_cache_entries = 16;
  const uint64_t tile = 16 * 16 * 4;
  const GpuRunResult a = run(two_giant_triangles(nullptr), config);
  for (const bool color : {false, true}) {
    const ClearState c = clear_between(color, !color);
    const GpuRunResult b = run(two_giant_triangles(&c), config);
    const char* what = color ? "colour clear" : "depth clear";
    const char* cleared = color ? "rop_0" : "depth_test_0";
    const char* other = color ? "depth_test_0" : "rop_0";
    EXPECT_EQ(stage_counter(a, cleared, "bytes_read"), 256 * tile) << what;
    EXPECT_EQ(stage_counter(a, cleared, "bytes_written"), 512 * tile) << what;
    EXPECT_EQ(stage_counter(b, cleared, "bytes_read"), 0u) << what;
    EXPECT_EQ(stage_counter(b, cleared, "bytes_written"), 496 * tile) << what;
    EXPECT_EQ(stage_counter(b, cleared, "cache_writebacks"), 496u) << what;
    // The other buffer's traffic does not change.
    EXPECT_EQ(stage_counter(b, other, "bytes_read"), stage_counter(a, other, "bytes_read")) << what;
    EXPECT_EQ(stage_counter(b, other, "bytes_written"), stage_counter(a, other, "bytes_written"))
        << what;
    EXPECT_LT(b.cycles, a.cycles) << what << ": 256 tile reads saved";
  }
}

TEST(Cycles, ClearTokensReachEveryUnit) {
  // Every unit executes every clear on the tiles it owns: each unit's
  // rasterizer, depth test and ROP spend ii = 1 on it, and each unit's
  // depth test counts it.
  const ClearState c = clear_between(false, true);
  for (const unsigned n : {2u, 4u}) {
    const GpuRunResult a = run(two_giant_triangles(nullptr), fill_bound(n));
    const GpuRunResult b = run(two_giant_triangles(&c), fill_bound(n));
    for (unsigned u = 0; u < n; ++u) {
      for (const std::string stage : {"tile_rasterizer_", "depth_test_", "rop_"}) {
        const std::string name = stage + std::to_string(u);
        EXPECT_EQ(stage_counter(b, name, "busy_cycles") - stage_counter(a, name, "busy_cycles"), 1u)
            << n << " units, " << name;
      }
      EXPECT_EQ(stage_counter(b, "depth_test_" + std::to_string(u), "depth_clears"), 2u);
    }
  }
}

// The giant triangle lit per pixel (Phong, spec 9b) under `lights` directional
// lights: normals +z, depth test off, so every one of the 65536 pixels
// reaches the interpolator.
Scene giant_lit_triangle(Shading shading, int lights) {
  Scene s = clip_space_scene();
  for (int i = 0; i < lights; ++i) {
    Light l;
    l.vector = glm::normalize(glm::vec3(0.1f * static_cast<float>(i), 0.2f, 1.0f));
    s.lights.push_back(l);
  }
  Draw d = giant_triangle();
  d.lighting = true;
  d.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  d.material.specular = {0.5f, 0.5f, 0.5f, 1.0f};
  d.material.shininess = 8.0f;
  d.state.shading = shading;
  s.draws.push_back(d);
  return s;
}

TEST(Cycles, PerPixelLightingCostsPerPixelAndPerLight) {
  // One unit: the interpolator reads 4096 stamps (ii = 1 each) and two
  // control tokens (1 each). Gouraud: 4098 busy cycles whatever the lights,
  // and no pixel lit. Phong with L lights adds, for each of the 65536
  // pixels, lighting_cycles_per_pixel + L * lighting_cycles_per_light:
  // 1 + 2 L with the defaults.
  const GpuConfig c = fill_bound(1);
  ASSERT_EQ(c.lighting_cycles_per_pixel, 1u);
  ASSERT_EQ(c.lighting_cycles_per_light, 2u);
  const GpuRunResult gouraud = run(giant_lit_triangle(Shading::gouraud, 3), c);
  EXPECT_EQ(stage_counter(gouraud, "interpolator_0", "busy_cycles"), 4098u);
  EXPECT_EQ(stage_counter(gouraud, "interpolator_0", "pixels_lit"), 0u);
  for (const int lights : {0, 1, 3}) {
    const GpuRunResult r = run(giant_lit_triangle(Shading::phong, lights), c);
    const uint64_t per_pixel = 1u + 2u * static_cast<uint64_t>(lights);
    EXPECT_EQ(stage_counter(r, "interpolator_0", "busy_cycles"), 4098u + 65536u * per_pixel)
        << lights << " lights";
    EXPECT_EQ(stage_counter(r, "interpolator_0", "pixels_lit"), 65536u);
    EXPECT_EQ(stage_counter(r, "interpolator_0", "light_evaluations"),
              65536u * static_cast<uint64_t>(lights));
    // The interpolator is now the bottleneck by far: it needs 65536 * per_pixel
    // more cycles than the rasterizer's 4354, and the frame grows by at least
    // the difference (the rest of the pipeline only waits on it).
    EXPECT_GE(cycles(r) - cycles(gouraud), static_cast<int64_t>(65536u * per_pixel) - 4354)
        << lights << " lights";
  }
  // The costs come from the configuration: 3 + 5 L cycles per pixel.
  GpuConfig slow = c;
  slow.lighting_cycles_per_pixel = 3;
  slow.lighting_cycles_per_light = 5;
  const GpuRunResult r = run(giant_lit_triangle(Shading::phong, 2), slow);
  EXPECT_EQ(stage_counter(r, "interpolator_0", "busy_cycles"), 4098u + 65536u * 13u);
}

TEST(Cycles, PerPixelLightingSplitsAcrossUnits) {
  // Four units own 64 tiles each: 1024 stamps and 16384 pixels per
  // interpolator, so each is busy 1024 + 2 + 16384 * (1 + 2 * 2) cycles.
  const GpuRunResult r = run(giant_lit_triangle(Shading::phong, 2), fill_bound(4));
  for (unsigned u = 0; u < 4; ++u) {
    const std::string name = "interpolator_" + std::to_string(u);
    EXPECT_EQ(stage_counter(r, name, "busy_cycles"), 1026u + 16384u * 5u) << u;
    EXPECT_EQ(stage_counter(r, name, "pixels_lit"), 16384u) << u;
  }
}

}  // namespace
}  // namespace gpusim
