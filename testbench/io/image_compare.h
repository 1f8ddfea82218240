// Comparison of two EXR images channel by channel, as `gpusim compare` prints
// it, with a heat-map of the difference.
#pragma once

#include <map>
#include <ostream>
#include <string>
#include <vector>

#include "testbench/io/image_files.h"

namespace gpusim {

struct CompareOptions {
  // Per-channel tolerance on |a - b|; channels not listed use default_tolerance.
  // exact == true: bitwise equality of the float values (NaN == NaN when both are).
  bool exact = false;
  float default_tolerance = 0.0f;
  std::map<std::string, float> tolerance;
};

struct ChannelDiff {
  std::string name;
  double tolerance = 0.0;  // as applied (unused in exact mode)
  double max_abs_error = 0.0;
  long long differing_pixels = 0;  // pixels where this channel exceeds tolerance
};

// |a - b| is computed in double; NaN against a number, and +inf against -inf
// or a finite value, count as an infinite error. NaN against NaN and equal
// infinities count as equal.
struct CompareResult {
  int width = 0;
  int height = 0;
  bool exact = false;
  std::vector<ChannelDiff> channels;
  long long differing_pixels = 0;  // pixels where any channel exceeds tolerance
  double differing_share = 0.0;    // differing_pixels / (width * height)
  bool has_first = false;
  int first_x = 0;  // first differing pixel in window coordinates (y up, origin lower left)
  int first_y = 0;
  // Values of both images at the first differing pixel, one per channel in
  // the order of `channels`.
  std::vector<float> first_a;
  std::vector<float> first_b;
  bool pass() const { return differing_pixels == 0; }
};

// Throws InputError naming both images (a_name, b_name: usually their paths)
// when sizes or channel sets differ, and when a tolerance is negative or
// names a channel neither image has. Channels are matched by name; results
// follow a's channel order.
CompareResult compare_images(const Image& a, const Image& b, const CompareOptions& options,
                             const std::string& a_name = "first image",
                             const std::string& b_name = "second image");

// Heat-map PNG: black where the pixel does not differ (by `options`; the
// default means exactly equal), otherwise blue -> red -> yellow with the
// largest per-pixel error across channels, scaled to the largest finite error
// in the image (infinite errors are full yellow). Rows in file order (top
// row first), like the images. Throws InputError like compare_images.
void write_diff_heatmap(const Image& a, const Image& b, const std::string& png_path,
                        const CompareOptions& options = {});

// The report `gpusim compare` prints: per-channel table (tolerance, max abs
// error, differing pixels), count and share of differing pixels, the first
// differing pixel in window coordinates with both images' values, and a final
// line "PASS" or "FAIL".
void print_compare_report(std::ostream& os, const CompareResult& result, const std::string& a_path,
                          const std::string& b_path);

}  // namespace gpusim
