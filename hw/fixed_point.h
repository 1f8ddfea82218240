// Number formats shared by the golden model and the hardware stages, with the
// bounds that prove each width suffices. Only formats and spec constants live
// here; each model implements its own algorithms on top of them.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

namespace gpusim {

// Window coordinates are snapped to signed fixed point with 8 fractional bits
// (1/256 pixel), the precision of GL implementations such as llvmpipe.
constexpr int kSubpixelBits = 8;
constexpr int32_t kSubpixelOne = 1 << kSubpixelBits;  // one pixel
constexpr int32_t kSubpixelHalf = kSubpixelOne / 2;   // pixel centre offset

// Largest framebuffer side. Keeps pixel indices in 14 bits.
constexpr int kMaxFramebufferSide = 8192;
static_assert(kMaxFramebufferSide <= (1 << 14), "pixel indices are 14 bits");

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
//
// Lines (docs/pipeline-spec.md, sections 8b and 9) use the same type:
// L2 = dx^2 + dy^2 < 2^51, T = (px - Xa) dx + (py - Ya) dy has |T| < 2^51
// for every point within 2^25 subpixels of the end points, so
// E0 = L2 - T, E1 = T and their equations' constants (< 2^51) fit with room;
// a band edge, s D +- 128 w |dM| with w <= 255 (kMaxLineWidth, hw/render_state.h), adds less
// than 2^15 * 2^25 = 2^40 to a value below 2^51.
using EdgeValue = int64_t;
using Subpixel = int32_t;

// Snapped coordinates saturate at +-2^24 subpixels (2^16 pixels, twice the
// guard band), so the bounds above hold for every input.
constexpr int32_t kSnapLimit = 1 << 24;

// The bit budgets above, checked by the compiler (llvmpipe's MAX_FIXED_LENGTH
// pattern): a change of one constant that breaks a proof fails the build.
namespace bit_budget {
// Bits of a value below 2^n, as a constant: log2 of the power of two given.
constexpr int bits_of(int64_t power_of_two) {
  int n = 0;
  while ((int64_t{1} << n) < power_of_two) ++n;
  return n;
}
// The guard band in subpixels fits the snap limit, which a Subpixel holds
// with room for the rounding overshoot of the clipper (7 bits).
constexpr int64_t kGuardBandSubpixels = static_cast<int64_t>(kGuardBandPixels) * kSubpixelOne;
static_assert(kGuardBandSubpixels <= kSnapLimit / 2, "the snap limit is twice the guard band");
static_assert(bits_of(kSnapLimit) + 1 + 7 <= std::numeric_limits<Subpixel>::digits + 1,
              "a snapped coordinate, its sign and 7 bits of overshoot fit a Subpixel");
// A difference of two snapped coordinates is below 2^25; an edge product
// below 2^50; the edge function (two products) below 2^51.
constexpr int kDifferenceBits = bits_of(kSnapLimit) + 1;
constexpr int kEdgeBits = 2 * kDifferenceBits + 1;
static_assert(kEdgeBits == 51, "E < 2^51 as documented");
// int64 keeps 12 bits of headroom over it, for stepping E incrementally
// across the guard band.
static_assert(kEdgeBits + 12 <= std::numeric_limits<EdgeValue>::digits,
              "the edge function fits an EdgeValue with 12 bits of headroom");
// A line's band edge adds s D +- 128 w |dM| with w < 2^8 (kMaxLineWidth): less
// than 2^15 * 2^25 = 2^40, far below the headroom.
static_assert(15 + kDifferenceBits < kEdgeBits, "a line's band term is below E's bound");
// Pixel centres of the largest framebuffer are far inside the snap limit.
static_assert(int64_t{kMaxFramebufferSide} * kSubpixelOne + kSubpixelHalf < kSnapLimit,
              "pixel centres are representable snapped coordinates");
}  // namespace bit_budget

// The widths packets carry these values in (hw/packets.h lists each field's),
// from the bounds above, each with its sign where it has one.
namespace field_bits {
using bit_budget::bits_of;
// A pixel index or a framebuffer side, 0..kMaxFramebufferSide.
constexpr unsigned kPixel = bits_of(kMaxFramebufferSide) + 1;
static_assert(kPixel == 14, "pixel indices are 14 bits");
// A snapped coordinate, -kSnapLimit..kSnapLimit: 25 bits and a sign.
constexpr unsigned kSubpixel = bits_of(kSnapLimit) + 2;
// The pixel of a snapped coordinate (floor(X / 256)): 17 bits and a sign.
constexpr unsigned kSnappedPixel = kSubpixel - kSubpixelBits;
// An edge coefficient a or b, a difference of two snapped coordinates.
constexpr unsigned kEdgeCoefficient = bit_budget::kDifferenceBits + 1;
// An edge function's value or constant term: below 2^51 for a triangle, and
// a line's band term (< 2^40) keeps it below 2^52.
constexpr unsigned kEdgeValue = bit_budget::kEdgeBits + 2;
// Twice a triangle's area, or a line's squared length: positive, below 2^51.
constexpr unsigned kArea2 = bit_budget::kEdgeBits;
static_assert(kEdgeValue <= 64 && kSubpixel <= 32, "the model's integer types hold them");
}  // namespace field_bits

// Round a window coordinate to the subpixel grid: to nearest, ties to even.
// x * 256 is exact in binary floating point, so the only rounding is the one
// to an integer. After clipping |x| is within the guard band, except that
// float rounding in the clipper on extreme inputs (coordinates near the float
// range, or a cut next to w = 0 on large coordinates) can land a vertex far
// outside, or at infinity or NaN: such values saturate at +-kSnapLimit, and
// NaN snaps to 0 (docs/pipeline-spec.md, section 6), rather than overflow the
// conversion to int (undefined behaviour) and the edge functions after it.
inline Subpixel snap_to_subpixel(float x) {
  const float v = x * static_cast<float>(kSubpixelOne);
  if (v != v) return 0;
  if (v >= static_cast<float>(kSnapLimit)) return kSnapLimit;
  if (v <= -static_cast<float>(kSnapLimit)) return -kSnapLimit;
  return static_cast<Subpixel>(std::nearbyint(v));
}

// Pixel (ix, iy) has its centre at subpixel (ix * 256 + 128, iy * 256 + 128).
// Round to an integer, half away from zero (C's lround, util_iround in
// Mesa), saturating as snap_to_subpixel does: |v| >= kSnapLimit gives
// +-kSnapLimit and NaN gives 0. The rounding of a point's square
// (docs/pipeline-spec.md, section 8c), whose corner comes from an unsnapped
// window coordinate: a polygon-mode vertex on extreme inputs can be anywhere.
inline int32_t round_half_away(float v) {
  if (v != v) return 0;
  if (v >= static_cast<float>(kSnapLimit)) return kSnapLimit;
  if (v <= -static_cast<float>(kSnapLimit)) return -kSnapLimit;
  return static_cast<int32_t>(std::lround(v));
}

inline Subpixel pixel_center(int i) {
  return i * kSubpixelOne + kSubpixelHalf;
}

// Floor division by 256 for subpixel -> pixel conversions of negative values.
inline int32_t floor_div_subpixel(int64_t v) {
  return static_cast<int32_t>(v >= 0 ? v >> kSubpixelBits
                                     : -((-v + kSubpixelOne - 1) >> kSubpixelBits));
}

}  // namespace gpusim
