// The colour and depth buffers as stored bits. Row 0 is the bottom row
// (window y = 0, GL's lower-left origin); image files flip it so pictures are
// upright. A multisampled render target (docs/pipeline-spec.md, section 14)
// keeps `samples` colours and depths per pixel, a pixel's samples adjacent;
// images written out have one.
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
  unsigned samples = 1;
  std::vector<ColorChannel> color;  // 4 channels (R, G, B, A) per sample
  std::vector<DepthValue> depth;    // 1 per sample

  Framebuffer() = default;
  Framebuffer(int w, int h, ColorFormat cf, DepthFormat df, unsigned n = 1)
      : width(w),
        height(h),
        color_format(cf),
        depth_format(df),
        samples(n),
        color(static_cast<size_t>(w) * h * n * 4),
        depth(static_cast<size_t>(w) * h * n) {}

  size_t pixel_index(int x, int y) const { return static_cast<size_t>(y) * width + x; }
  // Index of sample s of pixel (x, y) in `depth` (times 4 in `color`).
  size_t sample_index(int x, int y, unsigned s) const { return pixel_index(x, y) * samples + s; }
  ColorChannel* color_at(int x, int y) { return &color[pixel_index(x, y) * 4]; }
  const ColorChannel* color_at(int x, int y) const { return &color[pixel_index(x, y) * 4]; }

  void clear(const float rgba[4], float z) {
    clear_color(rgba);
    clear_depth(z);
  }
  // Every sample of one buffer (a mid-frame clear may clear either).
  void clear_color(const float rgba[4]) {
    ColorChannel c[4];
    for (int i = 0; i < 4; ++i) c[i] = encode_color(color_format, rgba[i]);
    for (size_t p = 0; p < depth.size(); ++p) {
      for (int i = 0; i < 4; ++i) color[p * 4 + i] = c[i];
    }
  }
  void clear_depth(float z) {
    std::fill(depth.begin(), depth.end(), encode_depth(depth_format, z));
  }

  bool operator==(const Framebuffer& o) const {
    return width == o.width && height == o.height && color_format == o.color_format &&
           depth_format == o.depth_format && samples == o.samples && color == o.color &&
           depth == o.depth;
  }
};

}  // namespace gpusim
