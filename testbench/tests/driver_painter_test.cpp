// The painter's algorithm (testbench/driver/painter_sort.h, docs/painter.md):
// each of Newell, Newell and Sancha's tests on hand-made triangles, the
// split, and on the painter scenes the frame against the z-buffered frame
// of the same scene, rendered by the golden model.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <string>

#include "testbench/driver/painter_sort.h"
#include "testbench/golden/golden_model.h"

namespace gpusim::painter {
namespace {

// A triangle given in NDC (w = 1, so clip = NDC), white.
SortTriangle tri(glm::vec3 a, glm::vec3 b, glm::vec3 c) {
  const glm::vec4 white(1.0f);
  return make_triangle({glm::vec4(a, 1.0f), glm::vec4(b, 1.0f), glm::vec4(c, 1.0f)},
                       {white, white, white});
}

double area(const SortTriangle& t) {
  const glm::dvec3 e = glm::cross(t.ndc[1] - t.ndc[0], t.ndc[2] - t.ndc[0]);
  return 0.5 * std::abs(e.z);
}

TEST(PainterTests, DepthExtentsDisjoint) {
  const SortTriangle p = tri({-1, -1, 0.5f}, {1, -1, 0.6f}, {0, 1, 0.55f});
  const SortTriangle q = tri({-1, -1, -0.5f}, {1, -1, -0.4f}, {0, 1, -0.45f});
  EXPECT_EQ(decide(p, q), Decision::depth_extents);
}

TEST(PainterTests, XExtentsDisjoint) {
  const SortTriangle p = tri({-1, -1, 0.5f}, {-0.5f, -1, 0.0f}, {-0.7f, 1, 0.2f});
  const SortTriangle q = tri({0.5f, -1, 0.4f}, {1, -1, 0.1f}, {0.7f, 1, 0.2f});
  EXPECT_EQ(decide(p, q), Decision::x_extents);
  // Extents that only touch do not overlap: the fill rule gives a pixel on
  // a shared boundary to one triangle.
  const SortTriangle touching = tri({-0.5f, -1, 0.4f}, {1, -1, 0.1f}, {0.7f, 1, 0.2f});
  EXPECT_EQ(decide(p, touching), Decision::x_extents);
}

TEST(PainterTests, YExtentsDisjoint) {
  const SortTriangle p = tri({-1, -1, 0.5f}, {1, -1, 0.0f}, {0, -0.5f, 0.2f});
  const SortTriangle q = tri({-1, 0.5f, 0.4f}, {1, 0.5f, 0.1f}, {0, 1, 0.2f});
  EXPECT_EQ(decide(p, q), Decision::y_extents);
}

// q lies in the plane z = 0.2 x; p lies 0.1 to 0.15 behind it.
TEST(PainterTests, PBehindQPlane) {
  const SortTriangle q = tri({-1, -1, -0.2f}, {1, -1, 0.2f}, {0, 1, 0.0f});
  const SortTriangle p = tri({-0.5f, -0.5f, 0.0f}, {0.5f, -0.5f, 0.25f}, {0, 0.5f, 0.15f});
  EXPECT_TRUE(entirely_behind(p, q));
  EXPECT_FALSE(entirely_in_front(p, q));
  EXPECT_EQ(decide(p, q), Decision::p_behind_q_plane);
}

// p lies in z = 0.2 x + 0.1; q is in front of it but steep, so that p
// straddles q's plane and the third test cannot decide.
TEST(PainterTests, QInFrontOfPPlane) {
  const SortTriangle p = tri({-1, -1, -0.1f}, {1, -1, 0.3f}, {0, 1, 0.1f});
  const SortTriangle q = tri({-0.3f, -0.3f, -0.2f}, {0.3f, -0.3f, 0.0f}, {0, 0.3f, -0.9f});
  ASSERT_FALSE(entirely_behind(p, q));
  EXPECT_TRUE(entirely_in_front(q, p));
  EXPECT_EQ(decide(p, q), Decision::q_in_front_p_plane);
}

// Above and below the diagonal y = x: the boxes overlap, each straddles the
// other's plane (z = 0.3 x and z = -0.3 x), and only the projections decide.
TEST(PainterTests, ProjectionsDisjoint) {
  const SortTriangle p = tri({-1, -1, -0.3f}, {1, 1, 0.3f}, {-1, 1, -0.3f});
  const SortTriangle q = tri({-0.9f, -1, 0.27f}, {1, -1, -0.3f}, {1, 0.9f, -0.3f});
  ASSERT_FALSE(entirely_behind(p, q));
  ASSERT_FALSE(entirely_in_front(q, p));
  EXPECT_FALSE(projections_overlap(p, q));
  EXPECT_EQ(decide(p, q), Decision::projections);
  // Two halves of a square share the diagonal: touching is not overlapping.
  const SortTriangle lower = tri({-1, -1, 0.3f}, {1, -1, -0.3f}, {1, 1, -0.3f});
  EXPECT_FALSE(projections_overlap(p, lower));
}

// Two triangles passing through each other along x = 0: every test fails,
// and splitting p by q's plane gives pieces on either side of x = 0 whose
// areas add up to p's.
TEST(PainterTests, InterpenetratingPairIsAmbiguousAndSplits) {
  const glm::vec4 red(1, 0, 0, 1), blue(0, 0, 1, 1);
  const SortTriangle p =
      make_triangle({glm::vec4(-1, -1, -0.3f, 1), glm::vec4(1, -1, 0.3f, 1), glm::vec4(0, 1, 0, 1)},
                    {red, blue, red});
  const SortTriangle q = tri({-1, -1, 0.3f}, {1, -1, -0.3f}, {0, 1, 0});
  EXPECT_EQ(decide(p, q), Decision::ambiguous);
  EXPECT_EQ(decide(q, p), Decision::ambiguous);
  const SplitResult s = split(p, q);
  ASSERT_FALSE(s.behind.empty());
  ASSERT_FALSE(s.in_front.empty());
  double total = 0.0;
  // p (z = 0.3 x) is behind q's plane (z = -0.3 x) where x > 0.
  for (const SortTriangle& t : s.behind) {
    total += area(t);
    for (const glm::dvec3& v : t.ndc) EXPECT_GE(v.x, -1e-12);
    EXPECT_TRUE(entirely_behind(t, q));
  }
  for (const SortTriangle& t : s.in_front) {
    total += area(t);
    for (const glm::dvec3& v : t.ndc) EXPECT_LE(v.x, 1e-12);
    EXPECT_TRUE(entirely_in_front(t, q));
  }
  EXPECT_NEAR(total, area(p), 1e-9);
  // The cut of edge (-1,-1) -> (1,-1) is its midpoint, coloured halfway.
  bool found = false;
  for (const auto* side : {&s.behind, &s.in_front}) {
    for (const SortTriangle& t : *side) {
      for (int i = 0; i < 3; ++i) {
        if (t.clip[i].x == 0.0f && t.clip[i].y == -1.0f) {
          found = true;
          EXPECT_EQ(t.color[i], glm::vec4(0.5f, 0, 0.5f, 1));
        }
      }
    }
  }
  EXPECT_TRUE(found);
}

// The cut is made in clip space: with perspective (w differing per vertex)
// a cut vertex's colour is the clip-linear (perspective-correct) blend, not
// the screen-linear one.
TEST(PainterTests, SplitInterpolatesInClipSpace) {
  const glm::vec4 black(0, 0, 0, 1), white(1, 1, 1, 1);
  // Edge from (x, w) = (-1, 1) to (3, 3): NDC x from -1 to 1, crossing
  // NDC x = 0 at clip parameter t = 0.25 (x = 0), screen halfway.
  const SortTriangle p =
      make_triangle({glm::vec4(-1, -1, 0, 1), glm::vec4(3, -3, 0, 3), glm::vec4(0, 1, 0.5f, 1)},
                    {black, white, black});
  const SortTriangle q = tri({0, -1, -1}, {0, 1, -1}, {0, 0, 1});  // the plane x = 0
  const SplitResult s = split(p, q);
  bool found = false;
  for (const auto* side : {&s.behind, &s.in_front}) {
    for (const SortTriangle& t : *side) {
      for (int i = 0; i < 3; ++i) {
        if (t.clip[i].x == 0.0f && t.clip[i].w == 1.5f) {
          found = true;
          EXPECT_EQ(t.color[i], glm::vec4(0.25f, 0.25f, 0.25f, 1));
        }
      }
    }
  }
  EXPECT_TRUE(found);
}

void expect_counters_balance(const Stats& s) {
  EXPECT_EQ(s.decided_depth_extents + s.decided_x_extents + s.decided_y_extents +
                s.decided_p_behind_q_plane + s.decided_q_in_front_p_plane + s.decided_projections +
                s.ambiguous,
            s.comparisons);
  // Without near-plane cuts every triangle is dropped or sorted.
  if (s.triangles_near_clipped == 0) {
    EXPECT_EQ(s.triangles_in, s.triangles_dropped + s.triangles_sorted);
  }
  EXPECT_GE(s.triangles_out, s.triangles_sorted + s.splits);  // a split adds one piece or two
  EXPECT_LE(s.triangles_out, s.triangles_sorted + 2 * s.splits);
}

Scene scene_file(const std::string& name) {
  return load_scene(std::string(GPUSIM_SOURCE_DIR) + "/testbench/scenes/" + name + ".json");
}

// The same scene under the z-buffer: the draws as the file gives them.
Scene zbuffered(Scene s) {
  s.visibility = Visibility::zbuffer;
  return s;
}

// Pixel by pixel against the z-buffered frame: the colour's largest
// difference in unorm8 steps and the depth's in unorm24 steps.
struct FrameDiff {
  long long color_one_step = 0;  // colour differs by exactly one step
  long long wrong = 0;           // colour differs by more: the other surface shows
  long long wrong_near_tie = 0;  // of those, surfaces within kNearTieSteps in depth
  long long depth_only = 0;      // same colour, depth differs
  long long max_depth_steps = 0;
};
// A pixel where two surfaces lie within this many depth steps (2^-21 of the
// depth range) is a near-tie: the sort's plane tests treat vertices within
// one step of NDC z (2^-23, two window depth steps) as on the plane, and
// snapping a vertex by up to 1/512 pixel moves depth across a steep
// triangle by a few steps more.
constexpr long long kNearTieSteps = 8;

FrameDiff compare(const Framebuffer& painter, const Framebuffer& zbuffer) {
  FrameDiff d;
  EXPECT_EQ(painter.width, zbuffer.width);
  EXPECT_EQ(painter.color_format, ColorFormat::rgba8);
  EXPECT_EQ(painter.depth_format, DepthFormat::unorm24);
  for (int y = 0; y < painter.height; ++y) {
    for (int x = 0; x < painter.width; ++x) {
      long long dc = 0;
      for (int k = 0; k < 4; ++k) {
        dc = std::max(dc, std::llabs(static_cast<long long>(painter.color_at(x, y)[k]) -
                                     static_cast<long long>(zbuffer.color_at(x, y)[k])));
      }
      const size_t p = painter.pixel_index(x, y);
      const long long dz = std::llabs(static_cast<long long>(painter.depth[p]) -
                                      static_cast<long long>(zbuffer.depth[p]));
      d.max_depth_steps = std::max(d.max_depth_steps, dz);
      if (dc == 1) ++d.color_one_step;
      if (dc > 1) {
        ++d.wrong;
        if (dz <= kNearTieSteps) ++d.wrong_near_tie;
      }
      if (dc == 0 && dz != 0) ++d.depth_only;
    }
  }
  return d;
}

// The scene rendered with the painter's draws against the same scene
// z-buffered.
FrameDiff painter_vs_zbuffer(const std::string& name, Stats* stats_out) {
  Scene painted = scene_file(name);
  EXPECT_EQ(painted.visibility, Visibility::painter);
  const Scene plain = zbuffered(painted);
  const std::optional<Stats> stats = apply_visibility(painted);
  EXPECT_TRUE(stats.has_value());
  if (stats) *stats_out = *stats;
  const FrameDiff d =
      compare(golden::render(painted).framebuffer, golden::render(plain).framebuffer);
  std::printf(
      "%s: %lld pixels show another surface (%lld within %lld depth steps), %lld differ "
      "by one colour step, %lld in depth only (at most %lld steps)\n",
      name.c_str(), d.wrong, d.wrong_near_tie, kNearTieSteps, d.color_one_step, d.depth_only,
      d.max_depth_steps);
  return d;
}

// Every order of the scene's sortable triangles, drawn with the depth test
// always passing, leaves some pixel showing the wrong surface: sorting alone
// cannot succeed.
void expect_no_order_is_right(const std::string& name) {
  Scene s = zbuffered(scene_file(name));
  const Framebuffer want = golden::render(s).framebuffer;
  std::vector<size_t> order(s.draws.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  do {
    Scene permuted = s;
    permuted.draws.clear();
    for (size_t i : order) {
      permuted.draws.push_back(s.draws[i]);
      permuted.draws.back().state.depth_func = CompareFunc::always;
    }
    const FrameDiff d = compare(golden::render(permuted).framebuffer, want);
    EXPECT_GT(d.wrong - d.wrong_near_tie, 0) << name << ": an order without splits is right";
  } while (std::next_permutation(order.begin(), order.end()));
}

TEST(PainterScenes, CycleNeedsASplitAndThenMatchesTheZBuffer) {
  expect_no_order_is_right("painter_cycle");
  Stats stats;
  const FrameDiff d = painter_vs_zbuffer("painter_cycle", &stats);
  EXPECT_GT(stats.splits, 0u);
  EXPECT_EQ(stats.unresolved, 0u);
  expect_counters_balance(stats);
  // No pixel shows the wrong blade; split pieces' colours may round one
  // step differently from the whole triangle's.
  EXPECT_EQ(d.wrong, 0);
}

TEST(PainterScenes, InterpenetrationIsSplitAndThenMatchesTheZBuffer) {
  expect_no_order_is_right("painter_interpenetrate");
  Stats stats;
  const FrameDiff d = painter_vs_zbuffer("painter_interpenetrate", &stats);
  EXPECT_GT(stats.splits, 0u);
  EXPECT_EQ(stats.unresolved, 0u);
  expect_counters_balance(stats);
  // Along the line of intersection the two surfaces are a near-tie.
  EXPECT_EQ(d.wrong, d.wrong_near_tie);
}

TEST(PainterScenes, DefaultMatchesTheZBufferExceptNearTies) {
  Stats stats;
  const FrameDiff d = painter_vs_zbuffer("painter_default", &stats);
  expect_counters_balance(stats);
  EXPECT_EQ(stats.draws_passed, 1u);       // the blended quad
  EXPECT_GT(stats.triangles_dropped, 0u);  // the mesh's back faces
  EXPECT_EQ(d.wrong, d.wrong_near_tie);
}

// Clears, viewports, flat shading under the first-vertex convention,
// screen interpolation and Phong in one frame (painter_features.json).
TEST(PainterScenes, FeaturesMatchTheZBufferExceptNearTies) {
  Stats stats;
  const FrameDiff d = painter_vs_zbuffer("painter_features", &stats);
  expect_counters_balance(stats);
  // The Phong sphere, the screen-interpolated triangle, the other viewport.
  EXPECT_EQ(stats.draws_passed, 3u);
  EXPECT_EQ(stats.draws_sorted, 5u);
  EXPECT_GT(stats.splits, 0u);  // near a and near b interpenetrate
  EXPECT_EQ(d.wrong, d.wrong_near_tie);
}

TEST(PainterScenes, PassedDrawsFollowUnchanged) {
  Scene s = scene_file("painter_default");
  const Draw blended = s.draws.back();
  ASSERT_TRUE(blended.state.blend);
  ASSERT_TRUE(apply_visibility(s).has_value());
  const Draw& last = s.draws.back();
  EXPECT_EQ(last.name, blended.name);
  EXPECT_EQ(last.state, blended.state);
  EXPECT_EQ(last.positions, blended.positions);
  for (size_t i = 0; i + 1 < s.draws.size(); ++i) {
    EXPECT_EQ(s.draws[i].state.depth_func, CompareFunc::always) << s.draws[i].name;
    EXPECT_FALSE(s.draws[i].lighting);
  }
}

TEST(PainterScenes, ZBufferSceneIsLeftAlone) {
  Scene s = scene_file("painter_cycle");
  s.visibility = Visibility::zbuffer;
  const Scene before = s;
  EXPECT_FALSE(apply_visibility(s).has_value());
  ASSERT_EQ(s.draws.size(), before.draws.size());
  for (size_t i = 0; i < s.draws.size(); ++i)
    EXPECT_EQ(s.draws[i].positions, before.draws[i].positions);
}

TEST(PainterScenes, Deterministic) {
  Scene a = scene_file("painter_default"), b = scene_file("painter_default");
  const Stats sa = *apply_visibility(a), sb = *apply_visibility(b);
  EXPECT_EQ(sa.to_json(), sb.to_json());
  ASSERT_EQ(a.draws.size(), b.draws.size());
  for (size_t i = 0; i < a.draws.size(); ++i) {
    EXPECT_EQ(a.draws[i].positions, b.draws[i].positions);
    EXPECT_EQ(a.draws[i].colors, b.draws[i].colors);
  }
}

// A triangle reaching behind the eye is cut at the near plane before the
// sort divides by w; what is left draws as the z-buffer draws it.
TEST(PainterScenes, NearPlaneCutBeforeSorting) {
  const std::string text = R"({
    "visibility": "painter",
    "framebuffer": {"width": 64, "height": 64},
    "camera": {"type": "perspective", "fovy": 60, "near": 0.5, "far": 10},
    "draws": [
      {"positions": [[-1, -0.5, -3], [1, -0.5, -3], [0, -0.5, 2]],
       "colors": [[1, 0, 0, 1], [0, 1, 0, 1], [0, 0, 1, 1]]},
      {"positions": [[-1, -1, -2], [1, -1, -2], [0, 1, -2]]}
    ]})";
  Scene painted = load_scene_from_string(text, "near.json");
  const Scene plain = zbuffered(painted);
  const std::optional<Stats> stats = apply_visibility(painted);
  ASSERT_TRUE(stats.has_value());
  EXPECT_EQ(stats->triangles_near_clipped, 1u);
  for (const Draw& d : painted.draws) {
    for (const glm::vec4& p : d.positions) EXPECT_GE(p.z, -p.w) << d.name;  // inside the near plane
  }
  const FrameDiff d =
      compare(golden::render(painted).framebuffer, golden::render(plain).framebuffer);
  EXPECT_EQ(d.wrong, d.wrong_near_tie);
}

// The painter scene given as text, rendered rewritten against the same
// scene z-buffered.
FrameDiff text_vs_zbuffer(const std::string& text, Stats* stats_out, Scene* painted_out = nullptr) {
  Scene painted = load_scene_from_string(text, "painter.json");
  const Scene plain = zbuffered(painted);
  const std::optional<Stats> stats = apply_visibility(painted);
  EXPECT_TRUE(stats.has_value());
  if (stats) *stats_out = *stats;
  if (painted_out != nullptr) *painted_out = painted;
  return compare(golden::render(painted).framebuffer, golden::render(plain).framebuffer);
}

// The depth-partition trick: the far part of a scene is drawn, the depth
// buffer cleared, then the near part, whose surfaces lie farther in NDC
// than the far part's but must cover them. A sort across the clear would
// draw the near part first, under the far one; each stretch in the wrong
// API order shows that each is still sorted.
TEST(PainterScenes, ClearsDivideTheSortAndKeepTheirPlaces) {
  const std::string text = R"({
    "visibility": "painter",
    "framebuffer": {"width": 64, "height": 64, "depth_format": "unorm24"},
    "draws": [
      {"name": "far near", "positions": [[-0.5, -0.5, -0.6, 1], [0.5, -0.5, -0.6, 1], [0, 0.5, -0.6, 1]],
       "colors": [[1, 0, 0, 1], [1, 0, 0, 1], [1, 0, 0, 1]]},
      {"name": "far back", "positions": [[-1, -1, -0.4, 1], [1, -1, -0.4, 1], [-1, 1, -0.4, 1]],
       "colors": [[0, 1, 0, 1], [0, 1, 0, 1], [0, 1, 0, 1]]},
      {"clear": {"depth": 1}},
      {"name": "near near", "positions": [[-0.2, -0.9, 0.6, 1], [0.9, -0.9, 0.6, 1], [0.9, 0.2, 0.6, 1]],
       "colors": [[0, 0, 1, 1], [0, 0, 1, 1], [0, 0, 1, 1]]},
      {"name": "near back", "positions": [[-0.1, -1, 0.8, 1], [1, -1, 0.8, 1], [1, 1, 0.8, 1]],
       "colors": [[1, 1, 0, 1], [1, 1, 0, 1], [1, 1, 0, 1]]},
      {"clear": {"depth": 0.5}}
    ]})";
  Stats stats;
  Scene painted;
  const FrameDiff d = text_vs_zbuffer(text, &stats, &painted);
  expect_counters_balance(stats);
  EXPECT_EQ(stats.draws_sorted, 4u);
  EXPECT_EQ(d.wrong, 0);
  EXPECT_EQ(d.color_one_step, 0);
  EXPECT_EQ(d.depth_only, 0);
  // Each stretch is drawn back to front, and each clear stands where its
  // stretch ends.
  const std::vector<std::string> want = {
      "draws[1] far back (painter)", "draws[0] far near (painter)", "draws[4] near back (painter)",
      "draws[3] near near (painter)"};
  ASSERT_EQ(painted.draws.size(), want.size());
  for (size_t i = 0; i < want.size(); ++i) EXPECT_EQ(painted.draws[i].name, want[i]);
  ASSERT_EQ(painted.clears.size(), 2u);
  EXPECT_EQ(painted.clears[0].before_draw, 2u);
  EXPECT_TRUE(painted.clears[0].depth);
  EXPECT_EQ(painted.clears[1].before_draw, 4u);
  EXPECT_TRUE(painted.clears[1].depth);
}

// Passed draws follow the sorted ones of their own stretch, before the clear.
TEST(PainterScenes, PassedDrawsStayInTheirStretch) {
  const std::string text = R"({
    "visibility": "painter",
    "framebuffer": {"width": 32, "height": 32},
    "draws": [
      {"name": "line", "primitive": "lines", "positions": [[-1, 0, 0, 1], [1, 0, 0, 1]]},
      {"name": "tri", "positions": [[-1, -1, 0, 1], [1, -1, 0, 1], [0, 1, 0, 1]]},
      {"clear": {"depth": 1}},
      {"name": "tri 2", "positions": [[-1, -1, 0.5, 1], [1, -1, 0.5, 1], [0, 1, 0.5, 1]]}
    ]})";
  Scene painted = load_scene_from_string(text, "a.json");
  ASSERT_TRUE(apply_visibility(painted).has_value());
  ASSERT_EQ(painted.draws.size(), 3u);
  EXPECT_EQ(painted.draws[0].name, "draws[1] tri (painter)");
  EXPECT_EQ(painted.draws[1].name, "draws[0] line");
  EXPECT_EQ(painted.draws[2].name, "draws[3] tri 2 (painter)");
  ASSERT_EQ(painted.clears.size(), 1u);
  EXPECT_EQ(painted.clears[0].before_draw, 2u);
}

// Overlapping draws in two viewports (supersampled, so the viewports are
// scaled) and under two depth ranges: the first sortable draw's viewport
// and depth range are sorted, the others passed; a reversed depth range is
// passed too. Every frame is the z-buffer's.
TEST(PainterScenes, ViewportsAndDepthRanges) {
  const std::string text = R"({
    "visibility": "painter",
    "framebuffer": {"width": 48, "height": 40, "supersample": 2, "depth_format": "unorm24"},
    "draws": [
      {"name": "front", "positions": [[-0.6, -0.6, -0.5, 1], [0.6, -0.6, -0.5, 1], [0, 0.6, 0.0, 1]],
       "colors": [[1, 0, 0, 1], [1, 0.5, 0, 1], [1, 0, 0.5, 1]], "state": {"viewport": [4, 2, 30, 30]}},
      {"name": "back", "positions": [[-1, -1, 0.2, 1], [1, -1, 0.2, 1], [-1, 1, 0.2, 1]],
       "colors": [[0, 1, 0, 1], [0, 1, 0, 1], [0, 1, 0, 1]], "state": {"viewport": [4, 2, 30, 30]}},
      {"name": "other viewport", "positions": [[-1, -1, 0.0, 1], [1, -1, 0.0, 1], [1, 1, 0.0, 1]],
       "colors": [[0, 0, 1, 1], [0, 0, 1, 1], [0, 0, 1, 1]], "state": {"viewport": [14, 6, 30, 30]}},
      {"name": "other range", "positions": [[-1, 1, 0.0, 1], [1, -1, 0.0, 1], [1, 1, 0.0, 1]],
       "colors": [[1, 1, 0, 1], [1, 1, 0, 1], [1, 1, 0, 1]],
       "state": {"viewport": [4, 2, 30, 30], "depth_range": [0.1, 0.9]}},
      {"name": "reversed", "positions": [[-0.2, -1, 0.9, 1], [1, -0.2, 0.9, 1], [1, 1, -0.9, 1]],
       "colors": [[0, 1, 1, 1], [0, 1, 1, 1], [0, 1, 1, 1]],
       "state": {"viewport": [4, 2, 30, 30], "depth_range": [1, 0]}}
    ]})";
  Stats stats;
  Scene painted;
  const FrameDiff d = text_vs_zbuffer(text, &stats, &painted);
  expect_counters_balance(stats);
  EXPECT_EQ(stats.draws_sorted, 2u);
  EXPECT_EQ(stats.draws_passed, 3u);
  ASSERT_EQ(painted.draws.size(), 5u);
  EXPECT_EQ(painted.draws[0].name, "draws[1] back (painter)");
  EXPECT_EQ(painted.draws[1].name, "draws[0] front (painter)");
  EXPECT_EQ(painted.draws[2].name, "draws[2] other viewport");
  EXPECT_EQ(painted.draws[3].name, "draws[3] other range");
  EXPECT_EQ(painted.draws[4].name, "draws[4] reversed");
  EXPECT_EQ(d.wrong, 0);
}

// A triangle of a few subpixels on the whole target snaps to zero area in
// an 8 x 8 viewport: the driver drops what the model drops, in the draw's
// viewport, as the golden model's counters say.
TEST(PainterScenes, CullsInTheDrawsViewport) {
  const std::string text = R"({
    "visibility": "painter",
    "framebuffer": {"width": 256, "height": 256},
    "draws": [
      {"name": "tiny", "positions": [[0, 0, 0, 1], [0.0002, 0, 0, 1], [0, 0.0002, 0, 1]],
       "state": {"viewport": [0, 0, 8, 8]}},
      {"name": "back-facing", "positions": [[0, 0, 0, 1], [0, 1, 0, 1], [1, 0, 0, 1]],
       "state": {"viewport": [0, 0, 8, 8], "cull": "back"}},
      {"name": "kept", "positions": [[-1, -1, 0, 1], [1, -1, 0, 1], [0, 1, 0, 1]],
       "state": {"viewport": [0, 0, 8, 8]}}
    ]})";
  Scene painted = load_scene_from_string(text, "a.json");
  const golden::Result plain = golden::render(zbuffered(painted));
  ASSERT_EQ(plain.stats.triangles_degenerate, 1u);
  ASSERT_EQ(plain.stats.triangles_culled, 1u);
  const Stats stats = *apply_visibility(painted);
  EXPECT_EQ(stats.triangles_dropped,
            plain.stats.triangles_degenerate + plain.stats.triangles_culled);
  EXPECT_EQ(stats.triangles_out, 1u);
}

// Flat-shaded strips and fans under both conventions: the painter draws
// them behind a nearer triangle given first, in the provoking vertex's
// colour (every vertex coloured differently, so any other is wrong).
TEST(PainterScenes, FlatShadingTakesTheProvokingVertex) {
  for (const std::string convention : {"first", "last"}) {
    const std::string text = R"({
      "visibility": "painter",
      "framebuffer": {"width": 64, "height": 64, "depth_format": "unorm24"},
      "draws": [
        {"name": "near", "positions": [[-0.3, -0.3, -0.5, 1], [0.3, -0.3, -0.5, 1], [0, 0.3, -0.5, 1]]},
        {"name": "strip", "primitive": "triangle_strip",
         "positions": [[-1, -1, 0.3, 1], [-1, 0, 0.3, 1], [0, -1, 0.3, 1], [0, 0, 0.3, 1], [1, -1, 0.3, 1]],
         "colors": [[1, 0, 0, 1], [0, 1, 0, 1], [0, 0, 1, 1], [1, 1, 0, 1], [0, 1, 1, 1]],
         "state": {"shading": "flat", "provoking_vertex": ")" +
                             convention + R"("}},
        {"name": "fan", "primitive": "triangle_fan",
         "positions": [[0, 0.5, 0.2, 1], [1, 0.5, 0.2, 1], [1, 1, 0.2, 1], [0, 1, 0.2, 1]],
         "colors": [[1, 0, 1, 1], [0.5, 0.5, 0.5, 1], [0.2, 0.6, 0.9, 1], [0.9, 0.4, 0.1, 1]],
         "state": {"shading": "flat", "provoking_vertex": ")" +
                             convention + R"("}}
      ]})";
    Stats stats;
    const FrameDiff d = text_vs_zbuffer(text, &stats);
    EXPECT_EQ(stats.draws_sorted, 3u) << convention;
    EXPECT_EQ(d.wrong, 0) << convention;
    EXPECT_EQ(d.color_one_step, 0) << convention;
  }
}

// Screen interpolation: a Gouraud draw with varying w is passed unchanged
// (a split's clip-linear colour is not the affine one), a flat one is
// sorted; they interpenetrate a perspective draw, and the frame is the
// z-buffer's.
TEST(PainterScenes, ScreenInterpolatedGouraudIsPassed) {
  const std::string text = R"({
    "visibility": "painter",
    "framebuffer": {"width": 64, "height": 64, "depth_format": "unorm24"},
    "draws": [
      {"name": "screen gouraud", "positions": [[-2, -2, -1, 2], [0.5, -0.5, 0.5, 0.5], [-1, 1, 0.4, 1]],
       "colors": [[1, 0, 0, 1], [0, 1, 0, 1], [0, 0, 1, 1]],
       "state": {"interpolation": "screen"}},
      {"name": "screen flat", "positions": [[1, -1, 0.4, 1], [1, 1, -0.4, 1], [-0.5, 0.5, 0.2, 1]],
       "colors": [[1, 1, 0, 1], [0, 1, 1, 1], [1, 0, 1, 1]],
       "state": {"interpolation": "screen", "shading": "flat"}},
      {"name": "perspective", "positions": [[-1, -1, 0.3, 1], [2, -2, -0.8, 2], [0.5, 1, 0.0, 1]],
       "colors": [[0.5, 0, 0, 1], [0, 0.5, 0, 1], [0, 0, 0.5, 1]]}
    ]})";
  Stats stats;
  Scene painted;
  const FrameDiff d = text_vs_zbuffer(text, &stats, &painted);
  expect_counters_balance(stats);
  EXPECT_EQ(stats.draws_sorted, 2u);
  EXPECT_EQ(stats.draws_passed, 1u);
  const Draw& last = painted.draws.back();
  EXPECT_EQ(last.name, "draws[0] screen gouraud");
  EXPECT_EQ(last.state.interpolation, Interpolation::screen);
  EXPECT_EQ(d.wrong, d.wrong_near_tie);
}

// The Phong scene as a painter's: the per-pixel lit draws (and the lines)
// are passed, still lit per pixel, and the frame is the z-buffer's; drawn
// pre-lit they would be Gouraud, far off the z-buffered frame.
TEST(PainterScenes, PhongDrawsArePassedStillLitPerPixel) {
  Scene painted = scene_file("phong");
  painted.visibility = Visibility::painter;
  const Scene plain = zbuffered(painted);
  size_t phong = 0;
  for (const Draw& d : plain.draws) phong += golden::lit_per_pixel(d) ? 1 : 0;
  ASSERT_GT(phong, 0u);
  const Stats stats = *apply_visibility(painted);
  expect_counters_balance(stats);
  EXPECT_GT(stats.draws_sorted, 0u);
  size_t phong_after = 0;
  for (const Draw& d : painted.draws) phong_after += golden::lit_per_pixel(d) ? 1 : 0;
  EXPECT_EQ(phong_after, phong);
  const FrameDiff d =
      compare(golden::render(painted).framebuffer, golden::render(plain).framebuffer);
  EXPECT_EQ(d.wrong, d.wrong_near_tie);
}

TEST(PainterScenes, VisibilityKeyIsValidated) {
  const std::string base = R"({"visibility": )";
  EXPECT_EQ(load_scene_from_string(base + R"("painter"})", "a.json").visibility,
            Visibility::painter);
  EXPECT_EQ(load_scene_from_string(base + R"("zbuffer"})", "a.json").visibility,
            Visibility::zbuffer);
  EXPECT_EQ(load_scene_from_string("{}", "a.json").visibility, Visibility::zbuffer);
  try {
    load_scene_from_string(base + R"("sorted"})", "a.json");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), R"(a.json: visibility: expected one of zbuffer, painter, got "sorted")");
  }
}

}  // namespace
}  // namespace gpusim::painter
