// Comparison of two images (EXR or PNG) channel by channel, as `gpusim
// compare` prints it, with a heat-map of the difference. Thresholds, warning
// and failure follow OpenImageIO's idiff (see docs/validation.md).
#pragma once

#include <cstdint>
#include <limits>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "hw/input_error.h"
#include "testbench/io/image_files.h"

namespace gpusim {

// The images cannot be compared pixel for pixel: different sizes, or
// different channel sets where both are EXR (gpusim compare exits 3).
class ImageMismatch : public InputError {
 public:
  using InputError::InputError;
};

constexpr double kDefaultFailThreshold = 1e-6;  // idiff's -fail and -warn defaults

struct CompareOptions {
  // A pixel fails when any channel's |a - b| exceeds that channel's fail
  // threshold: channel_fail's last entry naming the channel, else `fail`.
  // It warns when any channel's |a - b| exceeds `warn` (default: that
  // channel's fail threshold, so no warning band unless asked for).
  // exact == true: a pixel fails (and warns) when any channel's float bits
  // differ (NaN == NaN whatever the payload); fail, warn and channel_fail are
  // then unused.
  bool exact = false;
  double fail = kDefaultFailThreshold;
  double warn = -1.0;  // < 0: each channel's fail threshold
  // NAME=VALUE entries in the order given (parse_channel_threshold); NAME is a
  // channel or a group of the one-letter channels R, G, B, A, Z ("RGBA").
  std::vector<std::pair<std::string, double>> channel_fail;
  // Result: FAILURE when more than fail_percent % of the pixels fail or any
  // channel's error exceeds hard_fail; else WARNING when more than
  // warn_percent % warn or any error exceeds hard_warn; else PASS.
  double fail_percent = 0.0;
  double warn_percent = 0.0;
  double hard_fail = std::numeric_limits<double>::infinity();
  double hard_warn = std::numeric_limits<double>::infinity();
  // Compare the channels both images have (set when a PNG is involved);
  // otherwise different channel sets are an ImageMismatch.
  bool common_channels = false;
};

// "R=0.004", "RGBA=0.004", "Z=1e-6" -> {name, value}; throws InputError
// quoting `spec` unless it is NAME=VALUE with VALUE a number >= 0.
std::pair<std::string, double> parse_channel_threshold(const std::string& spec);

enum class Verdict { pass = 0, warning = 1, failure = 2 };  // gpusim compare's exit codes
const char* to_string(Verdict v);

// Error statistics of one channel, or of a group of them (the colour row).
struct ErrorStats {
  std::string name;
  double fail = 0.0;  // thresholds as applied (unused in exact mode)
  double warn = 0.0;
  double max_error = 0.0;
  bool has_max = false;  // max_error > 0; then at max_x, max_y (window coordinates)
  int max_x = 0;
  int max_y = 0;
  double mean_error = 0.0;       // mean |a - b| over the pixels
  double rms_error = 0.0;        // sqrt(mean (a - b)^2)
  double psnr = 0.0;             // 20 log10(1 / rms_error), dB; inf when rms_error == 0
  long long failing_pixels = 0;  // pixels where this channel exceeds its fail threshold
  long long warning_pixels = 0;  // ... its warn threshold
};

// |a - b| is computed in double; NaN against a number, and +inf against -inf
// or a finite value, count as an infinite error. NaN against NaN and equal
// infinities count as equal.
struct CompareResult {
  int width = 0;
  int height = 0;
  bool exact = false;
  std::vector<ErrorStats> channels;  // compared channels, in a's order
  bool has_color = false;            // color: R, G, B, A among them, together
  ErrorStats color;
  std::vector<std::string> only_in_a, only_in_b;  // channels not compared
  long long failing_pixels = 0;                   // pixels where any channel fails
  long long warning_pixels = 0;                   // pixels where any channel warns
  double fail_percent = 0.0, warn_percent = 0.0, hard_fail = 0.0, hard_warn = 0.0;
  Verdict verdict = Verdict::pass;
  bool has_first = false;
  bool first_fails = false;  // the first failing pixel, else the first warning one
  int first_x = 0;           // window coordinates (y up, origin lower left)
  int first_y = 0;
  // Values of both images at that pixel, one per channel in `channels` order.
  std::vector<float> first_a;
  std::vector<float> first_b;
  bool pass() const { return verdict == Verdict::pass; }
};

// Throws ImageMismatch naming both images (a_name, b_name: usually their
// paths) when sizes or channel sets differ (see common_channels) or no
// channel is common, and InputError when a threshold is negative or names a
// channel neither image has. Channels are matched by name.
CompareResult compare_images(const Image& a, const Image& b, const CompareOptions& options,
                             const std::string& a_name = "first image",
                             const std::string& b_name = "second image");

// Heat-map PNG, rows in file order (top row first) like the images: black
// where the pixel does not fail, otherwise heat_color(e / max) with e the
// pixel's largest channel error and max the largest finite e of a failing
// pixel (infinite errors are full yellow). Below the image a legend strip of
// kLegendHeight rows: a bar of heat_color(x / (width - 1)) for x across the
// image (rows kLegendBarTop .. +kLegendBarHeight), then the labels 0, max/2
// and max where they fit. Returns max (0 when no pixel fails). Throws like
// compare_images.
constexpr int kLegendHeight = 24;
constexpr int kLegendBarTop = 2;  // rows below the image
constexpr int kLegendBarHeight = 8;
double write_diff_heatmap(const Image& a, const Image& b, const std::string& png_path,
                          const CompareOptions& options = {});

// t in [0, 1] -> linear ramp blue (0, 0, 1) -> red (1, 0, 0) at 0.5 ->
// yellow (1, 1, 0), as 8-bit values round(v * 255).
void heat_color(double t, uint8_t rgb[3]);

// The report `gpusim compare` prints: channels compared, a table per channel
// (thresholds, max error and where, mean, RMS, PSNR, failing and warning
// pixels) and a colour row, counts and shares against --failpercent and
// --warnpercent, the first failing (else warning) pixel with both images'
// values, and a final line PASS, WARNING or FAILURE.
void print_compare_report(std::ostream& os, const CompareResult& result, const std::string& a_path,
                          const std::string& b_path);

}  // namespace gpusim
