// Textures from image files (PNG, JPEG, TGA, BMP, EXR and whatever else
// OpenImageIO reads) and from images embedded in mesh files, and the
// mipmap chains the scene format can generate (docs/scene-format.md,
// "textures"). Kept apart from scene_loader.cpp so OpenImageIO's headers
// stay here.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "testbench/scene/scene.h"

namespace gpusim {

// An image that cannot be a texture: what() is one line naming the problem
// (the caller names the file).
class TextureImageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The format a texture read from an image of `channels` channels takes when
// the scene does not say: luminance8, luminance_alpha8, rgb8 or rgba8.
TextureFormat natural_format(int channels);

// Level 0 of a texture read from an image file, converted to `format`
// (rows from the bottom: the file's last row is t = 0), or to
// natural_format() of its channels when `format` is empty. Throws
// TextureImageError when it cannot be read or is larger than
// kMaxTextureSize on a side.
TextureImage read_image_file(const std::string& path, std::optional<TextureFormat> format,
                             TextureFormat* chosen);
// The same for an encoded image in memory (a glb's embedded PNG or JPEG);
// `extension` ("png", "jpg") tells the decoder what it is.
TextureImage decode_image(const void* data, size_t size, const std::string& extension,
                          std::optional<TextureFormat> format, TextureFormat* chosen);

// Appends the rest of the mipmap chain down to 1 x 1 to `texture` (which
// holds level 0): each level half the last (at least 1), each texel the
// mean of the 2 x 2 (2 x 1, 1 x 2) texels it covers per stored channel,
// rounded half up (glGenerateMipmap's box filter).
void generate_mipmaps(Texture& texture);

// A texel's channel values as a scene file writes them (rgb565: r 0..31, g
// 0..63, b 0..31; rgba4444 0..15 each; else 0..255), stored in `format`, and
// read back; channel_count and channel_bits say how many and how wide.
unsigned channel_count(TextureFormat format);
unsigned channel_bits(TextureFormat format, unsigned channel);
void store_texel(TextureFormat format, const std::array<unsigned, 4>& value,
                 std::vector<uint8_t>& out);
std::array<unsigned, 4> load_texel(TextureFormat format, const uint8_t* stored);

}  // namespace gpusim
