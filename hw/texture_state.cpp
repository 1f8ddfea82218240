#include "hw/texture_state.h"

namespace gpusim {
namespace {

// An n-bit channel widened to 8 bits by replicating its high bits.
uint8_t widen(unsigned v, unsigned bits) {
  return static_cast<uint8_t>(v << (8 - bits) | v >> (2 * bits - 8));
}

}  // namespace

unsigned texel_bytes(TextureFormat f) {
  switch (f) {
    case TextureFormat::alpha8:
    case TextureFormat::luminance8:
    case TextureFormat::intensity8:
      return 1;
    case TextureFormat::luminance_alpha8:
    case TextureFormat::rgb565:
    case TextureFormat::rgba4444:
      return 2;
    case TextureFormat::rgb8:
      return 3;
    case TextureFormat::rgba8:
      return 4;
  }
  return 4;
}

BaseFormat base_format(TextureFormat f) {
  switch (f) {
    case TextureFormat::alpha8:
      return BaseFormat::alpha;
    case TextureFormat::luminance8:
      return BaseFormat::luminance;
    case TextureFormat::luminance_alpha8:
      return BaseFormat::luminance_alpha;
    case TextureFormat::intensity8:
      return BaseFormat::intensity;
    case TextureFormat::rgb8:
    case TextureFormat::rgb565:
      return BaseFormat::rgb;
    case TextureFormat::rgba8:
    case TextureFormat::rgba4444:
      return BaseFormat::rgba;
  }
  return BaseFormat::rgba;
}

Texel expand_texel(TextureFormat f, const uint8_t* p) {
  switch (f) {
    case TextureFormat::alpha8:
      return {0, 0, 0, p[0]};
    case TextureFormat::luminance8:
      return {p[0], p[0], p[0], 255};
    case TextureFormat::luminance_alpha8:
      return {p[0], p[0], p[0], p[1]};
    case TextureFormat::intensity8:
      return {p[0], p[0], p[0], p[0]};
    case TextureFormat::rgb8:
      return {p[0], p[1], p[2], 255};
    case TextureFormat::rgba8:
      return {p[0], p[1], p[2], p[3]};
    case TextureFormat::rgb565: {
      // GL's UNSIGNED_SHORT_5_6_5, little endian: red in the high 5 bits.
      const unsigned v = p[0] | unsigned{p[1]} << 8;
      return {widen(v >> 11, 5), widen(v >> 5 & 63, 6), widen(v & 31, 5), 255};
    }
    case TextureFormat::rgba4444: {
      // GL's UNSIGNED_SHORT_4_4_4_4: red in the high 4 bits, alpha in the low.
      const unsigned v = p[0] | unsigned{p[1]} << 8;
      return {widen(v >> 12, 4), widen(v >> 8 & 15, 4), widen(v >> 4 & 15, 4), widen(v & 15, 4)};
    }
  }
  return {0, 0, 0, 0};
}

std::ostream& operator<<(std::ostream& os, const TextureSampler& s) {
  return os << "{wrap=" << to_string(s.wrap_s) << "," << to_string(s.wrap_t)
            << " min=" << to_string(s.min_filter) << " mag=" << to_string(s.mag_filter)
            << " lod_bias=" << s.lod_bias << " lod=[" << s.min_lod << "," << s.max_lod << "]}";
}

}  // namespace gpusim
