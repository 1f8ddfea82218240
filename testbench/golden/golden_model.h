// The golden model: the executable specification of the pipeline
// (docs/pipeline-spec.md). Plain C++, no SystemC, the simplest correct
// algorithm: per primitive in API order, evaluate every candidate pixel
// exactly: a triangle's bounding box, the few pixels per column (or row)
// around a line, tested against the diamond-exit rule's definition, a point's
// square. Each step is a free function so tests can check it alone.
#pragma once

#include <array>
#include <cstdint>
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>
#include <vector>

#include "hw/fixed_point.h"
#include "hw/framebuffer.h"
#include "hw/pipeline_counts.h"
#include "testbench/scene/scene.h"

namespace gpusim::golden {

// A vertex after transform and lighting: clip-space position and colour; in
// a lit Phong draw also its eye-space unit normal and position, interpolated
// per pixel (spec section 9b); in a textured draw its texture coordinate
// (section 9c); 0 otherwise.
struct ShadedVertex {
  glm::vec4 clip{0.0f};
  glm::vec4 color{0.0f};
  glm::vec3 normal{0.0f};
  glm::vec3 eye{0.0f};
  glm::vec2 texcoord{0.0f};
};

// Transform and light vertex `i` of the draw (spec: "Vertex transform and lighting").
ShadedVertex shade_vertex(const Scene& scene, const Draw& draw, uint32_t i);

// Whether the draw's triangles and lines are lit per pixel (spec section 9b):
// shading "phong", lighting on, normals present.
bool lit_per_pixel(const Draw& draw);
// Section 2's equation for eye position `eye` and unit normal `n`, the
// scene's lights and the draw's material: the lit colour, clamped.
glm::vec4 light(const Scene& scene, const Material& material, const glm::vec3& eye,
                const glm::vec3& n);
// Section 9b: the colour of a pixel whose interpolated normal and eye
// position are `normal` (not yet unit) and `eye`.
glm::vec4 light_pixel(const Scene& scene, const Material& material, const glm::vec3& normal,
                      const glm::vec3& eye);

// Primitive assembly: the draw's triangles as triples of vertex slots (positions
// in the index list, or vertex numbers when not indexed) in API order.
std::vector<std::array<uint32_t, 3>> assemble_triangles(PrimitiveType type, size_t slot_count);
// Triangle i of them (i < primitive_count(type, slot_count)), without the
// list: render() walks a 10 M-triangle draw without holding 120 MB of triples.
std::array<uint32_t, 3> triangle_slots(PrimitiveType type, uint32_t i);
// Which of triangle i's three assembled slots is its provoking vertex (spec
// section 3, GL's table of provoking vertices): the third under the
// last-vertex convention; under the first-vertex one the first, except an odd
// strip triangle's (its slots start i+1, i) and a fan's (slot i+1, not the
// centre), where it is the second.
int provoking_position(PrimitiveType type, uint32_t i, ProvokingVertex convention);

// A line as two vertex slots (the closing line of a loop: n-1, 0), the
// second the provoking vertex under the last-vertex convention, the first
// under the first-vertex one (spec section 3), with the Bresenham end flags: whether its first and
// its last pixel are drawn (cleared where a strip or loop shares a vertex).
struct LineSlots {
  std::array<uint32_t, 2> v{};
  bool draw_first = true, draw_last = true;
  bool operator==(const LineSlots& o) const {
    return v == o.v && draw_first == o.draw_first && draw_last == o.draw_last;
  }
};
// Primitive assembly of a `lines`, `line_strip` or `line_loop` draw (empty
// for other types).
std::vector<LineSlots> assemble_lines(PrimitiveType type, size_t slot_count);
// Primitive assembly of a `points` draw: every slot (empty for other types).
std::vector<uint32_t> assemble_points(PrimitiveType type, size_t slot_count);

// Clipping planes in clip space, each a distance d(v) with d >= 0 inside:
// w >= kMinClipW, near (z >= -w), far (z <= w), then the guard band's
// left, right, bottom, top.
constexpr int kClipPlaneCount = 7;
constexpr float kMinClipW = 1.0f / 4294967296.0f;  // 2^-32: keeps 1/w finite
struct GuardBand {
  float left, right, bottom, top;  // x >= -left*w, x <= right*w, ...
};
// The guard band of a viewport (spec section 4): window x and y stay within
// +-kGuardBandPixels. guard_band_for(W, H) is the whole W x H target's.
GuardBand guard_band_for(const PixelRect& viewport);
GuardBand guard_band_for(int width, int height);
float clip_distance(int plane, const glm::vec4& clip, const GuardBand& gb);

// Sutherland-Hodgman clip of a triangle against every plane; returns the
// clipped convex polygon (empty when nothing is left). Vertices are unchanged
// when all of them are inside every plane. A cut's colour is perspective-
// correct, or linear in window space with screen interpolation (section 4).
std::vector<ShadedVertex> clip_triangle(const std::array<ShadedVertex, 3>& tri, const GuardBand& gb,
                                        Interpolation interpolation = Interpolation::perspective);

// The same clip for polygon mode (spec section 4d): every polygon vertex also
// carries an edge flag, whether the polygon edge starting at it lies on an
// edge of the original triangle.
struct FlaggedPolygon {
  std::vector<ShadedVertex> v;
  std::vector<bool> edge_flag;  // one per vertex
};
FlaggedPolygon clip_triangle_with_edge_flags(
    const std::array<ShadedVertex, 3>& tri, const GuardBand& gb,
    Interpolation interpolation = Interpolation::perspective);

// Line clipping (spec section 4b).
enum class LineClip : uint8_t {
  accepted,  // inside every plane, unchanged
  clipped,   // cut, a part kept
  rejected,  // clipped away
};
struct ClippedLine {
  LineClip result = LineClip::rejected;
  std::array<ShadedVertex, 2> v;  // valid unless rejected
};
ClippedLine clip_line(const std::array<ShadedVertex, 2>& line, const GuardBand& gb,
                      Interpolation interpolation = Interpolation::perspective);

// Whether a point's vertex lies in the view volume (spec section 4c).
bool point_in_view_volume(const glm::vec4& clip);

// A vertex in window space, snapped.
struct WindowVertex {
  Subpixel x = 0, y = 0;            // 1/256 pixel
  float z = 0.0f;                   // window depth, [0, 1] inside the frustum
  float inv_w = 0.0f;               // varying weight: 1 / w_clip (screen interpolation: 1)
  glm::vec4 color_over_w{0.0f};     // colour * inv_w, for perspective correction
  glm::vec3 normal_over_w{0.0f};    // Phong: normal * inv_w
  glm::vec3 eye_over_w{0.0f};       // Phong: eye position * inv_w
  glm::vec2 texcoord_over_w{0.0f};  // textured: (s, t) * inv_w
};
// The viewport transform's parameters (spec section 5): the viewport in
// render-target pixels and the depth range.
struct ViewportTransform {
  PixelRect rect;
  float near = 0.0f, far = 1.0f;
};
WindowVertex to_window(const ShadedVertex& v, const ViewportTransform& vp,
                       Interpolation interpolation = Interpolation::perspective);
// The whole width x height target, depth range [0, 1].
WindowVertex to_window(const ShadedVertex& v, int width, int height,
                       Interpolation interpolation = Interpolation::perspective);
// The window x and y of a vertex before snapping (spec section 5).
glm::vec2 window_xy(const ShadedVertex& v, const PixelRect& viewport);
glm::vec2 window_xy(const ShadedVertex& v, int width, int height);

// Twice the signed area in subpixel^2: > 0 counter-clockwise (y up).
EdgeValue signed_area2(const WindowVertex& a, const WindowVertex& b, const WindowVertex& c);
// Edge function of edge a -> b at subpixel point (px, py).
EdgeValue edge_function(const WindowVertex& a, const WindowVertex& b, Subpixel px, Subpixel py);
// Fill rule: whether pixel centres exactly on edge a -> b (of a CCW triangle)
// belong to the triangle: left edges and bottom horizontal edges.
bool edge_owns_boundary(const WindowVertex& a, const WindowVertex& b);

// Sum of the fan's area2 values of a polygon (p0, p_i, p_i+1): its facing
// and degeneracy in polygon mode (spec section 4d).
EdgeValue polygon_area2(const std::vector<WindowVertex>& poly);

// Lines (spec section 8b). A pixel, as a fragment position.
struct Pixel {
  int x = 0, y = 0;
  bool operator==(const Pixel& o) const { return x == o.x && y == o.y; }
  bool operator<(const Pixel& o) const { return y != o.y ? y < o.y : x < o.x; }
};
// Whether a line counts as x-major: |dx| >= |dy| (a 45-degree line does).
bool line_is_x_major(int64_t dx, int64_t dy);
// Width in pixels: max(1, round(width)), rounding half away from zero.
int line_width_pixels(float line_width);
// The diamond-exit rule by its definition, for one pixel: whether the
// segment A'B' (A and B in subpixels, both moved by -(eps, eps^2)) meets the
// pixel's open diamond and B' is not inside it. Exact integer arithmetic.
bool diamond_exit_covers(int64_t ax, int64_t ay, int64_t bx, int64_t by, int x, int y);
// Every fragment of a diamond-exit line of width w (pixels), inside the
// rectangle [0, width) x [0, height), in no particular order.
std::vector<Pixel> diamond_exit_pixels(int64_t ax, int64_t ay, int64_t bx, int64_t by, int w,
                                       int width, int height);
// Every fragment of a Bresenham line of width w inside [0, width) x [0, height).
std::vector<Pixel> bresenham_pixels(int64_t ax, int64_t ay, int64_t bx, int64_t by, bool draw_first,
                                    bool draw_last, int w, int width, int height);

// Points (spec section 8c): the covered square [x0, x0 + side) x [y0, y0 +
// side) in subpixels, before the framebuffer bounds it.
struct PointSquare {
  int64_t x0 = 0, y0 = 0, side = 0;
};
PointSquare point_square(float x_w, float y_w, float point_size);
std::vector<Pixel> point_pixels(const PointSquare& sq, int width, int height);

// Antialiasing (spec section 14). A multisampled line's rectangle: the
// corners P0..P3 (counter-clockwise, subpixels) of the segment A B (snapped,
// A != B) widened by w pixels.
struct LineRectangle {
  std::array<int64_t, 4> x{}, y{};
};
LineRectangle line_rectangle(int64_t ax, int64_t ay, int64_t bx, int64_t by, float w);
// The frame written out: the box filter of a render target's samples over
// k x k pixels (colour), sample 0 of the block's lower-left pixel (depth).
Framebuffer resolve(const Framebuffer& target, unsigned k);

// The pipeline's counters (hw/pipeline_counts.h), which the cycle model keeps too.
using Stats = PipelineCounts;

struct Result {
  Framebuffer framebuffer;  // resolved: the scene's width x height, one sample
  // Per render-target pixel (the framebuffer's pixels unless supersampled),
  // the id of the primitive that last wrote a colour sample of it (assembled
  // primitives of every kind numbered from 0 in API order across draws), or -1.
  std::vector<int64_t> last_writer;
  Stats stats;
};

struct RenderOptions {
  // Keep Result::last_writer (8 bytes a render-target pixel). Only comparisons
  // with the cycle model read it (`gpusim run --check`, the tests); `gpusim
  // golden` and `gpusim replay` leave it empty. Frames and stats are the same
  // either way.
  bool record_last_writer = true;
};

// Render the scene: clear, then every draw and clear of the draw list in
// order, then resolve. A draw's vertices are shaded when its primitives first
// use them, through a direct-mapped cache of at most kShadedVertexCache
// entries, not into an array per position: shade_vertex depends on the vertex
// alone, so a vertex shaded again is the same bits.
Result render(const Scene& scene, const RenderOptions& options = {});
constexpr uint32_t kShadedVertexCache = 1u << 16;  // entries of 64 + 8 bytes

}  // namespace gpusim::golden
