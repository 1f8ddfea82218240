// Number formats shared by the golden model and the hardware stages, with the
// bounds that prove each width suffices. Only formats and spec constants live
// here; each model implements its own algorithms on top of them.
#pragma once

#include <cmath>
#include <cstdint>

namespace gpusim {

// Window coordinates are snapped to signed fixed point with 8 fractional bits
// (1/256 pixel), the precision of GL implementations such as llvmpipe.
constexpr int kSubpixelBits = 8;
constexpr int32_t kSubpixelOne = 1 << kSubpixelBits;   // one pixel
constexpr int32_t kSubpixelHalf = kSubpixelOne / 2;    // pixel centre offset

// Largest framebuffer side. Keeps pixel indices in 14 bits.
constexpr int kMaxFramebufferSide = 8192;

// Guard band: after clipping, every window x and y lies in
// [-kGuardBandPixels, +kGuardBandPixels]. Triangles inside it are rasterized
// unclipped (exact coverage); only geometry beyond it is clipped for real.
// 2^15 pixels = 2^23 subpixels, so a snapped coordinate needs 24 bits plus a
// sign; float rounding in clip -> window can exceed the plane by a few ulps,
// which int32 absorbs with 7 bits to spare.
constexpr float kGuardBandPixels = 32768.0f;

// Edge function E(p) = dx * (py - ay) - dy * (px - ax) over snapped
// coordinates. |dx|, |dy|, |px - ax| < 2^25 subpixels (two coordinates of at
// most 2^24 each), so each product is < 2^50 and E < 2^51: int64 holds it
// with 12 bits of headroom, also for a rasterizer that steps E incrementally
// across the guard band.
using EdgeValue = int64_t;
using Subpixel = int32_t;

// Round a window coordinate to the subpixel grid: to nearest, ties to even.
// x * 256 is exact in binary floating point, so the only rounding is the one
// to an integer. The caller guarantees |x| is within the guard band.
inline Subpixel snap_to_subpixel(float x) {
  return static_cast<Subpixel>(std::nearbyint(x * static_cast<float>(kSubpixelOne)));
}

// Pixel (ix, iy) has its centre at subpixel (ix * 256 + 128, iy * 256 + 128).
inline Subpixel pixel_center(int i) { return i * kSubpixelOne + kSubpixelHalf; }

// Floor division by 256 for subpixel -> pixel conversions of negative values.
inline int32_t floor_div_subpixel(int64_t v) {
  return static_cast<int32_t>(v >= 0 ? v >> kSubpixelBits : -((-v + kSubpixelOne - 1) >> kSubpixelBits));
}

}  // namespace gpusim
