// Golden model: the accuracy of multisampling (docs/pipeline-spec.md section
// 14), measured the way piglit's ext_framebuffer_multisample/accuracy does
// (tests/spec/ext_framebuffer_multisample/common.cpp, the "color" test):
//
// - the test pattern is piglit's Triangles: 8 x 8 triangles (-0.5, -1),
//   (0, 1), (0.5, -1) scaled by 0.8 / 8, triangle t rotated by t * 2pi / 64
//   and moved to the centre of cell (t % 8, 7 - t / 8), everything scaled by
//   0.95, white on a (0, 0, 0, 0) clear, in a 256 x 256 framebuffer;
// - the reference is the same pattern supersampled: piglit renders it 16x
//   larger in x and y and box-filters 16 x 16 pixels; here supersample 4 with
//   16 samples per render-target pixel, 256 samples per output pixel too;
// - edge pixels are the channels whose reference value is strictly between
//   0 and 1 ("partially lit"); the RMS of (test - reference) over them must
//   be below 0.333 * 0.62^log2(N). Channels the reference has fully lit or
//   unlit are counted and printed as well.
//
// Also: the error must decrease as N grows.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "hw/pixel_formats.h"
#include "testbench/golden/golden_model.h"

namespace gpusim {
namespace {

constexpr int kSize = 256;
constexpr double kPi = 3.14159265358979323846;

// piglit's Triangles pattern in clip space (w = 1; identity matrices).
Scene triangles_pattern(unsigned samples, unsigned supersample) {
  Scene s;
  s.framebuffer.width = kSize;
  s.framebuffer.height = kSize;
  s.framebuffer.samples = samples;
  s.framebuffer.supersample = supersample;
  s.framebuffer.color_format = ColorFormat::rgba8;
  s.framebuffer.clear_color = {0, 0, 0, 0};
  Draw d;
  d.state.depth_test = false;
  d.state.shading = Shading::flat;
  const float within[3][2] = {{-0.5f, -1.0f}, {0.0f, 1.0f}, {0.5f, -1.0f}};
  const int across = 8;
  const int count = across * across;
  const float tri_scale = 0.8f / across;
  const float rotation_delta = static_cast<float>(kPi * 2.0 / count);
  const float final_scale = 0.95f;
  for (int t = 0; t < count; ++t) {
    const float rotation = rotation_delta * static_cast<float>(t);
    const int i = t % across;
    const int j = across - 1 - t / across;
    for (const auto& v : within) {
      float x = tri_scale * v[0], y = tri_scale * v[1];
      // GLSL's mat2(c, s, -s, c) * pos (column-major).
      const float rx = std::cos(rotation) * x - std::sin(rotation) * y;
      const float ry = std::sin(rotation) * x + std::cos(rotation) * y;
      x = (rx + (static_cast<float>(i) * 2.0f + 1.0f) / across - 1.0f) * final_scale;
      y = (ry + (static_cast<float>(j) * 2.0f + 1.0f) / across - 1.0f) * final_scale;
      d.positions.push_back({x, y, 0.0f, 1.0f});
      d.colors.push_back({1.0f, 1.0f, 1.0f, 1.0f});
    }
  }
  s.draws.push_back(d);
  return s;
}

struct Accuracy {
  double rms = 0.0;       // over the partially lit channels of the reference
  int partial = 0;        // channels the reference has strictly between 0 and 1
  int wrong_extreme = 0;  // channels the reference has at 0 or 1 and the test not
};

std::vector<float> colours(const Framebuffer& fb) {
  std::vector<float> out(fb.color.size());
  for (size_t i = 0; i < out.size(); ++i) out[i] = decode_color(fb.color_format, fb.color[i]);
  return out;
}

Accuracy measure(const std::vector<float>& test, const std::vector<float>& ref) {
  Accuracy a;
  double sum = 0.0;
  for (size_t i = 0; i < ref.size(); ++i) {
    const double e = static_cast<double>(test[i]) - ref[i];
    if (ref[i] <= 0.0f || ref[i] >= 1.0f) {
      if (e != 0.0) ++a.wrong_extreme;
    } else {
      sum += e * e;
      ++a.partial;
    }
  }
  a.rms = a.partial > 0 ? std::sqrt(sum / a.partial) : 0.0;
  return a;
}

TEST(GoldenAntialias, PiglitAccuracyAgainstSupersampledReference) {
  const golden::Result reference = golden::render(triangles_pattern(16, 4));
  ASSERT_EQ(reference.framebuffer.width, kSize);
  ASSERT_EQ(reference.framebuffer.height, kSize);
  const std::vector<float> ref = colours(reference.framebuffer);
  const std::vector<float> coarse_ref =
      colours(golden::render(triangles_pattern(1, 4)).framebuffer);
  double previous = 1.0;
  for (unsigned n : {1u, 2u, 4u, 8u, 16u}) {
    const golden::Result test = golden::render(triangles_pattern(n, 1));
    ASSERT_EQ(test.framebuffer.width, kSize);
    const Accuracy a = measure(colours(test.framebuffer), ref);
    const double limit = 0.333 * std::pow(0.62, std::log2(static_cast<double>(n)));
    std::printf(
        "piglit accuracy, %2u samples: RMS error %.4f over %d partially lit channels "
        "(limit %.4f); %d fully lit or unlit channels differ\n",
        n, a.rms, a.partial, limit, a.wrong_extreme);
    // For comparison only: against supersample 4 alone (16 samples per
    // pixel on a regular 4 x 4 grid), a reference as coarse as the 16-sample
    // test itself.
    const Accuracy coarse = measure(colours(test.framebuffer), coarse_ref);
    std::printf("                            against supersample 4 x 1 sample: RMS %.4f over %d\n",
                coarse.rms, coarse.partial);
    EXPECT_GT(a.partial, 1000) << n << " samples: the pattern has edges";
    EXPECT_LT(a.rms, limit) << n << " samples";
    EXPECT_LT(a.rms, previous) << n << " samples: the error must decrease as N grows";
    previous = a.rms;
  }
}

}  // namespace
}  // namespace gpusim
