// The golden model: the executable specification of the pipeline
// (docs/pipeline-spec.md). Plain C++, no SystemC, the simplest correct
// algorithm: per triangle in API order, scan the bounding box, evaluate every
// pixel exactly. Each step is a free function so tests can check it alone.
#pragma once

#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>
#include <vector>

#include "hw/fixed_point.h"
#include "hw/framebuffer.h"
#include "testbench/scene/scene.h"

namespace gpusim::golden {

// A vertex after transform and lighting: clip-space position and colour.
struct ShadedVertex {
  glm::vec4 clip{0.0f};
  glm::vec4 color{0.0f};
};

// Transform and light vertex `i` of the draw (spec: "Vertex transform and lighting").
ShadedVertex shade_vertex(const Scene& scene, const Draw& draw, uint32_t i);

// Primitive assembly: the draw's triangles as triples of vertex slots (positions
// in the index list, or vertex numbers when not indexed) in API order. The
// third slot is the provoking vertex (GL's last-vertex convention).
std::vector<std::array<uint32_t, 3>> assemble_triangles(PrimitiveType type, size_t slot_count);

// Clipping planes in clip space, each a distance d(v) with d >= 0 inside:
// w >= kMinClipW, near (z >= -w), far (z <= w), then the guard band's
// left, right, bottom, top.
constexpr int kClipPlaneCount = 7;
constexpr float kMinClipW = 1.0f / 4294967296.0f;  // 2^-32: keeps 1/w finite
struct GuardBand {
  float left, right, bottom, top;  // x >= -left*w, x <= right*w, ...
};
GuardBand guard_band_for(int width, int height);
float clip_distance(int plane, const glm::vec4& clip, const GuardBand& gb);

// Sutherland-Hodgman clip of a triangle against every plane; returns the
// clipped convex polygon (empty when nothing is left). Vertices are unchanged
// when all of them are inside every plane.
std::vector<ShadedVertex> clip_triangle(const std::array<ShadedVertex, 3>& tri,
                                        const GuardBand& gb);

// A vertex in window space, snapped.
struct WindowVertex {
  Subpixel x = 0, y = 0;         // 1/256 pixel
  float z = 0.0f;                // window depth, [0, 1] inside the frustum
  float inv_w = 0.0f;            // 1 / w_clip
  glm::vec4 color_over_w{0.0f};  // colour * (1 / w), for perspective correction
};
WindowVertex to_window(const ShadedVertex& v, int width, int height);

// Twice the signed area in subpixel^2: > 0 counter-clockwise (y up).
EdgeValue signed_area2(const WindowVertex& a, const WindowVertex& b, const WindowVertex& c);
// Edge function of edge a -> b at subpixel point (px, py).
EdgeValue edge_function(const WindowVertex& a, const WindowVertex& b, Subpixel px, Subpixel py);
// Fill rule: whether pixel centres exactly on edge a -> b (of a CCW triangle)
// belong to the triangle: left edges and bottom horizontal edges.
bool edge_owns_boundary(const WindowVertex& a, const WindowVertex& b);

struct Stats {
  uint64_t triangles_in = 0;            // assembled
  uint64_t triangles_invalid = 0;       // non-finite position or out-of-range index
  uint64_t triangles_clipped_away = 0;  // entirely outside the clip volume
  uint64_t triangles_clipped = 0;       // needed clipping and kept a part
  uint64_t triangles_after_clip = 0;    // triangles leaving the clipper
  uint64_t triangles_degenerate = 0;    // zero area after snapping
  uint64_t triangles_culled = 0;        // removed by face culling
  uint64_t triangles_rasterized = 0;    // set up and scanned
  uint64_t fragments_generated = 0;     // covered pixels
  uint64_t fragments_passed_depth = 0;
  uint64_t fragments_written = 0;  // passed depth with a colour channel enabled
  nlohmann::json to_json() const;
};

struct Result {
  Framebuffer framebuffer;
  // Per pixel, the id of the triangle that last wrote its colour (assembled
  // triangles numbered from 0 in API order across draws), or -1.
  std::vector<int64_t> last_writer;
  Stats stats;
};

// Render the scene: clear, then every draw in order.
Result render(const Scene& scene);

}  // namespace gpusim::golden
