#include "hw/hierarchical_z.h"

#include <algorithm>
#include <cmath>

namespace gpusim {

std::ostream& operator<<(std::ostream& os, const HzRange& r) {
  return os << "[" << r.min << ", " << r.max << "]";
}

std::ostream& operator<<(std::ostream& os, const HzUpdate& u) {
  return os << "HzUpdate{tile " << u.tile << " seq " << u.seq << " epoch " << u.epoch << " "
            << u.range << " sent " << u.sent << "}";
}

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
// >= 0, bias_k in {0, 1}, for the three edges, and E0 + E1 + E2 = area2, so
// its barycentrics b_k = E_k / area2 are in [0, 1] and b1 + b2 <= 1. Exactly,
// z* = z0 + b1 (z1 - z0) + b2 (z2 - z0) lies in [zmin, zmax] of the vertices.
// Each float operation has relative error <= u = 2^-24 (plus at most 2^-150
// absolute where a result is denormal); a term b_k dz_k passes through six
// (f_k, dz_k, the product, the sum, fl(area2), the division), so the quotient
// differs from the exact one by <= 6.01 u (|dz1| + |dz2|) <= 12.02 u M, M =
// max |z_k| (|z_k - z0| <= 2M), and the final sum adds u (M + 12.02 u M):
// |z - z*| <= 13.1 u M < 2^-20 M, plus < 2^-145 absolute. The margin taken is
// 2^-19 M + 2^-140. Polygon offset adds o in float: z + o is within
// [lo + o, hi + o] exactly and its rounding moves it by <= u |z + o|, which
// the second margin, 2^-23 max(|lo + o|, |hi + o|) + 2^-140, covers. Rounding
// the double bounds outwards to floats keeps them bounds; clamp01 and the
// encodings (unorm: round to nearest of a non-negative multiple; float32: the
// bits of a float in [0, 1], -0 clamped to +0) are monotonic non-decreasing,
// so the encoded bounds bound every encoded value. Lines and points
// interpolate along their own functions, whose parameters can leave [0, 1]
// at a wide line's corners: no bound is claimed for them (the full range).
HzRange hz_primitive_range(const RasterPrimitive& t, DepthFormat format) {
  if (t.primitive_kind != PrimitiveKind::triangle) return HzRange{};
  const double zmin = std::min({t.z[0], t.z[1], t.z[2]});
  const double zmax = std::max({t.z[0], t.z[1], t.z[2]});
  if (!std::isfinite(zmin) || !std::isfinite(zmax)) return HzRange{};
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
