// `gpusim trace follow`: a primitive's cycles at every stage against a
// derivation by hand from the documented costs (docs/architecture.md) and
// the default configuration (testbench/configs/default.json); a pixel's
// fragments against the depth-test rules and the frame; clear messages for
// primitives and pixels the trace does not hold.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "testbench/io/image_files.h"
#include "testbench/tests/traces_support.h"
#include "traces/trace_follow.h"
#include "traces/trace_items.h"
#include "traces/trace_reader.h"

namespace gpusim {
namespace {

using trace_test::at_window;
using trace_test::CommandResult;
using trace_test::gpusim;
using TraceFollowTest = trace_test::TraceTest;

// One triangle, window vertices (1.25, 1.25), (13.5, 1.25), (1.25, 13.5) on
// a 64x64 framebuffer: exact in float through the viewport transform and
// exact in 1/256 subpixels. Its box holds pixels 1..13 in x and y (centres
// 1.5 .. 13.5), all in tile (0, 0). A pixel (i, j) is covered when its
// centre is inside x + y <= 14.75, i.e. i + j <= 13 for i, j >= 1 (no centre
// lies on an edge): 78 fragments. Of the 4 x 4 stamps of 4 x 4 pixels the
// box touches, those whose lowest pixel (max(1, 4 si), max(1, 4 sj)) has
// i + j <= 13 hold a covered pixel: 4 + 3 + 2 + 1 = 10 stamps.
nlohmann::json one_triangle_scene() {
  const int w = 64, h = 64;
  return {{"framebuffer", {{"width", w}, {"height", h}}},
          {"draws",
           {{{"primitive", "triangles"},
             {"positions",
              {at_window(1.25, 1.25, 0.0, w, h), at_window(13.5, 1.25, 0.0, w, h),
               at_window(1.25, 13.5, 0.0, w, h)}}}}}};
}

struct Expected {
  const char* stage;
  uint64_t cycle_in, cycle_out;
  uint32_t count;
};

TEST_F(TraceFollowTest, PrimitiveCyclesMatchTheCostModel) {
  // Default costs (ii / latency): command processor 1/2, vertex fetch 1/2,
  // vertex shader 4/24, clipper 2/8, setup 4/16, distributor 1/2,
  // rasterizer 1/2, depth test 1/2, interpolator 1/6, ROP 1/4; memory
  // latency 20, 32 bytes per cycle. An item written at cycle t by a stage of
  // latency L is readable at t + L; a stage takes it at max(readable, the
  // cycle it asks), and cycle_out is when it asks for the next item.
  //
  // The host writes clear, draw 0, end of frame at cycle 0.
  //  command_processor: clear 0..1 (readable at 3), draw 1..2 (at 4), eof
  //    2..3 (at 5).
  //  vertex_fetch: clear 3..4 (readable 6). Draw at 4: one batch of 3 slots,
  //    non-indexed, positions only: one 48-byte read at cycle 4 on an idle
  //    bus = ceil(48/32) = 2 bus cycles + 20 latency = 22 cycles. Busy
  //    ii x 3 = 3: the batch is written at 7, readable at
  //    4 + max(3, 22) + 2 = 28. The draw's interval: 4..7.
  //  vertex_shader: clear 6..10 (readable 34); the batch at 28, ii x 3 new
  //    vertices = 12: 28..40 (readable 64).
  //  clipper: clear 34..36 (readable 44); the batch at 64, ii x 1 triangle:
  //    64..66, the triangle readable at 74.
  //  primitive_setup: clear 44..48 (readable 64); the triangle 74..78
  //    (readable 94).
  //  tile_distributor: clear 64..65 (readable 67); the triangle at 94, one
  //    unit: 94..95 (readable 97). With 4 units it still goes to unit 0 only
  //    (its one tile (0,0) is owned by unit (0 + 0) mod 4 = 0), and control
  //    tokens cost ii once, so the timing is the same on 1 or 4 units.
  //  tile_rasterizer_0: clear 67..68 (readable 70 + 5, the hierarchical-Z
  //    test's access_latency on every token); the job at 97: 16 stamps
  //    evaluated (the tile is partial), the tile test overlapped with them
  //    (tile_test_overlap) = 16 cycles: 97..113, the batch of 10 stamps
  //    readable at 113 + 2 + 5 = 120.
  //  depth_test_0: clear 75..76 (readable 78); the batch at 120, ii x 10
  //    stamps, the tile filled from the fast clear without a memory read:
  //    120..130 (readable 132).
  //  interpolator_0: clear 78..79 (readable 85); the batch 132..142
  //    (readable 148).
  //  rop_0: clear 85..86; the batch at 148, ii x 10 stamps, again a clear
  //    fill: 148..158.
  const std::string scene = write_json("one_triangle.json", one_triangle_scene());
  const Expected expected[] = {
      {"command_processor", 1, 2, 1},     {"vertex_fetch", 4, 7, 1},
      {"vertex_shader", 28, 40, 3},       {"clipper", 64, 66, 3},
      {"primitive_setup", 74, 78, 1},     {"tile_distributor", 94, 95, 1},
      {"tile_rasterizer_0", 97, 113, 10}, {"depth_test_0", 120, 130, 10},
      {"interpolator_0", 132, 142, 10},   {"rop_0", 148, 158, 10},
  };
  for (const char* units : {"1", "4"}) {
    SCOPED_TRACE(std::string(units) + " units");
    const TraceReader reader(
        trace(scene, std::string("--units ") + units, std::string("t") + units));
    const std::vector<TraceFollow::Step> steps = TraceFollow(reader).prim_steps(0);
    ASSERT_EQ(steps.size(), std::size(expected));
    for (size_t i = 0; i < steps.size(); ++i) {
      const TransactionRecord& r = steps[i].record;
      EXPECT_EQ(steps[i].stage->name, expected[i].stage);
      EXPECT_EQ(r.cycle_in, expected[i].cycle_in) << expected[i].stage;
      EXPECT_EQ(r.cycle_out, expected[i].cycle_out) << expected[i].stage;
      EXPECT_EQ(r.count, expected[i].count) << expected[i].stage;
      EXPECT_EQ(r.prim_first, 0) << expected[i].stage;
      EXPECT_EQ(r.prim_last, 0) << expected[i].stage;
      EXPECT_EQ(r.draw, 0u) << expected[i].stage;
      if (steps[i].stage->kind == "depth_test" || steps[i].stage->kind == "rop") {
        EXPECT_EQ(r.tile_x, 0);  // a stamp batch lies in one tile
        EXPECT_EQ(r.tile_y, 0);
      }
    }
    // 78 fragments, each recorded at the depth test and at the ROP.
    EXPECT_EQ(reader.manifest().fragment_records, 2u * 78u);
  }

  // The command line prints the same, one row per stage.
  const CommandResult r = gpusim("trace follow " + (dir_ / "t1").string() + " --prim 0");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("triangle 0 (draw 0, triangles) in "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(" triangle\n"), std::string::npos) << r.out;  // setup's item
  EXPECT_NE(r.out.find("10 items at 10 stages"), std::string::npos) << r.out;
  // The ROP's row: stage, unit, tile, cycle_in, cycle_out, cycles, count.
  const size_t row = r.out.find("  rop_0 ");
  ASSERT_NE(row, std::string::npos) << r.out;
  std::istringstream fields(r.out.substr(row, r.out.find('\n', row) - row));
  std::string stage, unit, tile;
  uint64_t in = 0, out = 0, cycles = 0, count = 0;
  fields >> stage >> unit >> tile >> in >> out >> cycles >> count;
  EXPECT_EQ(unit, "0");
  EXPECT_EQ(tile, "(0,0)");
  EXPECT_EQ(in, 148u);
  EXPECT_EQ(out, 158u);
  EXPECT_EQ(cycles, 10u);
  EXPECT_EQ(count, 10u);
}

TEST_F(TraceFollowTest, PrimitiveAbsentOrFilteredIsExplained) {
  const std::string scene = write_json("one_triangle.json", one_triangle_scene());
  const std::string all = trace(scene, "--units 1", "all");
  // A primitive the scene does not have is bad input (issue #16 item 5: it
  // exited 0): exit 2, one line.
  for (const char* prim : {"7", "99999999"}) {
    CommandResult r = gpusim("trace follow " + all + " --prim " + prim);
    EXPECT_EQ(r.status, 2) << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
    EXPECT_NE(r.out.find("--prim " + std::string(prim) + ": primitive " + prim +
                         " does not exist: the scene has 1 primitive (ids 0..0)"),
              std::string::npos)
        << r.out;
  }
  CommandResult r;

  // A trace filtered to primitives 1:5 holds only control tokens for
  // primitive 0, and says which filter dropped it.
  const std::string filtered = trace(scene, "--units 1 --trace-prims 1:5", "filtered");
  r = gpusim("trace follow " + filtered + " --prim 0");
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("was filtered out of the trace"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--trace-prims 1:5"), std::string::npos) << r.out;

  // Neither --prim nor --pixel, both, a bad pixel: exit 2, one line.
  for (const std::string& args : {std::string(" "), std::string(" --prim 0 --pixel 1,1"),
                                  std::string(" --pixel 1"), std::string(" --pixel 64,0")}) {
    r = gpusim("trace follow " + all + args);
    EXPECT_EQ(r.status, 2) << args << ": " << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << args << ": " << r.out;
  }
}

// Three triangles over pixel (5, 5) of a 32x32 framebuffer, depth test
// "less" (the default), unorm24 depth cleared to 1: prim 0 red at window
// depth 0.5, prim 1 green behind it at 0.75, prim 2 blue in front at 0.25.
// Each is the lower-left half of the screen, window (0,0), (32,0), (0,32),
// which holds the pixel's centre (5.5, 5.5).
TEST_F(TraceFollowTest, PixelShowsEveryFragmentAndTheDepthTestOutcome) {
  const int w = 32, h = 32;
  nlohmann::json draws = nlohmann::json::array();
  const double z_clip[3] = {0.0, 0.5, -0.5};  // window depth (z + 1) / 2
  const nlohmann::json colors[3] = {{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1}};
  for (int i = 0; i < 3; ++i) {
    draws.push_back({{"positions",
                      {at_window(0, 0, z_clip[i], w, h), at_window(32, 0, z_clip[i], w, h),
                       at_window(0, 32, z_clip[i], w, h)}},
                     {"colors", {colors[i], colors[i], colors[i]}}});
  }
  const std::string scene =
      write_json("three.json", {{"framebuffer", {{"width", w}, {"height", h}}}, {"draws", draws}});
  const std::string dir = trace(scene);
  const TraceReader reader(dir);
  const std::vector<FragmentRecord> f = TraceFollow(reader).pixel_fragments(5, 5);

  // Expected, in time order: depth tests of 0, 1, 2 (in API order: one
  // unit owns the pixel and keeps its triangles in order), ROP writes of
  // the two that passed, each after its own depth test.
  std::vector<const FragmentRecord*> depth, rop;
  for (const FragmentRecord& r : f) {
    EXPECT_EQ(r.x, 5);
    EXPECT_EQ(r.y, 5);
    EXPECT_EQ(r.unit, 0);  // tile (0, 0): unit 0 of 4
    (r.stage == FragmentRecord::at_test ? depth : rop).push_back(&r);
  }
  ASSERT_EQ(depth.size(), 3u);
  ASSERT_EQ(rop.size(), 2u);
  const double unorm24 = 1.0 / 16777215.0;  // one step of the depth buffer
  // prim 0 at 0.5 against the cleared 1.0: passes, stores 0.5.
  EXPECT_EQ(depth[0]->prim, 0);
  EXPECT_EQ(depth[0]->outcome, FragmentRecord::passed);
  EXPECT_NEAR(depth[0]->depth, 0.5, unorm24);
  EXPECT_NEAR(depth[0]->old_depth, 1.0, unorm24);
  EXPECT_NEAR(depth[0]->value[0], 0.5, unorm24);
  // prim 1 at 0.75 against 0.5: fails, stores nothing.
  EXPECT_EQ(depth[1]->prim, 1);
  EXPECT_EQ(depth[1]->outcome, FragmentRecord::failed);
  EXPECT_NEAR(depth[1]->depth, 0.75, unorm24);
  EXPECT_NEAR(depth[1]->old_depth, 0.5, unorm24);
  EXPECT_TRUE(std::isnan(depth[1]->value[0]));
  // prim 2 at 0.25 against 0.5: passes, stores 0.25.
  EXPECT_EQ(depth[2]->prim, 2);
  EXPECT_EQ(depth[2]->outcome, FragmentRecord::passed);
  EXPECT_NEAR(depth[2]->depth, 0.25, unorm24);
  EXPECT_NEAR(depth[2]->old_depth, 0.5, unorm24);
  EXPECT_NEAR(depth[2]->value[0], 0.25, unorm24);
  // The ROP writes red, then blue, each later than its depth test.
  EXPECT_EQ(rop[0]->prim, 0);
  EXPECT_EQ(rop[1]->prim, 2);
  EXPECT_GT(rop[0]->cycle, depth[0]->cycle);
  EXPECT_GT(rop[1]->cycle, depth[2]->cycle);
  for (const FragmentRecord* r : rop) EXPECT_EQ(r->outcome, FragmentRecord::written);
  const float red[4] = {1, 0, 0, 1}, blue[4] = {0, 0, 1, 1};
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(rop[0]->value[k], red[k]);
    EXPECT_EQ(rop[1]->value[k], blue[k]);
  }
  for (size_t i = 1; i < f.size(); ++i) EXPECT_LE(f[i - 1].cycle, f[i].cycle);

  // The last write is the frame's pixel (frame.exr: rows top first).
  const Image img = read_exr(dir + "/frame.exr");
  const size_t p = static_cast<size_t>(h - 1 - 5) * w + 5;
  const char* channels[4] = {"R", "G", "B", "A"};
  for (int k = 0; k < 4; ++k) {
    ASSERT_NE(img.find(channels[k]), nullptr);
    EXPECT_EQ((*img.find(channels[k]))[p], rop[1]->value[k]) << channels[k];
  }
  ASSERT_NE(img.find("Z"), nullptr);
  EXPECT_NEAR((*img.find("Z"))[p], depth[2]->value[0], unorm24);

  const CommandResult r = gpusim("trace follow " + dir + " --pixel 5,5");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("5 fragment records (3 at the depth test, 2 at the ROP)"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("failed"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("frame.exr: rgba (0.0000, 0.0000, 1.0000, 1.0000)"), std::string::npos)
      << r.out;

  // A pixel no triangle covers: none, and the clear values.
  const CommandResult empty = gpusim("trace follow " + dir + " --pixel 31,31");
  ASSERT_EQ(empty.status, 0) << empty.out;
  EXPECT_NE(empty.out.find("no fragment touched it"), std::string::npos) << empty.out;
}

// A line and a point on a 32x32 framebuffer, one raster unit, tile size 16
// (testbench/configs/default.json), depth 0.5:
//  - draw 0, line 0: window (2.25, 5.5) to (12.25, 5.5), width 1, diamond
//    exit (docs/pipeline-spec.md 8b). Along y = 5.5 each pixel's diamond
//    spans x in (i, i + 1); the line starts inside pixel 2's diamond and
//    leaves it, crosses and leaves 3..11, and ends inside 12's without
//    leaving it: fragments at x = 2..11, y = 5 (10, all in tile (0, 0)).
//  - draw 1, point 1: window (20.5, 20.5), size 3 (8c): F = 768,
//    X0 = Y0 = round(20 * 256) - 384 = 4736, pixels with
//    4736 <= 256 x < 5504: x, y in 19..21 (9, all in tile (1, 1)).
TEST_F(TraceFollowTest, FollowsALineAndAPoint) {
  const int w = 32, h = 32;
  const std::string scene = write_json(
      "line_point.json",
      {{"framebuffer", {{"width", w}, {"height", h}}},
       {"draws",
        {{{"primitive", "lines"},
          {"positions", {at_window(2.25, 5.5, 0.0, w, h), at_window(12.25, 5.5, 0.0, w, h)}}},
         {{"primitive", "points"},
          {"positions", {at_window(20.5, 20.5, 0.0, w, h)}},
          {"state", {{"point_size", 3}}}}}}});
  const std::string dir = trace(scene, "--units 1");
  const TraceReader reader(dir);

  // Each primitive's fragments at the depth test: exactly its pixels.
  std::map<int64_t, std::set<std::pair<int, int>>> pixels;
  reader.for_each_fragment([&](const FragmentRecord& f) {
    if (f.stage == FragmentRecord::at_test) {
      EXPECT_TRUE(pixels[f.prim].insert({f.x, f.y}).second) << "twice: " << f.x << "," << f.y;
    }
  });
  std::set<std::pair<int, int>> line, point;
  for (int x = 2; x <= 11; ++x) line.insert({x, 5});
  for (int x = 19; x <= 21; ++x) {
    for (int y = 19; y <= 21; ++y) point.insert({x, y});
  }
  EXPECT_EQ(pixels[0], line);
  EXPECT_EQ(pixels[1], point);
  EXPECT_EQ(pixels.size(), 2u);

  struct Want {
    int64_t prim;
    const char* header;  // the first line, up to " in DIR"
    const char* word;    // the item at setup and the distributor
    PrimitiveKind kind;
    int tile;  // the tile (t, t) of its stamps
    size_t fragments;
  };
  for (const Want& want :
       {Want{0, "line 0 (draw 0, lines)", "line", PrimitiveKind::line, 0, 10},
        Want{1, "point 1 (draw 1, points)", "point", PrimitiveKind::point, 1, 9}}) {
    SCOPED_TRACE(want.header);
    const std::vector<TraceFollow::Step> steps = TraceFollow(reader).prim_steps(want.prim);
    std::vector<std::string> kinds;
    uint32_t stamps_in_rop = 0;
    for (const TraceFollow::Step& s : steps) {
      if (kinds.empty() || kinds.back() != s.stage->kind) kinds.push_back(s.stage->kind);
      EXPECT_EQ(s.record.draw, static_cast<uint32_t>(want.prim));
      // Every record of this draw's items is of the draw's kind.
      EXPECT_EQ(s.record.prim_kind, prim_kind_code(want.kind)) << s.stage->name;
      if (s.stage->kind == "depth_test" || s.stage->kind == "rop") {
        EXPECT_EQ(s.record.tile_x, want.tile) << s.stage->name;
        EXPECT_EQ(s.record.tile_y, want.tile) << s.stage->name;
      }
      if (s.stage->kind == "rop") stamps_in_rop += s.record.count;
    }
    // Through every stage to the ROP, as a triangle goes.
    EXPECT_EQ(kinds,
              (std::vector<std::string>{"command_processor", "vertex_fetch", "vertex_shader",
                                        "clipper", "primitive_setup", "tile_distributor",
                                        "tile_rasterizer", "depth_test", "interpolator", "rop"}));
    EXPECT_GE(stamps_in_rop, 1u);
    EXPECT_LE(stamps_in_rop, want.fragments);

    // The command line names the primitive by its kind at every row.
    const CommandResult r = gpusim("trace follow " + dir + " --prim " + std::to_string(want.prim));
    ASSERT_EQ(r.status, 0) << r.out;
    EXPECT_EQ(r.out.rfind(std::string(want.header) + " in " + dir + ": ", 0), 0u) << r.out;
    const std::string one = std::string(want.word) + " " + std::to_string(want.prim);
    EXPECT_NE(r.out.find("draw " + std::to_string(want.prim) + ": " + one + "\n"),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("slots: " + one + "\n"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("  " + std::string(want.word) + "\n"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("triangle "), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("ends at"), std::string::npos) << r.out;  // it reached the ROP
  }

  // The timeline names the items the same way.
  const std::string timeline = [&] {
    std::ifstream in(dir + "/timeline.json");
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }();
  EXPECT_NE(timeline.find("\"line 0 tile (0,0)\""), std::string::npos);
  EXPECT_NE(timeline.find("\"point 1 tile (1,1)\""), std::string::npos);
}

}  // namespace
}  // namespace gpusim
