// Colour and depth buffer storage formats: how a fragment's float value becomes
// the bits in memory and back. Shared by the golden model and the ROP/depth
// stages, since both must store identical bits.
#pragma once

#include <Imath/half.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "hw/render_state.h"

namespace gpusim {

// One colour channel as stored: an unorm8 value (0..255) for rgba8, the bits
// of an IEEE half for rgba16f.
using ColorChannel = uint16_t;
// One depth value as stored: unorm16 / unorm24 integers, or float32 bits.
using DepthValue = uint32_t;

inline float clamp01(float v) {
  // NaN maps to 0 so that a stored value is always defined.
  if (!(v > 0.0f)) return 0.0f;
  return v < 1.0f ? v : 1.0f;
}

inline float float_from_bits(uint32_t bits) {
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}
inline uint32_t bits_from_float(float f) {
  uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}

// rgba8: round to nearest (ties to even) of clamp(c) * 255 in float.
inline ColorChannel encode_unorm8(float c) {
  return static_cast<ColorChannel>(std::nearbyint(clamp01(c) * 255.0f));
}
inline float decode_unorm8(ColorChannel v) {
  return static_cast<float>(v) / 255.0f;
}

// rgba16f: IEEE binary16, round to nearest even (Imath's float -> half).
inline ColorChannel encode_half(float c) {
  return Imath::half(c).bits();
}
inline float decode_half(ColorChannel bits) {
  Imath::half h;
  h.setBits(bits);
  return static_cast<float>(h);
}

inline ColorChannel encode_color(ColorFormat f, float c) {
  return f == ColorFormat::rgba8 ? encode_unorm8(c) : encode_half(c);
}
inline float decode_color(ColorFormat f, ColorChannel v) {
  return f == ColorFormat::rgba8 ? decode_unorm8(v) : decode_half(v);
}

inline int depth_bits(DepthFormat f) {
  switch (f) {
    case DepthFormat::unorm16:
      return 16;
    case DepthFormat::unorm24:
      return 24;
    case DepthFormat::float32:
      return 32;
  }
  return 0;
}

// Largest stored value of a unorm depth format, 2^n - 1.
inline double unorm_depth_max(DepthFormat f) {
  return static_cast<double>((uint32_t{1} << depth_bits(f)) - 1u);
}

// z is the window-space depth after polygon offset. unorm formats clamp to
// [0, 1] and round to nearest (ties to even) in double: z * (2^24 - 1) is exact
// in double, so the only rounding is the one to an integer. float32 clamps to
// [0, 1] too (GL clamps fragment depth to the depth range) and stores the bits.
inline DepthValue encode_depth(DepthFormat f, float z) {
  const float c = clamp01(z);
  if (f == DepthFormat::float32) return bits_from_float(c);
  return static_cast<DepthValue>(std::nearbyint(static_cast<double>(c) * unorm_depth_max(f)));
}
inline float decode_depth(DepthFormat f, DepthValue v) {
  if (f == DepthFormat::float32) return float_from_bits(v);
  return static_cast<float>(static_cast<double>(v) / unorm_depth_max(f));
}

// Depth comparison of a fragment's stored-format value against the buffer's:
// unsigned integers for unorm formats, floats for float32 (both in [0, 1], so
// comparing the bit patterns as unsigned integers orders them the same way).
inline bool depth_compare(CompareFunc func, DepthValue fragment, DepthValue stored) {
  switch (func) {
    case CompareFunc::never:
      return false;
    case CompareFunc::less:
      return fragment < stored;
    case CompareFunc::equal:
      return fragment == stored;
    case CompareFunc::lequal:
      return fragment <= stored;
    case CompareFunc::greater:
      return fragment > stored;
    case CompareFunc::notequal:
      return fragment != stored;
    case CompareFunc::gequal:
      return fragment >= stored;
    case CompareFunc::always:
      return true;
  }
  return false;
}

// Polygon offset's minimum resolvable difference r (GL 4.6, 14.6.5): one step
// of a unorm buffer, 1 / (2^n - 1); for float32, 2^(e - 23) where e is the
// exponent of the largest |z| of the triangle's vertices (GL's rule for float
// depth buffers), with e clamped below so r never underflows to 0.
inline float min_resolvable_depth(DepthFormat f, float max_abs_z) {
  if (f != DepthFormat::float32) return static_cast<float>(1.0 / unorm_depth_max(f));
  // Zero has no exponent: take the smallest, so r is the smallest denormal.
  if (!(max_abs_z > 0.0f)) return std::ldexp(1.0f, -149);
  int e = 0;
  std::frexp(max_abs_z, &e);  // max_abs_z = m * 2^e, m in [0.5, 1)
  return std::ldexp(1.0f, std::max(e - 1, -126) - 23);
}

}  // namespace gpusim
