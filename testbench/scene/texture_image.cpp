#include "testbench/scene/texture_image.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <memory>

namespace gpusim {
namespace {

// Decoded 8-bit pixels, top row first as image files store them.
struct Pixels {
  int width = 0, height = 0, channels = 0;
  std::vector<uint8_t> data;
};

Pixels read_pixels(const std::string& name, OIIO::Filesystem::IOProxy* proxy) {
  auto in = OIIO::ImageInput::open(name, nullptr, proxy);
  if (!in) {
    std::string why = OIIO::geterror();
    std::replace(why.begin(), why.end(), '\n', ' ');
    throw TextureImageError(why.empty() ? "not an image OpenImageIO reads" : why);
  }
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width < 1 || spec.height < 1 || spec.width > kMaxTextureSize ||
      spec.height > kMaxTextureSize) {
    throw TextureImageError(std::to_string(spec.width) + " x " + std::to_string(spec.height) +
                            " pixels: a texture is 1 to " + std::to_string(kMaxTextureSize) +
                            " texels on a side");
  }
  Pixels p;
  p.width = spec.width;
  p.height = spec.height;
  // Four channels at most: the rest (extra AOVs of an EXR) are not colour.
  p.channels = std::min(spec.nchannels, 4);
  p.data.resize(size_t(p.width) * p.height * p.channels);
  // OpenImageIO converts any pixel type to 8 bits (clamped, rounded).
  if (!in->read_image(0, 0, 0, p.channels, OIIO::TypeDesc::UINT8, p.data.data())) {
    std::string why = in->geterror();
    std::replace(why.begin(), why.end(), '\n', ' ');
    throw TextureImageError("cannot decode it: " + why);
  }
  return p;
}

// GL's reading of an image's channels: 1 luminance, 2 luminance and alpha,
// 3 RGB, 4 RGBA; as r, g, b, a.
std::array<unsigned, 4> rgba_of(const uint8_t* p, int channels) {
  switch (channels) {
    case 1:
      return {p[0], p[0], p[0], 255};
    case 2:
      return {p[0], p[0], p[0], p[1]};
    case 3:
      return {p[0], p[1], p[2], 255};
    default:
      return {p[0], p[1], p[2], p[3]};
  }
}

// An 8-bit value in n bits, rounded to nearest.
unsigned narrow(unsigned v, unsigned bits) {
  const unsigned max = (1u << bits) - 1;
  return (v * max + 127) / 255;
}

TextureImage convert(const Pixels& p, std::optional<TextureFormat> format, TextureFormat* chosen) {
  const TextureFormat f = format.value_or(natural_format(p.channels));
  *chosen = f;
  TextureImage level;
  level.width = p.width;
  level.height = p.height;
  level.texels.reserve(size_t(p.width) * p.height * texel_bytes(f));
  for (int row = p.height - 1; row >= 0; --row) {  // t = 0 is the bottom row
    for (int x = 0; x < p.width; ++x) {
      const std::array<unsigned, 4> c =
          rgba_of(&p.data[(size_t(row) * p.width + x) * p.channels], p.channels);
      std::array<unsigned, 4> v{};
      switch (f) {
        case TextureFormat::alpha8:
          v = {c[3]};
          break;
        case TextureFormat::luminance8:
        case TextureFormat::intensity8:
          v = {c[0]};  // GL takes red as luminance
          break;
        case TextureFormat::luminance_alpha8:
          v = {c[0], c[3]};
          break;
        case TextureFormat::rgb8:
          v = {c[0], c[1], c[2]};
          break;
        case TextureFormat::rgba8:
          v = c;
          break;
        case TextureFormat::rgb565:
          v = {narrow(c[0], 5), narrow(c[1], 6), narrow(c[2], 5)};
          break;
        case TextureFormat::rgba4444:
          v = {narrow(c[0], 4), narrow(c[1], 4), narrow(c[2], 4), narrow(c[3], 4)};
          break;
      }
      store_texel(f, v, level.texels);
    }
  }
  return level;
}

}  // namespace

TextureFormat natural_format(int channels) {
  switch (channels) {
    case 1:
      return TextureFormat::luminance8;
    case 2:
      return TextureFormat::luminance_alpha8;
    case 3:
      return TextureFormat::rgb8;
    default:
      return TextureFormat::rgba8;
  }
}

TextureImage read_image_file(const std::string& path, std::optional<TextureFormat> format,
                             TextureFormat* chosen) {
  return convert(read_pixels(path, nullptr), format, chosen);
}

TextureImage decode_image(const void* data, size_t size, const std::string& extension,
                          std::optional<TextureFormat> format, TextureFormat* chosen) {
  OIIO::Filesystem::IOMemReader reader(data, size);
  return convert(read_pixels("embedded." + extension, &reader), format, chosen);
}

unsigned channel_count(TextureFormat f) {
  switch (f) {
    case TextureFormat::alpha8:
    case TextureFormat::luminance8:
    case TextureFormat::intensity8:
      return 1;
    case TextureFormat::luminance_alpha8:
      return 2;
    case TextureFormat::rgb8:
    case TextureFormat::rgb565:
      return 3;
    case TextureFormat::rgba8:
    case TextureFormat::rgba4444:
      return 4;
  }
  return 4;
}

unsigned channel_bits(TextureFormat f, unsigned channel) {
  if (f == TextureFormat::rgb565) return channel == 1 ? 6 : 5;
  if (f == TextureFormat::rgba4444) return 4;
  return 8;
}

void store_texel(TextureFormat f, const std::array<unsigned, 4>& v, std::vector<uint8_t>& out) {
  if (f == TextureFormat::rgb565 || f == TextureFormat::rgba4444) {
    // GL's packed types, the first channel in the high bits, little endian.
    const unsigned packed = f == TextureFormat::rgb565 ? v[0] << 11 | v[1] << 5 | v[2]
                                                       : v[0] << 12 | v[1] << 8 | v[2] << 4 | v[3];
    out.push_back(static_cast<uint8_t>(packed & 0xff));
    out.push_back(static_cast<uint8_t>(packed >> 8));
    return;
  }
  for (unsigned c = 0; c < channel_count(f); ++c) out.push_back(static_cast<uint8_t>(v[c]));
}

std::array<unsigned, 4> load_texel(TextureFormat f, const uint8_t* p) {
  if (f == TextureFormat::rgb565 || f == TextureFormat::rgba4444) {
    const unsigned v = p[0] | unsigned{p[1]} << 8;
    if (f == TextureFormat::rgb565) return {v >> 11, v >> 5 & 63, v & 31, 0};
    return {v >> 12, v >> 8 & 15, v >> 4 & 15, v & 15};
  }
  std::array<unsigned, 4> out{};
  for (unsigned c = 0; c < channel_count(f); ++c) out[c] = p[c];
  return out;
}

void generate_mipmaps(Texture& t) {
  const unsigned bytes = texel_bytes(t.format);
  while (t.levels.back().width > 1 || t.levels.back().height > 1) {
    const TextureImage& src = t.levels.back();
    TextureImage dst;
    dst.width = std::max(1, src.width / 2);
    dst.height = std::max(1, src.height / 2);
    const int sx = src.width > 1 ? 2 : 1, sy = src.height > 1 ? 2 : 1;
    const unsigned n = static_cast<unsigned>(sx * sy);
    dst.texels.reserve(size_t(dst.width) * dst.height * bytes);
    for (int y = 0; y < dst.height; ++y) {
      for (int x = 0; x < dst.width; ++x) {
        std::array<unsigned, 4> sum{};
        for (int j = 0; j < sy; ++j) {
          for (int i = 0; i < sx; ++i) {
            const size_t at = (size_t(y * sy + j) * src.width + (x * sx + i)) * bytes;
            const std::array<unsigned, 4> v = load_texel(t.format, &src.texels[at]);
            for (int c = 0; c < 4; ++c) sum[c] += v[c];
          }
        }
        for (unsigned& c : sum) c = (c + n / 2) / n;
        store_texel(t.format, sum, dst.texels);
      }
    }
    t.levels.push_back(std::move(dst));  // `src` is not used past here
  }
}

}  // namespace gpusim
