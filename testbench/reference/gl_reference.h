// The reference renderer: an independent OpenGL implementation (Mesa's
// llvmpipe, through EGL's surfaceless platform) renders a scene so that the
// golden model can be checked against it (docs/validation.md).
//
// Division of labour. The vertex stage is the spec's own (golden::shade_vertex:
// transform and lighting); OpenGL does everything after it: primitive
// assembly, clipping, rasterization and the fill rule, attribute and depth
// interpolation, texture sampling and the texture environment, polygon
// offset, the depth test, blending, colour masks and the conversions to the
// buffer formats.
//
// Window coordinates. The spec computes each vertex's window position in
// float and snaps it to 1/256 pixel; any other float evaluation of the same
// divide and viewport transform (llvmpipe's) rounds differently once in a
// while, and a vertex one subpixel off changes coverage. So a triangle the
// spec does not clip is handed to OpenGL already in window space: the vertex
// is (x_ndc, y_ndc, z_w, 1) where x_ndc = (X/256 - tx) / (V/2) for the
// spec's snapped X, with V a power of two (the viewport's side, 16384 for
// llvmpipe) and tx an integer. Every one of these operations is exact in
// binary32, and so is llvmpipe's x_ndc * (V/2) + tx, so OpenGL snaps exactly
// the spec's X. The viewport is V x V pixels placed so that window (0, 0) is
// the framebuffer's lower left corner: llvmpipe clips x and y to the
// viewport (it has no guard band when a depth buffer is bound), and this
// viewport reaches V/2 pixels beyond the framebuffer on every side, so no
// such clipping reaches a visible pixel unless a vertex lies farther out.
// Depth uses glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE) so window z is the
// spec's z_w unchanged, with GL_DEPTH_CLAMP on (no near/far clipping for
// these triangles, which the spec does not clip either; fragment depth is
// clamped to [0, 1] like the spec's). With w = 1 OpenGL's own perspective
// correction does nothing, so a Gouraud colour is passed as the spec's
// colour / w and 1 / w in `noperspective` varyings and divided per fragment,
// which is perspective-correct interpolation. Screen interpolation
// (`state.interpolation`, section 9) sends the colour itself and 1 in those
// varyings, in window space and in clip space alike, so OpenGL's clipper and
// rasterizer treat it as a `noperspective` varying. glProvokingVertex follows
// `state.provoking_vertex`; a draw handed over triangle by triangle has each
// triangle's vertices rotated so that GL_TRIANGLES provokes the spec's vertex.
//
// Lines take the same two routes: a line the spec does not clip (section 4b)
// goes over in window space with its snapped end points, a clipped one in
// clip space. Points differ: the spec's point rule (section 8c) rounds the
// unsnapped float x_w itself, so a point the spec keeps goes over through a
// second V x V viewport whose centre is window (0, 0), where the viewport
// transform is a multiplication by V/2 and any float x_w passes exactly; a
// point the spec discards goes over in plain clip space through the scene's
// own W x H viewport, so that OpenGL's clipper has to discard it too.
// Viewport, depth range and scissor (spec sections 5 and 8d). The window
// coordinates above are the spec's, so they already hold the draw's viewport
// offset and scale and its depth range (z_w); such batches draw with
// glDepthRange(0, 1). Clip-space batches (below) are rescaled for the
// draw's own viewport and drawn with glDepthRange(near, far), so OpenGL's
// viewport transform applies the depth range; points the spec discards go
// through glViewport(the draw's viewport). Since OpenGL only clips to the
// V x V viewport, the spec's draw rectangle (framebuffer, viewport and
// scissor intersected) becomes one glScissor rectangle per draw (off when it
// is the whole framebuffer), a per-pixel test as the spec's. The clear
// always runs with the scissor test off: clears are whole-frame.
// Triangles in polygon mode line or point are handed over like filled ones,
// and glPolygonMode has OpenGL cull them and draw their edges or vertices.
// Bresenham lines have no OpenGL equivalent: such scenes are refused
// (NotRenderable), never rendered some other way.
//
// Textured draws (spec section 9c). Each scene texture is uploaded once per
// render as a texture object holding every level the scene gives it (level
// 0 alone without mipmaps; GL_TEXTURE_MAX_LEVEL is its last level, so it is
// complete either way), each level as the loader made it (given or
// generated: OpenGL does not generate any), rows from t = 0 as stored, with
// its wrap modes, minification filter (all six, mipmapped ones included),
// magnification filter, GL_TEXTURE_LOD_BIAS, GL_TEXTURE_MIN_LOD and
// GL_TEXTURE_MAX_LOD: llvmpipe computes the level of detail from its own
// derivatives of the interpolated coordinate over each 2x2 quad. A core
// profile has no ALPHA, LUMINANCE or INTENSITY, so those are R8 or RG8 with
// a texture swizzle giving GL's expansion; RGB565 and RGBA4444 take their
// stored 16-bit words as UNSIGNED_SHORT_5_6_5 and _4_4_4_4. The texture
// coordinate goes the colour's way: (s, t)/w and 1/w in noperspective
// varyings for window-space vertices, divided per fragment; (s, t) itself
// for clip-space ones (OpenGL's perspective correction, or noperspective
// with screen interpolation); a point's (s, t) constant over the point (no
// point sprites). It is interpolated whatever the shading, flat included.
// The fragment shader samples with texture() and applies GL 1.5's texture
// environment (tables 3.22 and 3.23) by the texture's base format to the
// clamped colour; untextured draws use a program without any of it.
//
// A triangle the spec clips (crossing near, far, w = 0, or the guard band) is
// handed to OpenGL in homogeneous clip coordinates, rescaled so that the
// divide and viewport give the spec's window coordinates up to rounding, with
// depth clamp off: OpenGL clips it with its own algorithm and interpolates
// colours with its own perspective correction. Coverage along such cut edges
// can differ by rounding, and is reported separately.
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "hw/framebuffer.h"
#include "testbench/scene/scene.h"

namespace gpusim::reference {

// No usable OpenGL (EGL missing, no llvmpipe, a GL error): what() says why.
class ReferenceError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A scene the reference cannot render faithfully (line_rasterization
// "bresenham": OpenGL only has the diamond-exit rule; framebuffer.samples
// other than 1 and 4, the only counts llvmpipe multisamples with; samples 4
// together with supersample > 1; a texture with wrap "clamp", which a core
// profile lacks). Nothing is drawn. Mipmap filters are rendered.
class NotRenderable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// What happened to the scene's triangles, lines and points on the way into
// OpenGL.
struct ReferenceStats {
  uint64_t triangles = 0;          // assembled (spec section 3)
  uint64_t triangles_invalid = 0;  // out-of-range index or non-finite position: not drawn
  uint64_t triangles_exact = 0;    // handed over in window space (spec does not clip them)
  uint64_t triangles_clipped = 0;  // handed over in clip space: OpenGL clips them
  // Exact triangles with a vertex outside OpenGL's viewport: llvmpipe clips
  // them at the viewport edge, V/2 pixels beyond the framebuffer.
  uint64_t triangles_beyond_viewport = 0;
  uint64_t lines = 0;                  // assembled (spec section 3)
  uint64_t lines_invalid = 0;          // not drawn
  uint64_t lines_exact = 0;            // handed over in window space (spec does not clip them)
  uint64_t lines_clipped = 0;          // handed over in clip space: OpenGL clips them
  uint64_t lines_beyond_viewport = 0;  // exact, with an end outside OpenGL's viewport
  uint64_t points = 0;
  uint64_t points_invalid = 0;
  uint64_t points_exact = 0;      // kept by the spec: in window space (unsnapped x_w, y_w)
  uint64_t points_discarded = 0;  // discarded by the spec: in clip space, OpenGL must drop them
  uint64_t unfilled_draws = 0;    // triangle draws in polygon mode line or point
  uint64_t native_draws = 0;      // draws submitted with their own primitive type and indices
  uint64_t expanded_draws = 0;    // draws submitted primitive by primitive (GL_TRIANGLES, GL_LINES)
};

struct ReferenceResult {
  Framebuffer framebuffer;
  ReferenceStats stats;
  // Wall-clock times (steady_clock), in seconds. prepare_seconds: the spec's
  // vertex stage (golden::shade_vertex) on the CPU, the triangles'
  // classification and the upload of the scene's textures and of every draw
  // call's vertices and indices into buffer objects, up to glFinish().
  // render_seconds, one per repetition: from the clear through every draw
  // call to glFinish() returning — llvmpipe's vertex fetch and (pass-through) vertex shader,
  // clipping, setup, binning, rasterization, fragment shading, depth test,
  // blending. Neither covers creating the context, loading the scene,
  // allocating the framebuffer or reading it back.
  double prepare_seconds = 0.0;
  std::vector<double> render_seconds;
};

// One EGL display and OpenGL context; several renders per instance are fine.
class GlReference {
 public:
  // Creates the context (LIBGL_ALWAYS_SOFTWARE=1, GALLIUM_DRIVER=llvmpipe);
  // throws ReferenceError unless GL_RENDERER names llvmpipe.
  GlReference();
  ~GlReference();
  GlReference(const GlReference&) = delete;
  GlReference& operator=(const GlReference&) = delete;

  // Render the scene: clear, then every draw in order, and read back colour
  // and depth in the scene's formats. Multisampled scenes (4 samples) are
  // drawn into a multisampled framebuffer with GL_MULTISAMPLE on and resolved
  // by glBlitFramebuffer (colour: llvmpipe's box filter; depth: sample 0 of
  // each pixel); supersampled ones (single-sampled) at k*width x k*height with
  // line widths and point sizes times k, then box-filtered on the CPU as spec
  // section 14 says. Throws NotRenderable for a scene with
  // Bresenham lines or sample counts llvmpipe cannot give (see NotRenderable). With repeat > 1 the
  // frame (clear and draws, from the same uploaded buffers) is drawn that many times, each timed;
  // the result is the same each time. Throws ReferenceError on a GL error.
  ReferenceResult render(const Scene& scene, int repeat = 1);

  std::string renderer() const;  // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
  std::string version() const;   // GL_VERSION, e.g. "4.5 (Core Profile) Mesa 22.3.6"
  int viewport_side() const;     // V, the side of the viewport used for exact triangles

 private:
  struct Impl;
  std::unique_ptr<Impl> m_impl;
};

}  // namespace gpusim::reference
