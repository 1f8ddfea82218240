// The painter's algorithm as a host-side (driver) visibility option
// (docs/painter.md): a scene with "visibility": "painter" has its opaque
// filled triangles transformed and lit here, sorted from farthest to nearest
// with Newell, Newell and Sancha's overlap tests, split where they overlap
// cyclically or interpenetrate, and handed to the models as clip-space draws
// with the depth test set to always. Both the golden model and the cycle
// model consume the rewritten scene, so it plays no part in bit-exactness.
#pragma once

#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

#include "testbench/scene/scene.h"

namespace gpusim::painter {

// One triangle as the sort sees it: clip-space vertices and their colours
// (what is submitted), and in double precision its normalized device
// coordinates, extents and plane (what is compared).
struct SortTriangle {
  std::array<glm::vec4, 3> clip{};
  std::array<glm::vec4, 3> color{};
  uint32_t draw = 0;   // index of the draw it came from
  uint64_t order = 0;  // its position in API order, for a stable sort
  bool moved = false;  // moved ahead of another triangle once already
  std::array<glm::dvec3, 3> ndc{};
  glm::dvec3 min{0.0}, max{0.0};  // extents in NDC; larger z is farther
  // Plane n . p + d = 0 through ndc, |n| = 1, oriented so that n.z >= 0:
  // plane_side(p) > 0 means p lies behind the plane (farther from the viewer).
  glm::dvec3 n{0.0};
  double d = 0.0;
};

// Builds the sort's view of a triangle; every w must be > 0.
SortTriangle make_triangle(const std::array<glm::vec4, 3>& clip,
                           const std::array<glm::vec4, 3>& color);

// Signed distance of an NDC point from t's plane (> 0: behind it).
double plane_side(const SortTriangle& t, const glm::dvec3& p);

// The classic tests for a pair where p is ahead of q in the list (p is to be
// drawn first): each true answer proves drawing p before q is safe.
bool depth_extents_disjoint(const SortTriangle& p, const SortTriangle& q);  // q nearer than p
bool x_extents_disjoint(const SortTriangle& p, const SortTriangle& q);
bool y_extents_disjoint(const SortTriangle& p, const SortTriangle& q);
bool entirely_behind(const SortTriangle& t, const SortTriangle& plane);    // t behind plane's
bool entirely_in_front(const SortTriangle& t, const SortTriangle& plane);  // t in front
bool projections_overlap(const SortTriangle& p, const SortTriangle& q);    // interiors, x/y

// Which test decided a pair, in the order they are tried.
enum class Decision : uint8_t {
  depth_extents,       // q is entirely nearer than p: no overlap in depth
  x_extents,           // screen x extents do not overlap
  y_extents,           // screen y extents do not overlap
  p_behind_q_plane,    // p lies entirely behind q's plane
  q_in_front_p_plane,  // q lies entirely in front of p's plane
  projections,         // the projections do not overlap
  ambiguous,           // every test failed: q may have to be drawn before p
};
Decision decide(const SortTriangle& p, const SortTriangle& q);

// Splits t by the plane of `by` (in clip space, see docs/painter.md):
// the pieces behind the plane, then the pieces in front, as triangles with
// t's winding. Empty sides give no pieces.
struct SplitResult {
  std::vector<SortTriangle> behind, in_front;
};
SplitResult split(const SortTriangle& t, const SortTriangle& by);

struct Stats {
  uint64_t draws_sorted = 0;            // draws whose triangles took part in the sort
  uint64_t draws_passed = 0;            // submitted unchanged after their stretch's sorted ones
  uint64_t triangles_in = 0;            // assembled from the sorted draws
  uint64_t triangles_dropped = 0;       // invalid, degenerate or culled in the driver
  uint64_t triangles_near_clipped = 0;  // cut at the near plane before sorting
  uint64_t triangles_sorted = 0;        // entering the sort
  uint64_t comparisons = 0;             // pairs tested
  uint64_t decided_depth_extents = 0;
  uint64_t decided_x_extents = 0;
  uint64_t decided_y_extents = 0;
  uint64_t decided_p_behind_q_plane = 0;
  uint64_t decided_q_in_front_p_plane = 0;
  uint64_t decided_projections = 0;
  uint64_t ambiguous = 0;      // pairs every test left undecided
  uint64_t swaps = 0;          // q moved ahead of p
  uint64_t cycles = 0;         // a moved triangle met again undecided
  uint64_t splits = 0;         // triangles cut by another's plane
  uint64_t unresolved = 0;     // undecided pairs left in depth order, per meeting
  uint64_t triangles_out = 0;  // submitted
  uint64_t draws_out = 0;      // draws submitted, sorted and passed
  nlohmann::json to_json() const;
};

// Orders the triangles for drawing back to front (the first is drawn first).
std::vector<SortTriangle> sort(std::vector<SortTriangle> triangles, Stats& stats);

// The driver: when scene.visibility is painter, rewrites scene.draws as
// above, each stretch between clears on its own, moves each clear's
// before_draw to its place in the rewritten list, and returns the sort's
// figures; otherwise leaves the scene alone.
std::optional<Stats> apply_visibility(Scene& scene);

}  // namespace gpusim::painter
