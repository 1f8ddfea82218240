// Multisample positions (docs/pipeline-spec.md, section 14): Direct3D's
// standard patterns (D3D11_STANDARD_MULTISAMPLE_PATTERN, Vulkan's standard
// sample locations) for 1, 2, 4, 8 and 16 samples, in 1/16 pixel from the
// pixel's corner, used as they are with y measured upwards from the
// lower-left corner, where llvmpipe places them for OpenGL. A spec constant
// both models read; each position is on the 1/256 subpixel grid.
#pragma once

#include <array>
#include <cstdint>

#include "hw/fixed_point.h"

namespace gpusim {

constexpr unsigned kMaxSamples = 16;

struct SamplePosition {
  uint8_t x, y;  // 1/16 pixel from the lower-left corner, 0..15
};

// The n positions of an n-sample pattern (n = 1, 2, 4, 8 or 16), else null.
inline const SamplePosition* sample_pattern(unsigned n) {
  static constexpr SamplePosition k1[] = {{8, 8}};
  static constexpr SamplePosition k2[] = {{12, 12}, {4, 4}};
  static constexpr SamplePosition k4[] = {{6, 2}, {14, 6}, {2, 10}, {10, 14}};
  static constexpr SamplePosition k8[] = {{9, 5},  {7, 11}, {13, 9},  {5, 3},
                                          {3, 13}, {1, 7},  {11, 15}, {15, 1}};
  static constexpr SamplePosition k16[] = {{9, 9},   {7, 5},  {5, 10},  {12, 7}, {3, 6}, {10, 13},
                                           {13, 11}, {11, 3}, {6, 14},  {8, 1},  {4, 2}, {2, 12},
                                           {0, 8},   {15, 4}, {14, 15}, {1, 0}};
  switch (n) {
    case 1:
      return k1;
    case 2:
      return k2;
    case 4:
      return k4;
    case 8:
      return k8;
    case 16:
      return k16;
  }
  return nullptr;
}

// Sample i's offset from the pixel centre in subpixels (1/256 pixel): a
// multiple of 16 in [-128, 112]. For one sample it is (0, 0).
struct SampleOffset {
  Subpixel dx, dy;
};
inline SampleOffset sample_offset(unsigned n, unsigned i) {
  const SamplePosition p = sample_pattern(n)[i];
  return {Subpixel{p.x} * 16 - kSubpixelHalf, Subpixel{p.y} * 16 - kSubpixelHalf};
}

}  // namespace gpusim
