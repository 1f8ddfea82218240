#include "hw/hierarchical_z.h"

#include <algorithm>
#include <cmath>

namespace gpusim {

namespace {

// The largest float <= x and the smallest float >= x (x finite, in float range).
float float_below(double x) {
  const float f = static_cast<float>(x);
  return static_cast<double>(f) > x ? std::nextafter(f, -HUGE_VALF) : f;
}
float float_above(double x) {
  const float f = static_cast<float>(x);
  return static_cast<double>(f) < x ? std::nextafter(f, HUGE_VALF) : f;
}

}  // namespace

// Proof that the range bounds every stored value. The depth test computes,
// per covered pixel or sample (stages/depth_test.h, spec section 9),
//   z = fl(z0 + fl(fl(fl(f1 * dz1) + fl(f2 * dz2)) / fl(area2)))
// with f_k = fl(E_k), dz_k = fl(z_k - z0). A covered point has E_k - bias_k
// >= 0, bias_k in {0, 1}, for the three edges, and E0 + E1 + E2 = area2 > 0,
// so 0 <= E_k <= area2 < 2^63, its barycentrics b_k = E_k / area2 are in
// [0, 1] and b1 + b2 <= 1. Exactly, z* = z0 + b1 (z1 - z0) + b2 (z2 - z0)
// lies in [zmin, zmax] of the vertices.
// The error analysis needs every z_k finite and no operation overflowing, so
// a triangle that breaks either gets the full range: clipping can give a
// vertex a NaN depth (inf - inf in the interpolation), which the depth test
// carries to z = NaN and clamp01 stores as 0, far outside the other two
// vertices' range (issue #11: each z_k is checked, a NaN does not order in
// min/max). Overflow: |dz_k| <= fl(2M) = 2M, M = max |z_k|, f_k <=
// fl(area2) <= 2^63, so |fl(f_k dz_k)| <= 2^64 M and their sum <= 2^65 M, below
// FLT_MAX for M < 2^62 (the division by fl(area2) >= 1 and the final sum,
// |q| <= 2M (1 + 13 u), stay finite too); beyond, inf - inf gives NaN again.
// Each float operation has relative error <= u = 2^-24 (plus at most 2^-150
// absolute where a result is denormal); a term b_k dz_k passes through six
// (f_k, dz_k, the product, the sum, fl(area2), the division), so the quotient
// differs from the exact one by <= 6.01 u (|dz1| + |dz2|) <= 12.02 u M, and
// the final sum adds u (M + 12.02 u M): |z - z*| <= 13.1 u M < 2^-20 M, plus
// < 2^-145 absolute. The margin taken is 2^-19 M + 2^-140. Polygon offset
// (finite, else the full range) adds o in float: z + o is within
// [lo + o, hi + o] exactly and its rounding moves it by <= u |z + o| (an
// overflow to +-inf clamps like the bound beyond 2), which the second margin,
// 2^-23 max(|lo + o|, |hi + o|) + 2^-140, covers. Rounding
// the double bounds outwards to floats keeps them bounds; clamp01 and the
// encodings (unorm: round to nearest of a non-negative multiple; float32: the
// bits of a float in [0, 1], -0 clamped to +0) are monotonic non-decreasing,
// so the encoded bounds bound every encoded value. Lines and points
// interpolate along their own functions, whose parameters can leave [0, 1]
// at a wide line's corners: no bound is claimed for them (the full range).
HzRange hz_primitive_range(const RasterPrimitive& t, DepthFormat format) {
  if (t.primitive_kind != PrimitiveKind::triangle) return HzRange{};
  for (const float z : t.z) {
    if (!(std::fabs(z) < 0x1p62f)) return HzRange{};  // NaN, inf or overflow possible
  }
  if (t.has_depth_offset && !std::isfinite(t.depth_offset)) return HzRange{};
  const double zmin = std::min({t.z[0], t.z[1], t.z[2]});
  const double zmax = std::max({t.z[0], t.z[1], t.z[2]});
  const double m = std::max(std::fabs(zmin), std::fabs(zmax));
  double lo = zmin - (std::ldexp(m, -19) + std::ldexp(1.0, -140));
  double hi = zmax + (std::ldexp(m, -19) + std::ldexp(1.0, -140));
  if (t.has_depth_offset) {
    lo += t.depth_offset;
    hi += t.depth_offset;
    const double m2 = std::max(std::fabs(lo), std::fabs(hi));
    lo -= std::ldexp(m2, -23) + std::ldexp(1.0, -140);
    hi += std::ldexp(m2, -23) + std::ldexp(1.0, -140);
  }
  // Beyond float range the clamp decides anyway.
  lo = std::clamp(lo, -1.0, 2.0);
  hi = std::clamp(hi, -1.0, 2.0);
  return HzRange{encode_depth(format, float_below(lo)), encode_depth(format, float_above(hi))};
}

}  // namespace gpusim
