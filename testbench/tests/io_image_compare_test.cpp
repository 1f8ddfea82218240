// Image comparison: thresholds and verdicts (idiff's fail, warn, failpercent,
// hardfail), exact mode, NaN and infinity rules, error statistics against
// closed-form values, the first failing pixel in window coordinates, PNG
// input, the report and the heat-map with its legend.
#include <gtest/gtest.h>
#include <png.h>
#include <unistd.h>

#include <cfloat>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <sstream>

#include "hw/input_error.h"
#include "testbench/io/image_compare.h"

namespace gpusim {
namespace {

namespace fs = std::filesystem;

const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kInf = std::numeric_limits<float>::infinity();

// W x H image with channels B, G, R; value depends on channel and pixel so
// every sample is distinct.
Image make_image(int w = 4, int h = 3, std::vector<std::string> names = {"B", "G", "R"}) {
  Image img;
  img.width = w;
  img.height = h;
  img.channel_names = names;
  for (size_t c = 0; c < names.size(); ++c) {
    std::vector<float> v(static_cast<size_t>(w) * h);
    for (size_t i = 0; i < v.size(); ++i) v[i] = 0.125f * static_cast<float>(i) + 10.0f * c;
    img.channels.push_back(v);
  }
  return img;
}

// Index of window pixel (x, y) in file order (top row first).
size_t at(const Image& img, int x, int window_y) {
  return static_cast<size_t>(img.height - 1 - window_y) * img.width + x;
}

std::vector<float>& channel(Image& img, const std::string& name) {
  return const_cast<std::vector<float>&>(*img.find(name));
}

TEST(CompareImages, IdenticalImagesPass) {
  Image a = make_image();
  channel(a, "R")[5] = kNaN;  // NaN against NaN is equal
  channel(a, "G")[7] = kInf;  // as are equal infinities
  const Image b = a;
  const CompareResult r = compare_images(a, b, {});
  EXPECT_TRUE(r.pass());
  EXPECT_EQ(r.verdict, Verdict::pass);
  EXPECT_EQ(r.width, 4);
  EXPECT_EQ(r.height, 3);
  EXPECT_EQ(r.failing_pixels, 0);
  EXPECT_EQ(r.warning_pixels, 0);
  EXPECT_FALSE(r.has_first);
  ASSERT_EQ(r.channels.size(), 3u);
  EXPECT_EQ(r.channels[0].name, "B");
  EXPECT_EQ(r.channels[2].name, "R");
  for (const ErrorStats& d : r.channels) {
    EXPECT_EQ(d.max_error, 0.0) << d.name;
    EXPECT_FALSE(d.has_max) << d.name;
    EXPECT_EQ(d.mean_error, 0.0) << d.name;
    EXPECT_EQ(d.rms_error, 0.0) << d.name;
    EXPECT_EQ(d.psnr, std::numeric_limits<double>::infinity()) << d.name;
    EXPECT_EQ(d.failing_pixels, 0) << d.name;
    EXPECT_EQ(d.fail, kDefaultFailThreshold) << d.name;
    EXPECT_EQ(d.warn, kDefaultFailThreshold) << d.name;
  }
  CompareOptions exact;
  exact.exact = true;
  EXPECT_TRUE(compare_images(a, b, exact).pass());
}

TEST(CompareImages, OneChangedPixelIsNamedInWindowCoordinates) {
  const Image a = make_image();
  Image b = a;
  // File row 0, x = 2: the top row, so window y = height - 1 = 2.
  channel(b, "G")[2] = channel(b, "G")[2] + 0.5f;
  const CompareResult r = compare_images(a, b, {});
  EXPECT_EQ(r.verdict, Verdict::failure);
  EXPECT_EQ(r.failing_pixels, 1);
  ASSERT_TRUE(r.has_first);
  EXPECT_TRUE(r.first_fails);
  EXPECT_EQ(r.first_x, 2);
  EXPECT_EQ(r.first_y, 2);
  // Channels B, G, R: a's values are 0.25 + 10c at file index 2.
  EXPECT_EQ(r.first_a, (std::vector<float>{0.25f, 10.25f, 20.25f}));
  EXPECT_EQ(r.first_b, (std::vector<float>{0.25f, 10.75f, 20.25f}));
  EXPECT_EQ(r.channels[0].failing_pixels, 0);
  EXPECT_EQ(r.channels[1].failing_pixels, 1);
  EXPECT_EQ(r.channels[2].failing_pixels, 0);
  EXPECT_EQ(r.channels[1].max_error, 0.5);
  EXPECT_EQ(r.channels[1].max_x, 2);
  EXPECT_EQ(r.channels[1].max_y, 2);
  EXPECT_EQ(r.channels[0].max_error, 0.0);
  EXPECT_TRUE(r.has_color);
  EXPECT_EQ(r.color.name, "RGB");
}

TEST(CompareImages, FirstFailingPixelFollowsWindowScanOrder) {
  const Image a = make_image();
  Image b = a;
  channel(b, "R")[at(b, 0, 2)] = -1.0f;  // top left
  channel(b, "B")[at(b, 1, 1)] = -1.0f;  // middle row
  channel(b, "G")[at(b, 3, 0)] = -1.0f;  // bottom row, rightmost: first in window order
  const CompareResult r = compare_images(a, b, {});
  EXPECT_EQ(r.failing_pixels, 3);
  EXPECT_EQ(r.first_x, 3);
  EXPECT_EQ(r.first_y, 0);
  // Bottom-right pixel is file index 11: values 1.375 + 10c.
  EXPECT_EQ(r.first_a, (std::vector<float>{1.375f, 11.375f, 21.375f}));
  EXPECT_EQ(r.first_b, (std::vector<float>{1.375f, -1.0f, 21.375f}));
}

TEST(CompareImages, ChannelsAreMatchedByName) {
  const Image a = make_image(2, 2, {"B", "G", "R"});
  Image b;
  b.width = 2;
  b.height = 2;
  b.channel_names = {"R", "B", "G"};
  b.channels = {*a.find("R"), *a.find("B"), *a.find("G")};
  EXPECT_TRUE(compare_images(a, b, {}).pass());
  channel(b, "R")[3] += 1.0f;
  const CompareResult r = compare_images(a, b, {});
  EXPECT_EQ(r.channels[2].name, "R");
  EXPECT_EQ(r.channels[2].failing_pixels, 1);
  EXPECT_EQ(r.channels[0].failing_pixels, 0);
}

// Errors of 0.5 in channel R over k = 3 of 8 pixels, all else equal: mean
// 3 * 0.5 / 8, RMS sqrt(3 * 0.25 / 8), PSNR 20 log10(1 / RMS); over the four
// colour channels the same sums divide by 32 values.
TEST(CompareImages, StatisticsOfAKnownOffset) {
  Image a = make_image(4, 2, {"A", "B", "G", "R", "Z"});
  for (auto& c : a.channels) std::fill(c.begin(), c.end(), 0.25f);
  Image b = a;
  for (int x : {1, 2, 3}) channel(b, "R")[at(b, x, 1)] = 0.75f;  // top row (window y = 1)
  const CompareResult r = compare_images(a, b, {});
  ASSERT_EQ(r.channels.size(), 5u);
  const ErrorStats& red = r.channels[3];
  ASSERT_EQ(red.name, "R");
  EXPECT_DOUBLE_EQ(red.mean_error, 1.5 / 8);
  EXPECT_DOUBLE_EQ(red.rms_error, std::sqrt(0.75 / 8));
  EXPECT_DOUBLE_EQ(red.psnr, 20.0 * std::log10(1.0 / std::sqrt(0.75 / 8)));
  EXPECT_NEAR(red.psnr, 10.2803, 1e-4);
  EXPECT_EQ(red.max_error, 0.5);
  EXPECT_EQ(red.max_x, 1);  // the first of the three in window order
  EXPECT_EQ(red.max_y, 1);
  EXPECT_EQ(red.failing_pixels, 3);
  ASSERT_TRUE(r.has_color);
  EXPECT_EQ(r.color.name, "RGBA");
  EXPECT_DOUBLE_EQ(r.color.mean_error, 1.5 / 32);
  EXPECT_DOUBLE_EQ(r.color.rms_error, std::sqrt(0.75 / 32));
  EXPECT_DOUBLE_EQ(r.color.psnr, 20.0 * std::log10(1.0 / std::sqrt(0.75 / 32)));
  EXPECT_EQ(r.color.max_error, 0.5);
  EXPECT_EQ(r.color.failing_pixels, 3);
  const ErrorStats& z = r.channels[4];
  EXPECT_EQ(z.mean_error, 0.0);
  EXPECT_EQ(z.psnr, std::numeric_limits<double>::infinity());
  EXPECT_EQ(r.failing_pixels, 3);
  EXPECT_EQ(r.verdict, Verdict::failure);
}

TEST(CompareImages, ThresholdsAreInclusive) {
  Image a = make_image(2, 1, {"G", "R"});
  Image b = a;
  channel(a, "R") = {0.5f, 0.0f};
  channel(b, "R") = {0.75f, 0.0f};  // |diff| 0.25
  channel(a, "G") = {0.0f, 1.0f};
  channel(b, "G") = {0.0f, 1.125f};  // |diff| 0.125

  CompareOptions o;
  o.fail = 0.25;  // equal to the largest error: passes
  CompareResult r = compare_images(a, b, o);
  EXPECT_TRUE(r.pass());
  EXPECT_EQ(r.channels[1].max_error, 0.25);  // still reported
  EXPECT_EQ(r.channels[0].max_error, 0.125);
  EXPECT_EQ(r.channels[1].fail, 0.25);
  EXPECT_EQ(r.channels[1].warn, 0.25);  // warn follows the fail threshold

  o.fail = 0.125;  // R exceeds, G is exactly at it
  r = compare_images(a, b, o);
  EXPECT_EQ(r.failing_pixels, 1);
  EXPECT_EQ(r.channels[1].failing_pixels, 1);
  EXPECT_EQ(r.channels[0].failing_pixels, 0);
  EXPECT_EQ(r.first_x, 0);
  EXPECT_EQ(r.first_y, 0);

  o.fail = 0.0;
  o.channel_fail = {{"R", 0.25}};  // per channel overrides --fail: only G fails
  r = compare_images(a, b, o);
  EXPECT_EQ(r.failing_pixels, 1);
  EXPECT_EQ(r.channels[0].failing_pixels, 1);
  EXPECT_EQ(r.channels[1].failing_pixels, 0);
  EXPECT_EQ(r.channels[0].fail, 0.0);
  EXPECT_EQ(r.first_x, 1);
}

// --warn below the fail threshold: errors between the two give WARNING, and
// the first such pixel is reported as a warning pixel.
TEST(CompareImages, WarnThresholdGivesWarning) {
  Image a = make_image(2, 1, {"R"});
  Image b = a;
  channel(b, "R")[1] += 0.5f;
  CompareOptions o;
  o.fail = 0.75;
  o.warn = 0.25;
  CompareResult r = compare_images(a, b, o);
  EXPECT_EQ(r.verdict, Verdict::warning);
  EXPECT_EQ(r.failing_pixels, 0);
  EXPECT_EQ(r.warning_pixels, 1);
  ASSERT_TRUE(r.has_first);
  EXPECT_FALSE(r.first_fails);
  EXPECT_EQ(r.first_x, 1);
  o.warn = 0.5;  // inclusive
  EXPECT_EQ(compare_images(a, b, o).verdict, Verdict::pass);
  o.hard_warn = 0.4;  // any one error above it warns, whatever the share
  o.warn_percent = 100.0;
  EXPECT_EQ(compare_images(a, b, o).verdict, Verdict::warning);
  o.hard_fail = 0.4;
  EXPECT_EQ(compare_images(a, b, o).verdict, Verdict::failure);
}

// FAILURE needs more than --failpercent % of the pixels failing: 2 of 8 is
// exactly 25 % (not more: WARNING, as those pixels also warn), 3 of 8 fails.
TEST(CompareImages, FailPercentBoundary) {
  Image a = make_image(4, 2, {"R"});
  Image b = a;
  channel(b, "R")[0] += 1.0f;
  channel(b, "R")[1] += 1.0f;
  CompareOptions o;
  o.fail_percent = 25.0;
  CompareResult r = compare_images(a, b, o);
  EXPECT_EQ(r.failing_pixels, 2);
  EXPECT_EQ(r.verdict, Verdict::warning);
  o.warn_percent = 25.0;
  EXPECT_EQ(compare_images(a, b, o).verdict, Verdict::pass);
  channel(b, "R")[2] += 1.0f;
  r = compare_images(a, b, o);
  EXPECT_EQ(r.failing_pixels, 3);
  EXPECT_EQ(r.verdict, Verdict::failure);
  o.fail_percent = 0.0;  // the default: any failing pixel fails
  channel(b, "R") = *a.find("R");
  channel(b, "R")[7] += 1.0f;
  EXPECT_EQ(compare_images(a, b, o).verdict, Verdict::failure);
}

TEST(CompareImages, ChannelThresholdGroups) {
  EXPECT_EQ(parse_channel_threshold("RGBA=0.004"), (std::pair<std::string, double>{"RGBA", 0.004}));
  EXPECT_EQ(parse_channel_threshold("Z=1e-6"), (std::pair<std::string, double>{"Z", 1e-6}));
  for (const char* bad : {"RGBA", "=0.1", "R=", "R=-1", "R=0.1x", "R=nan"}) {
    EXPECT_THROW(parse_channel_threshold(bad), InputError) << bad;
  }
  Image a = make_image(1, 1, {"A", "B", "G", "R", "Z"});
  CompareOptions o;
  o.channel_fail = {{"RGBA", 0.004}, {"RGB", 0.01}, {"Z", 1e-6}, {"B", 0.5}};
  const CompareResult r = compare_images(a, a, o);
  std::map<std::string, double> fail;
  for (const ErrorStats& s : r.channels) fail[s.name] = s.fail;
  EXPECT_EQ(fail, (std::map<std::string, double>{
                      {"A", 0.004}, {"B", 0.5}, {"G", 0.01}, {"R", 0.01}, {"Z", 1e-6}}));
  // A group applies to the letters the images have; one with none is a typo.
  Image rgb = make_image(1, 1, {"B", "G", "R"});
  o.channel_fail = {{"RGBA", 0.004}};
  EXPECT_EQ(compare_images(rgb, rgb, o).channels[0].fail, 0.004);
  o.channel_fail = {{"AZ", 0.004}};
  EXPECT_THROW(compare_images(rgb, rgb, o), InputError);
}

TEST(CompareImages, ExactModeComparesBits) {
  Image a = make_image(3, 1, {"Z"});
  Image b = a;
  channel(a, "Z") = {0.0f, 1.0f, std::nanf("1")};
  channel(b, "Z") = {-0.0f, std::nextafter(1.0f, 2.0f), std::nanf("2")};
  const CompareResult l = compare_images(a, b, {});
  EXPECT_TRUE(l.pass());  // 0 == -0, 1 ulp within the default 1e-6, NaN == NaN
  EXPECT_DOUBLE_EQ(l.channels[0].max_error, std::ldexp(1.0, -23));

  CompareOptions exact;
  exact.exact = true;
  exact.fail = 1.0;  // unused in exact mode
  const CompareResult e = compare_images(a, b, exact);
  EXPECT_TRUE(e.exact);
  EXPECT_EQ(e.failing_pixels, 2);  // -0 and the ulp; NaNs with other payloads are equal
  EXPECT_EQ(e.first_x, 0);
  EXPECT_EQ(e.channels[0].failing_pixels, 2);
  EXPECT_EQ(e.verdict, Verdict::failure);
}

TEST(CompareImages, NaNAndInfinityRules) {
  Image a = make_image(6, 1, {"A"});
  Image b = a;
  channel(a, "A") = {kNaN, 1.0f, kNaN, kInf, kInf, FLT_MAX};
  channel(b, "A") = {1.0f, kNaN, kNaN, kInf, -kInf, -FLT_MAX};
  CompareOptions o;
  o.fail = 1e30;  // huge, yet NaN against a number still fails
  const CompareResult r = compare_images(a, b, o);
  // x = 0, 1 (NaN vs number), 4 (+inf vs -inf), 5 (2 * FLT_MAX > 1e30); x = 2
  // (NaN vs NaN) and 3 (inf vs inf) are equal.
  EXPECT_EQ(r.failing_pixels, 4);
  EXPECT_EQ(r.channels[0].failing_pixels, 4);
  EXPECT_EQ(r.channels[0].max_error, std::numeric_limits<double>::infinity());
  EXPECT_EQ(r.channels[0].rms_error, std::numeric_limits<double>::infinity());
  EXPECT_EQ(r.channels[0].psnr, -std::numeric_limits<double>::infinity());
  EXPECT_EQ(r.first_x, 0);
  EXPECT_TRUE(std::isnan(r.first_a[0]));
  EXPECT_EQ(r.first_b[0], 1.0f);

  // FLT_MAX - (-FLT_MAX) is finite in double: no spurious infinity.
  Image c = make_image(1, 1, {"A"});
  Image d = c;
  channel(c, "A") = {FLT_MAX};
  channel(d, "A") = {-FLT_MAX};
  const CompareResult big = compare_images(c, d, {});
  EXPECT_EQ(big.channels[0].max_error, 2.0 * static_cast<double>(FLT_MAX));
  EXPECT_EQ(big.failing_pixels, 1);
}

template <typename Error>
void expect_error(const Image& a, const Image& b, const CompareOptions& o,
                  const std::string& message) {
  try {
    compare_images(a, b, o, "a.exr", "b.exr");
    ADD_FAILURE() << "no error, expected: " << message;
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), message);
  }
}

TEST(CompareImages, MismatchesAndBadThresholdsAreInputErrors) {
  expect_error<ImageMismatch>(make_image(4, 3), make_image(3, 4), {},
                              "a.exr and b.exr differ in size: 4x3 vs 3x4");
  const Image rgb = make_image(2, 2, {"B", "G", "R"});
  const Image rgba = make_image(2, 2, {"A", "B", "G", "R"});
  expect_error<ImageMismatch>(rgb, rgba, {},
                              "a.exr and b.exr differ in channels: B,G,R vs A,B,G,R");
  CompareOptions common;
  common.common_channels = true;
  const CompareResult r = compare_images(rgb, rgba, common);
  EXPECT_EQ(r.channels.size(), 3u);
  EXPECT_TRUE(r.only_in_a.empty());
  EXPECT_EQ(r.only_in_b, (std::vector<std::string>{"A"}));
  expect_error<ImageMismatch>(make_image(2, 2, {"Z"}), rgb, common,
                              "a.exr and b.exr differ in channels: Z vs B,G,R (none in common)");
  CompareOptions typo;
  typo.channel_fail = {{"Y", 0.1}};
  expect_error<InputError>(make_image(), make_image(), typo,
                           "threshold given for channel Y, which a.exr and b.exr do not both "
                           "have (channels compared: B,G,R)");
  CompareOptions negative;
  negative.channel_fail = {{"G", -0.5}};
  expect_error<InputError>(make_image(), make_image(), negative,
                           "threshold for G must be a non-negative number");
  CompareOptions nan_fail;
  nan_fail.fail = kNaN;
  expect_error<InputError>(make_image(), make_image(), nan_fail,
                           "fail threshold (--fail, --tolerance) must be a non-negative number");
  CompareOptions percent;
  percent.fail_percent = 101.0;
  expect_error<InputError>(make_image(), make_image(), percent,
                           "--failpercent and --warnpercent must be between 0 and 100");
}

TEST(CompareReport, FailureShowsTableFirstPixelAndValues) {
  Image a = make_image(4, 3, {"B", "G", "R"});
  Image b = a;
  channel(b, "G")[2] += 0.5f;
  CompareOptions o;
  o.channel_fail = {{"R", 0.25}};
  const CompareResult r = compare_images(a, b, o);
  std::ostringstream os;
  print_compare_report(os, r, "golden.exr", "model.exr");
  const std::string text = os.str();
  EXPECT_NE(text.find("compare golden.exr model.exr: 4x3, channels compared: B,G,R\n"),
            std::string::npos)
      << text;
  EXPECT_NE(
      text.find("channel  fail     warn     max error      at x,y   mean error   RMS error    "
                "PSNR dB failing warning\n"),
      std::string::npos)
      << text;
  // G: one error of 0.5 in 12 pixels: mean 0.5 / 12, RMS sqrt(0.25 / 12), PSNR 16.81 dB.
  EXPECT_NE(
      text.find("\nG        1e-06    1e-06    0.5            2,2      0.0416667    0.144338     "
                "16.81   1       1\n"),
      std::string::npos)
      << text;
  EXPECT_NE(
      text.find("\nR        0.25     0.25     0              -        0            0            "
                "inf     0       0\n"),
      std::string::npos)
      << text;
  EXPECT_NE(
      text.find("\nRGB      -        -        0.5            2,2      0.0138889    0.0833333    "
                "21.58   1       1\n"),
      std::string::npos)
      << text;
  EXPECT_NE(text.find("failing pixels: 1 of 12 (8.3333%), FAILURE above 0% (--failpercent)\n"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("first failing pixel: x=2 y=2 (window coordinates, origin lower left)\n"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("  G        10.25           10.75\n"), std::string::npos) << text;
  ASSERT_GE(text.size(), 8u);
  EXPECT_EQ(text.substr(text.size() - 8), "FAILURE\n");
  EXPECT_EQ(text.find("PASS"), std::string::npos);
}

TEST(CompareReport, PassEndsWithPass) {
  const Image a = make_image();
  CompareOptions exact;
  exact.exact = true;
  std::ostringstream os;
  print_compare_report(os, compare_images(a, a, exact), "x.exr", "y.exr");
  const std::string text = os.str();
  EXPECT_NE(text.find("exact (bitwise)"), std::string::npos) << text;
  EXPECT_NE(text.find("\nB        bits     bits     0"), std::string::npos) << text;
  EXPECT_NE(text.find("failing pixels: 0 of 12 (0.0000%)"), std::string::npos) << text;
  EXPECT_EQ(text.find("first failing pixel"), std::string::npos) << text;
  EXPECT_EQ(text.substr(text.size() - 5), "PASS\n");
}

class HeatmapTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("gpusim_io_heatmap_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::vector<uint8_t> read_png_rgba(const std::string& p, int w, int h) {
    png_image image;
    std::memset(&image, 0, sizeof image);
    image.version = PNG_IMAGE_VERSION;
    EXPECT_TRUE(png_image_begin_read_from_file(&image, p.c_str())) << image.message;
    EXPECT_EQ(static_cast<int>(image.width), w);
    EXPECT_EQ(static_cast<int>(image.height), h);
    image.format = PNG_FORMAT_RGBA;
    std::vector<uint8_t> px(PNG_IMAGE_SIZE(image));
    EXPECT_TRUE(png_image_finish_read(&image, nullptr, px.data(), 0, nullptr)) << image.message;
    png_image_free(&image);
    return px;
  }
  fs::path dir_;
};

// The documented colour map, written out again: linear blue -> red -> yellow.
std::vector<uint8_t> ramp(double t) {
  const double r = t < 0.5 ? 2 * t : 1.0, g = t < 0.5 ? 0.0 : 2 * t - 1,
               b = t < 0.5 ? 1 - 2 * t : 0.0;
  return {static_cast<uint8_t>(std::lround(r * 255)), static_cast<uint8_t>(std::lround(g * 255)),
          static_cast<uint8_t>(std::lround(b * 255)), 255};
}

TEST_F(HeatmapTest, RampFromBlueThroughRedToYellow) {
  // Two rows of 4 in file order. Row 0: equal, error 1 (the maximum), 0.5,
  // 0.25. Row 1: NaN against a number (infinite: full yellow, not part of the
  // scale), error 0.125 on the other channel, equal, equal.
  Image a = make_image(4, 2, {"G", "R"});
  Image b = a;
  channel(a, "R") = {0.0f, 0.0f, 0.0f, 0.0f, kNaN, 0.0f, 5.0f, kNaN};
  channel(b, "R") = {0.0f, 1.0f, -0.5f, 0.25f, 1.0f, 0.0f, 5.0f, kNaN};
  channel(b, "G")[5] += 0.125f;
  const std::string p = (dir_ / "diff.png").string();
  EXPECT_EQ(write_diff_heatmap(a, b, p), 1.0);
  const std::vector<uint8_t> px = read_png_rgba(p, 4, 2 + kLegendHeight);
  const std::vector<uint8_t> want = {
      0,   0,   0,   255,  // equal: black
      255, 255, 0,   255,  // t = 1: yellow
      255, 0,   0,   255,  // t = 0.5: red
      128, 0,   128, 255,  // t = 0.25: halfway blue -> red (127.5 rounds up)
      255, 255, 0,   255,  // NaN vs 1: yellow
      64,  0,   191, 255,  // t = 0.125: (0.25, 0, 0.75) -> 63.75, 191.25
      0,   0,   0,   255,  // equal
      0,   0,   0,   255,  // NaN vs NaN: equal
  };
  EXPECT_EQ(std::vector<uint8_t>(px.begin(), px.begin() + 32), want);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);
}

TEST_F(HeatmapTest, ThresholdBlacksOutSmallDifferences) {
  Image a = make_image(2, 1, {"R"});
  Image b = a;
  channel(b, "R")[0] += 0.5f;
  channel(b, "R")[1] += 2.0f;
  CompareOptions o;
  o.fail = 1.0;
  const std::string p = (dir_ / "diff.png").string();
  EXPECT_EQ(write_diff_heatmap(a, b, p, o), 2.0);
  const std::vector<uint8_t> px = read_png_rgba(p, 2, 1 + kLegendHeight);
  EXPECT_EQ(std::vector<uint8_t>(px.begin(), px.begin() + 8),
            (std::vector<uint8_t>{0, 0, 0, 255, 255, 255, 0, 255}));
}

// Below the image: black rows, the bar (colour map of x / (width - 1)), and
// white labels 0, max / 2 and max; nothing else is drawn.
TEST_F(HeatmapTest, LegendBarFollowsTheColourMap) {
  const int w = 101, h = 3;
  Image a = make_image(w, h, {"R"});
  Image b = a;
  channel(b, "R")[5] += 0.25f;  // max 0.25: labels "0", "0.125", "0.25"
  const std::string p = (dir_ / "diff.png").string();
  EXPECT_EQ(write_diff_heatmap(a, b, p), 0.25);
  const std::vector<uint8_t> px = read_png_rgba(p, w, h + kLegendHeight);
  auto pixel = [&](int x, int y) {
    const size_t i = (static_cast<size_t>(y) * w + x) * 4;
    return std::vector<uint8_t>(px.begin() + i, px.begin() + i + 4);
  };
  const std::vector<uint8_t> black = {0, 0, 0, 255}, white = {255, 255, 255, 255};
  for (int x = 0; x < w; ++x) {
    for (int y = 0; y < kLegendBarTop; ++y) EXPECT_EQ(pixel(x, h + y), black) << x;
    for (int y = 0; y < kLegendBarHeight; ++y) {
      EXPECT_EQ(pixel(x, h + kLegendBarTop + y), ramp(x / 100.0)) << x << "," << y;
    }
  }
  EXPECT_EQ(pixel(0, h + kLegendBarTop), (std::vector<uint8_t>{0, 0, 255, 255}));
  EXPECT_EQ(pixel(50, h + kLegendBarTop), (std::vector<uint8_t>{255, 0, 0, 255}));
  EXPECT_EQ(pixel(100, h + kLegendBarTop), (std::vector<uint8_t>{255, 255, 0, 255}));
  // Labels: only black and white below the bar, white in the left, middle and
  // right thirds (the three numbers).
  int white_in[3] = {0, 0, 0};
  for (int y = h + kLegendBarTop + kLegendBarHeight; y < h + kLegendHeight; ++y) {
    for (int x = 0; x < w; ++x) {
      const std::vector<uint8_t> v = pixel(x, y);
      ASSERT_TRUE(v == black || v == white) << x << "," << y;
      if (v == white) ++white_in[x * 3 / w];
    }
  }
  EXPECT_GT(white_in[0], 0);
  EXPECT_GT(white_in[1], 0);
  EXPECT_GT(white_in[2], 0);
}

TEST_F(HeatmapTest, SizeMismatchThrows) {
  EXPECT_THROW(write_diff_heatmap(make_image(2, 2), make_image(2, 3), (dir_ / "d.png").string()),
               ImageMismatch);
  EXPECT_FALSE(fs::exists(dir_ / "d.png"));
}

// PNG input: 8-bit values as v / 255, R, G, B and A when the file has alpha;
// read_image tells PNG from EXR by the signature; 16-bit files are refused.
TEST_F(HeatmapTest, PngInput) {
  const std::string p = (dir_ / "in.png").string();
  write_png_rgba8(p, 2, 1, {0, 51, 255, 128, 10, 20, 30, 255});
  for (const Image& img : {read_png(p), read_image(p)}) {
    EXPECT_TRUE(img.png);
    EXPECT_EQ(img.width, 2);
    EXPECT_EQ(img.height, 1);
    EXPECT_EQ(img.channel_names, (std::vector<std::string>{"R", "G", "B", "A"}));
    EXPECT_EQ(*img.find("R"), (std::vector<float>{0.0f, 10 / 255.0f}));
    EXPECT_EQ(*img.find("G"), (std::vector<float>{0.2f, 20 / 255.0f}));
    EXPECT_EQ(*img.find("A"), (std::vector<float>{128 / 255.0f, 1.0f}));
  }
  // 16-bit: written through libpng's linear (16-bit) format.
  const std::string p16 = (dir_ / "deep.png").string();
  png_image image;
  std::memset(&image, 0, sizeof image);
  image.version = PNG_IMAGE_VERSION;
  image.width = 1;
  image.height = 1;
  image.format = PNG_FORMAT_LINEAR_RGB;
  const uint16_t rgb16[3] = {0, 1000, 65535};
  ASSERT_TRUE(png_image_write_to_file(&image, p16.c_str(), 0, rgb16, 0, nullptr)) << image.message;
  png_image_free(&image);
  try {
    read_image(p16);
    ADD_FAILURE() << "16-bit PNG accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), p16 + ": 16-bit PNG files are not supported (8-bit only)");
  }
  const std::string text = (dir_ / "frame.png.txt").string();
  std::FILE* f = std::fopen(text.c_str(), "w");
  std::fputs("not an image", f);
  std::fclose(f);
  try {
    read_image(text);
    ADD_FAILURE() << "text accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), text + ": not an OpenEXR or PNG file");
  }
}

}  // namespace
}  // namespace gpusim
