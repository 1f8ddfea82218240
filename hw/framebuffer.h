// The colour and depth buffers as stored bits. Row 0 is the bottom row
// (window y = 0, GL's lower-left origin); image files flip it so pictures are
// upright.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include "hw/pixel_formats.h"

namespace gpusim {

struct Framebuffer {
  int width = 0;
  int height = 0;
  ColorFormat color_format = ColorFormat::rgba8;
  DepthFormat depth_format = DepthFormat::unorm24;
  std::vector<ColorChannel> color;  // 4 channels (R, G, B, A) per pixel
  std::vector<DepthValue> depth;    // 1 per pixel

  Framebuffer() = default;
  Framebuffer(int w, int h, ColorFormat cf, DepthFormat df)
      : width(w),
        height(h),
        color_format(cf),
        depth_format(df),
        color(static_cast<size_t>(w) * h * 4),
        depth(static_cast<size_t>(w) * h) {}

  size_t pixel_index(int x, int y) const { return static_cast<size_t>(y) * width + x; }
  ColorChannel* color_at(int x, int y) { return &color[pixel_index(x, y) * 4]; }
  const ColorChannel* color_at(int x, int y) const { return &color[pixel_index(x, y) * 4]; }

  void clear(const float rgba[4], float z) {
    ColorChannel c[4];
    for (int i = 0; i < 4; ++i) c[i] = encode_color(color_format, rgba[i]);
    for (size_t p = 0; p < depth.size(); ++p) {
      for (int i = 0; i < 4; ++i) color[p * 4 + i] = c[i];
    }
    std::fill(depth.begin(), depth.end(), encode_depth(depth_format, z));
  }

  bool operator==(const Framebuffer& o) const {
    return width == o.width && height == o.height && color_format == o.color_format &&
           depth_format == o.depth_format && color == o.color && depth == o.depth;
  }
};

}  // namespace gpusim
