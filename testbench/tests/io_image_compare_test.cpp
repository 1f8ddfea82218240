// Image comparison: pass/fail, tolerances, exact mode, NaN and infinity
// rules, the first differing pixel in window coordinates, the report and the
// heat-map.
#include <gtest/gtest.h>
#include <png.h>
#include <unistd.h>

#include <cfloat>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
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
  EXPECT_EQ(r.width, 4);
  EXPECT_EQ(r.height, 3);
  EXPECT_EQ(r.differing_pixels, 0);
  EXPECT_EQ(r.differing_share, 0.0);
  EXPECT_FALSE(r.has_first);
  ASSERT_EQ(r.channels.size(), 3u);
  EXPECT_EQ(r.channels[0].name, "B");
  EXPECT_EQ(r.channels[2].name, "R");
  for (const ChannelDiff& d : r.channels) {
    EXPECT_EQ(d.max_abs_error, 0.0) << d.name;
    EXPECT_EQ(d.differing_pixels, 0) << d.name;
  }
  EXPECT_TRUE(compare_images(a, b, CompareOptions{true, 0.0f, {}}).pass());
}

TEST(CompareImages, OneChangedPixelIsNamedInWindowCoordinates) {
  const Image a = make_image();
  Image b = a;
  // File row 0, x = 2: the top row, so window y = height - 1 = 2.
  channel(b, "G")[2] = channel(b, "G")[2] + 0.5f;
  const CompareResult r = compare_images(a, b, {});
  EXPECT_FALSE(r.pass());
  EXPECT_EQ(r.differing_pixels, 1);
  EXPECT_DOUBLE_EQ(r.differing_share, 1.0 / 12.0);
  ASSERT_TRUE(r.has_first);
  EXPECT_EQ(r.first_x, 2);
  EXPECT_EQ(r.first_y, 2);
  // Channels B, G, R: a's values are 0.25 + 10c at file index 2.
  EXPECT_EQ(r.first_a, (std::vector<float>{0.25f, 10.25f, 20.25f}));
  EXPECT_EQ(r.first_b, (std::vector<float>{0.25f, 10.75f, 20.25f}));
  EXPECT_EQ(r.channels[0].differing_pixels, 0);
  EXPECT_EQ(r.channels[1].differing_pixels, 1);
  EXPECT_EQ(r.channels[2].differing_pixels, 0);
  EXPECT_EQ(r.channels[1].max_abs_error, 0.5);
  EXPECT_EQ(r.channels[0].max_abs_error, 0.0);
}

TEST(CompareImages, FirstDifferingPixelFollowsWindowScanOrder) {
  const Image a = make_image();
  Image b = a;
  channel(b, "R")[at(b, 0, 2)] = -1.0f;  // top left
  channel(b, "B")[at(b, 1, 1)] = -1.0f;  // middle row
  channel(b, "G")[at(b, 3, 0)] = -1.0f;  // bottom row, rightmost: first in window order
  const CompareResult r = compare_images(a, b, {});
  EXPECT_EQ(r.differing_pixels, 3);
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
  EXPECT_EQ(r.channels[2].differing_pixels, 1);
  EXPECT_EQ(r.channels[0].differing_pixels, 0);
}

TEST(CompareImages, TolerancesAreInclusive) {
  Image a = make_image(2, 1, {"G", "R"});
  Image b = a;
  channel(a, "R") = {0.5f, 0.0f};
  channel(b, "R") = {0.75f, 0.0f};  // |diff| 0.25
  channel(a, "G") = {0.0f, 1.0f};
  channel(b, "G") = {0.0f, 1.125f};  // |diff| 0.125

  CompareOptions o;
  o.default_tolerance = 0.25f;  // equal to the largest error: passes
  CompareResult r = compare_images(a, b, o);
  EXPECT_TRUE(r.pass());
  EXPECT_EQ(r.channels[1].max_abs_error, 0.25);  // still reported
  EXPECT_EQ(r.channels[0].max_abs_error, 0.125);
  EXPECT_EQ(r.channels[1].tolerance, 0.25);

  o.default_tolerance = 0.125f;  // R exceeds, G is exactly at it
  r = compare_images(a, b, o);
  EXPECT_EQ(r.differing_pixels, 1);
  EXPECT_EQ(r.channels[1].differing_pixels, 1);
  EXPECT_EQ(r.channels[0].differing_pixels, 0);
  EXPECT_EQ(r.first_x, 0);
  EXPECT_EQ(r.first_y, 0);

  o.default_tolerance = 0.0f;
  o.tolerance["R"] = 0.25f;  // per channel overrides the default: only G fails
  r = compare_images(a, b, o);
  EXPECT_EQ(r.differing_pixels, 1);
  EXPECT_EQ(r.channels[0].differing_pixels, 1);
  EXPECT_EQ(r.channels[1].differing_pixels, 0);
  EXPECT_EQ(r.channels[0].tolerance, 0.0);
  EXPECT_EQ(r.first_x, 1);
}

TEST(CompareImages, ExactModeComparesBits) {
  Image a = make_image(3, 1, {"Z"});
  Image b = a;
  channel(a, "Z") = {0.0f, 1.0f, std::nanf("1")};
  channel(b, "Z") = {-0.0f, std::nextafter(1.0f, 2.0f), std::nanf("2")};
  CompareOptions loose;
  loose.default_tolerance = 1e-6f;
  const CompareResult l = compare_images(a, b, loose);
  EXPECT_TRUE(l.pass());  // 0 == -0, 1 ulp within 1e-6, NaN == NaN
  EXPECT_DOUBLE_EQ(l.channels[0].max_abs_error, std::ldexp(1.0, -23));

  CompareOptions exact;
  exact.exact = true;
  exact.default_tolerance = 1.0f;  // ignored in exact mode
  const CompareResult e = compare_images(a, b, exact);
  EXPECT_TRUE(e.exact);
  EXPECT_EQ(e.differing_pixels, 2);  // -0 and the ulp; NaNs with other payloads are equal
  EXPECT_EQ(e.first_x, 0);
  EXPECT_EQ(e.channels[0].differing_pixels, 2);
}

TEST(CompareImages, NaNAndInfinityRules) {
  Image a = make_image(6, 1, {"A"});
  Image b = a;
  channel(a, "A") = {kNaN, 1.0f, kNaN, kInf, kInf, FLT_MAX};
  channel(b, "A") = {1.0f, kNaN, kNaN, kInf, -kInf, -FLT_MAX};
  CompareOptions o;
  o.default_tolerance = 1e30f;  // huge, yet NaN against a number still differs
  const CompareResult r = compare_images(a, b, o);
  // x = 0, 1 (NaN vs number), 4 (+inf vs -inf), 5 (2 * FLT_MAX > 1e30); x = 2
  // (NaN vs NaN) and 3 (inf vs inf) are equal.
  EXPECT_EQ(r.differing_pixels, 4);
  EXPECT_EQ(r.channels[0].differing_pixels, 4);
  EXPECT_EQ(r.channels[0].max_abs_error, std::numeric_limits<double>::infinity());
  EXPECT_EQ(r.first_x, 0);
  EXPECT_TRUE(std::isnan(r.first_a[0]));
  EXPECT_EQ(r.first_b[0], 1.0f);

  // FLT_MAX - (-FLT_MAX) is finite in double: no spurious infinity.
  Image c = make_image(1, 1, {"A"});
  Image d = c;
  channel(c, "A") = {FLT_MAX};
  channel(d, "A") = {-FLT_MAX};
  const CompareResult big = compare_images(c, d, {});
  EXPECT_EQ(big.channels[0].max_abs_error, 2.0 * static_cast<double>(FLT_MAX));
  EXPECT_EQ(big.differing_pixels, 1);
}

void expect_input_error(const Image& a, const Image& b, const CompareOptions& o,
                        const std::string& message) {
  try {
    compare_images(a, b, o, "a.exr", "b.exr");
    ADD_FAILURE() << "no InputError, expected: " << message;
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), message);
  }
}

TEST(CompareImages, MismatchesAndBadTolerancesAreInputErrors) {
  expect_input_error(make_image(4, 3), make_image(3, 4), {},
                     "a.exr and b.exr differ in size: 4x3 vs 3x4");
  expect_input_error(make_image(2, 2, {"B", "G", "R"}), make_image(2, 2, {"A", "B", "G", "R"}), {},
                     "a.exr and b.exr differ in channels: B,G,R vs A,B,G,R");
  CompareOptions typo;
  typo.tolerance["Y"] = 0.1f;
  expect_input_error(make_image(), make_image(), typo,
                     "tolerance given for channel Y, which a.exr and b.exr do not have "
                     "(channels: B,G,R)");
  CompareOptions negative;
  negative.tolerance["G"] = -0.5f;
  expect_input_error(make_image(), make_image(), negative,
                     "tolerance for channel G must be a non-negative number");
  CompareOptions nan_default;
  nan_default.default_tolerance = kNaN;
  expect_input_error(make_image(), make_image(), nan_default,
                     "tolerance must be a non-negative number");
}

TEST(CompareReport, FailShowsTableFirstPixelAndValues) {
  const Image a = make_image();
  Image b = a;
  channel(b, "G")[2] += 0.5f;
  CompareOptions o;
  o.tolerance["R"] = 0.25f;
  const CompareResult r = compare_images(a, b, o);
  std::ostringstream os;
  print_compare_report(os, r, "golden.exr", "model.exr");
  const std::string text = os.str();
  EXPECT_NE(text.find("compare golden.exr model.exr: 4x3, 3 channels\n"), std::string::npos)
      << text;
  EXPECT_NE(text.find("channel  tolerance       max abs error   differing pixels\n"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("\nG        0               0.5             1\n"), std::string::npos) << text;
  EXPECT_NE(text.find("\nR        0.25            0               0\n"), std::string::npos) << text;
  EXPECT_NE(text.find("differing pixels: 1 of 12 (8.3333%)\n"), std::string::npos) << text;
  EXPECT_NE(text.find("first differing pixel: x=2 y=2 (window coordinates, origin lower left)\n"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("  G        10.25           10.75\n"), std::string::npos) << text;
  ASSERT_GE(text.size(), 5u);
  EXPECT_EQ(text.substr(text.size() - 5), "FAIL\n");
  EXPECT_EQ(text.find("PASS"), std::string::npos);
}

TEST(CompareReport, PassEndsWithPass) {
  const Image a = make_image();
  std::ostringstream os;
  print_compare_report(os, compare_images(a, a, CompareOptions{true, 0.0f, {}}), "x.exr", "y.exr");
  const std::string text = os.str();
  EXPECT_NE(text.find("exact (bitwise)"), std::string::npos) << text;
  EXPECT_NE(text.find("differing pixels: 0 of 12 (0.0000%)\n"), std::string::npos) << text;
  EXPECT_EQ(text.find("first differing pixel"), std::string::npos) << text;
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

  std::vector<uint8_t> read_png(const std::string& p, int w, int h) {
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
  write_diff_heatmap(a, b, p);
  const std::vector<uint8_t> px = read_png(p, 4, 2);
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
  EXPECT_EQ(px, want);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);
}

TEST_F(HeatmapTest, ToleranceBlacksOutSmallDifferences) {
  Image a = make_image(2, 1, {"R"});
  Image b = a;
  channel(b, "R")[0] += 0.5f;
  channel(b, "R")[1] += 2.0f;
  CompareOptions o;
  o.default_tolerance = 1.0f;
  const std::string p = (dir_ / "diff.png").string();
  write_diff_heatmap(a, b, p, o);
  EXPECT_EQ(read_png(p, 2, 1), (std::vector<uint8_t>{0, 0, 0, 255, 255, 255, 0, 255}));
}

TEST_F(HeatmapTest, SizeMismatchThrows) {
  EXPECT_THROW(write_diff_heatmap(make_image(2, 2), make_image(2, 3), (dir_ / "d.png").string()),
               InputError);
  EXPECT_FALSE(fs::exists(dir_ / "d.png"));
}

}  // namespace
}  // namespace gpusim
