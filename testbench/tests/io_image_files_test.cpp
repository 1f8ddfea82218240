// EXR and PNG frame dumps: round trips checked against values derived here,
// the row flip, exact half bits, header contents, and read_exr's errors.
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>
#include <ImfTileDescription.h>
#include <ImfTiledOutputFile.h>
#include <gtest/gtest.h>
#include <png.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>

#include "hw/input_error.h"
#include "testbench/io/image_files.h"

namespace gpusim {
namespace {

namespace fs = std::filesystem;

class ImageFilesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = std::string(info->test_suite_name()) + "_" + info->name();
    for (char& c : name) {
      if (c == '/') c = '_';  // parameterised tests are named "Prefix/Suite.Test/param"
    }
    dir_ =
        fs::temp_directory_path() / ("gpusim_io_files_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::set<std::string> listing() const {
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_)) names.insert(e.path().filename().string());
    return names;
  }
  fs::path dir_;
};

// IEEE binary16 -> float written out from the definition, independent of
// Imath and of hw/pixel_formats.h.
float half_bits_to_float(uint16_t h) {
  const int sign = h >> 15;
  const int exponent = (h >> 10) & 0x1f;
  const int mantissa = h & 0x3ff;
  float v;
  if (exponent == 0) {
    v = std::ldexp(static_cast<float>(mantissa), -24);
  } else if (exponent == 31) {
    v = mantissa == 0 ? INFINITY : NAN;
  } else {
    v = std::ldexp(static_cast<float>(mantissa + 1024), exponent - 25);
  }
  return sign ? -v : v;
}

// Equal as floats, or both NaN.
void expect_same_float(float expected, float actual, const std::string& where) {
  if (std::isnan(expected)) {
    EXPECT_TRUE(std::isnan(actual)) << where << ": got " << actual;
  } else {
    uint32_t e, a;
    std::memcpy(&e, &expected, 4);
    std::memcpy(&a, &actual, 4);
    EXPECT_EQ(e, a) << where << ": expected " << expected << " got " << actual;
  }
}

constexpr int kW = 5;
constexpr int kH = 3;

// Distinct stored values per pixel and channel. Row flips and channel mix-ups
// both change what is read back.
Framebuffer make_framebuffer(ColorFormat cf, DepthFormat df) {
  Framebuffer fb(kW, kH, cf, df);
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      const int i = y * kW + x;
      for (int c = 0; c < 4; ++c) {
        uint16_t v;
        if (cf == ColorFormat::rgba8) {
          v = static_cast<uint16_t>(i * 17 + c * 4 + 1);  // 1..252, all distinct
        } else {
          // Distinct halves, mixing signs and magnitudes: sign bit from c,
          // exponents 10..24, mantissa from i and c.
          v = static_cast<uint16_t>(((c & 1) << 15) | ((10 + i) << 10) | (i * 61 + c * 7));
        }
        fb.color_at(x, y)[c] = v;
      }
      uint32_t d;
      switch (df) {
        case DepthFormat::unorm16:
          d = static_cast<uint32_t>(i * 3001 + 17);
          break;
        case DepthFormat::unorm24:
          d = static_cast<uint32_t>(i * 1000003 + 5);
          break;
        default: {
          const float z = 0.0625f * static_cast<float>(i) + 1.0f / 3.0f;
          std::memcpy(&d, &z, 4);
        }
      }
      fb.depth[fb.pixel_index(x, y)] = d;
    }
  }
  // Special halves must survive too.
  if (cf == ColorFormat::rgba16f) {
    uint16_t* p = fb.color_at(1, 1);
    p[0] = 0x7c00;  // +inf
    p[1] = 0x8000;  // -0
    p[2] = 0x0001;  // smallest denormal
    p[3] = 0x7e00;  // quiet NaN
  }
  return fb;
}

float expected_color(ColorFormat cf, uint16_t v) {
  // rgba8: v / 255 rounded to half (the file's channel type).
  return cf == ColorFormat::rgba8 ? static_cast<float>(Imath::half(static_cast<float>(v) / 255.0f))
                                  : half_bits_to_float(v);
}

float expected_depth(DepthFormat df, uint32_t v) {
  if (df == DepthFormat::unorm16) return static_cast<float>(v / 65535.0);
  if (df == DepthFormat::unorm24) return static_cast<float>(v / 16777215.0);
  float f;
  std::memcpy(&f, &v, 4);
  return f;
}

struct Formats {
  ColorFormat color;
  DepthFormat depth;
  const char* color_name;
  const char* depth_name;
};
void PrintTo(const Formats& f, std::ostream* os) {
  *os << f.color_name << "/" << f.depth_name;
}

class ExrRoundTripTest : public ImageFilesTest, public ::testing::WithParamInterface<Formats> {};

TEST_P(ExrRoundTripTest, AllChannelsRowFlippedAndHeader) {
  const Formats f = GetParam();
  const Framebuffer fb = make_framebuffer(f.color, f.depth);
  const std::string p = path("frame.exr");
  write_frame_exr(fb, p);
  EXPECT_EQ(listing(), std::set<std::string>{"frame.exr"});  // no temporaries left

  const Image img = read_exr(p);
  ASSERT_EQ(img.width, kW);
  ASSERT_EQ(img.height, kH);
  ASSERT_EQ(img.channel_names, (std::vector<std::string>{"A", "B", "G", "R", "Z"}));
  const char* rgba_names[4] = {"R", "G", "B", "A"};
  for (int y = 0; y < kH; ++y) {
    const int file_row = kH - 1 - y;
    for (int x = 0; x < kW; ++x) {
      const size_t i = static_cast<size_t>(file_row) * kW + x;
      for (int c = 0; c < 4; ++c) {
        expect_same_float(expected_color(f.color, fb.color_at(x, y)[c]),
                          (*img.find(rgba_names[c]))[i],
                          std::string(rgba_names[c]) + " at fb (" + std::to_string(x) + "," +
                              std::to_string(y) + ")");
      }
      expect_same_float(expected_depth(f.depth, fb.depth[fb.pixel_index(x, y)]),
                        (*img.find("Z"))[i],
                        "Z at fb (" + std::to_string(x) + "," + std::to_string(y) + ")");
    }
  }
  // Framebuffer row 0 (bottom) is the last file row, not the first.
  const float bottom_r = expected_color(f.color, fb.color_at(2, 0)[0]);
  EXPECT_EQ((*img.find("R"))[(kH - 1) * kW + 2], bottom_r);
  EXPECT_NE((*img.find("R"))[2], bottom_r);

  // Header: channel types, lossless compression, format attributes.
  Imf::InputFile in(p.c_str());
  const Imf::Header& h = in.header();
  EXPECT_TRUE(h.compression() == Imf::ZIP_COMPRESSION || h.compression() == Imf::PIZ_COMPRESSION);
  for (const char* n : rgba_names) EXPECT_EQ(h.channels().findChannel(n)->type, Imf::HALF) << n;
  EXPECT_EQ(h.channels().findChannel("Z")->type, Imf::FLOAT);
  EXPECT_EQ(h.typedAttribute<Imf::StringAttribute>("gpusim:color_format").value(), f.color_name);
  EXPECT_EQ(h.typedAttribute<Imf::StringAttribute>("gpusim:depth_format").value(), f.depth_name);
}

INSTANTIATE_TEST_SUITE_P(
    Formats, ExrRoundTripTest,
    ::testing::Values(Formats{ColorFormat::rgba8, DepthFormat::unorm16, "rgba8", "unorm16"},
                      Formats{ColorFormat::rgba8, DepthFormat::unorm24, "rgba8", "unorm24"},
                      Formats{ColorFormat::rgba8, DepthFormat::float32, "rgba8", "float32"},
                      Formats{ColorFormat::rgba16f, DepthFormat::unorm16, "rgba16f", "unorm16"},
                      Formats{ColorFormat::rgba16f, DepthFormat::unorm24, "rgba16f", "unorm24"},
                      Formats{ColorFormat::rgba16f, DepthFormat::float32, "rgba16f", "float32"}),
    [](const auto& info) {
      return std::string(info.param.color_name) + "_" + info.param.depth_name;
    });

uint16_t rotl16(uint16_t v, int s) {
  return static_cast<uint16_t>((v << s) | (v >> (16 - s)));
}

TEST_F(ImageFilesTest, EveryHalfBitPatternSurvivesExactly) {
  // 256 x 256 pixels: each channel holds every 16-bit pattern once, in a
  // different arrangement per channel.
  Framebuffer fb(256, 256, ColorFormat::rgba16f, DepthFormat::float32);
  auto pattern = [](int c, uint32_t i) -> uint16_t {
    switch (c) {
      case 0:
        return static_cast<uint16_t>(i);
      case 1:
        return static_cast<uint16_t>(i * 40503u);  // odd multiplier: a permutation
      case 2:
        return static_cast<uint16_t>(0xffffu - i);
      default:
        return rotl16(static_cast<uint16_t>(i), 8);
    }
  };
  for (int y = 0; y < 256; ++y) {
    for (int x = 0; x < 256; ++x) {
      for (int c = 0; c < 4; ++c) fb.color_at(x, y)[c] = pattern(c, y * 256u + x);
    }
  }
  const std::string p = path("halves.exr");
  write_frame_exr(fb, p);

  // Read the halves themselves, bypassing any float conversion.
  Imf::InputFile in(p.c_str());
  std::vector<Imath::half> file[4];
  Imf::FrameBuffer frame;
  const char* names[4] = {"R", "G", "B", "A"};
  for (int c = 0; c < 4; ++c) {
    file[c].resize(256 * 256);
    frame.insert(names[c], Imf::Slice(Imf::HALF, reinterpret_cast<char*>(file[c].data()),
                                      sizeof(Imath::half), sizeof(Imath::half) * 256));
  }
  in.setFrameBuffer(frame);
  in.readPixels(0, 255);
  const Image img = read_exr(p);
  int mismatches = 0;
  for (int r = 0; r < 256; ++r) {
    for (int x = 0; x < 256; ++x) {
      const uint32_t i = static_cast<uint32_t>(255 - r) * 256u + x;  // fb index
      for (int c = 0; c < 4; ++c) {
        const uint16_t want = pattern(c, i);
        const uint16_t got = file[c][r * 256 + x].bits();
        if (got != want && ++mismatches < 10) {
          ADD_FAILURE() << names[c] << " file (" << x << "," << r << "): wrote 0x" << std::hex
                        << want << " read 0x" << got;
        }
        const float f = (*img.find(names[c]))[r * 256 + x];
        const float e = half_bits_to_float(want);
        if (std::isnan(e) ? !std::isnan(f) : std::memcmp(&e, &f, 4) != 0) {
          if (++mismatches < 10) ADD_FAILURE() << "read_exr 0x" << std::hex << want << ": " << f;
        }
      }
    }
  }
  EXPECT_EQ(mismatches, 0);
}

TEST_F(ImageFilesTest, ExrheaderListsHalfColourAndFloatDepth) {
  // scripts/setup installs it: its absence is a broken set-up, not a reason to skip.
  ASSERT_EQ(std::system("command -v exrheader > /dev/null 2>&1"), 0)
      << "exrheader (Debian package openexr, installed by scripts/setup) is missing";
  const std::string p = path("frame.exr");
  write_frame_exr(make_framebuffer(ColorFormat::rgba8, DepthFormat::unorm24), p);
  FILE* pipe = ::popen(("exrheader '" + p + "' 2>&1").c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string out;
  char buf[512];
  while (std::fgets(buf, sizeof buf, pipe)) out += buf;
  ASSERT_EQ(::pclose(pipe), 0) << out;
  for (const char* c : {"R", "G", "B", "A"}) {
    EXPECT_NE(out.find(std::string("\n    ") + c + ", 16-bit floating-point, sampling 1 1\n"),
              std::string::npos)
        << c << " not half in:\n"
        << out;
  }
  EXPECT_NE(out.find("\n    Z, 32-bit floating-point, sampling 1 1\n"), std::string::npos) << out;
  EXPECT_NE(out.find("gpusim:color_format (type string): \"rgba8\""), std::string::npos) << out;
  EXPECT_NE(out.find("gpusim:depth_format (type string): \"unorm24\""), std::string::npos) << out;
  EXPECT_NE(out.find("compression (type compression): zip"), std::string::npos) << out;
}

TEST_F(ImageFilesTest, ReadExrTiledUintFloatWithOffsetDataWindow) {
  // A tiled file with a data window away from the origin and the three pixel
  // types, as another tool might write it.
  const Imath::Box2i dw(Imath::V2i(10, 20), Imath::V2i(13, 22));  // 4 x 3
  Imf::Header header(Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(31, 31)), dw);
  header.setTileDescription(Imf::TileDescription(3, 2, Imf::ONE_LEVEL));
  header.channels().insert("id", Imf::Channel(Imf::UINT));
  header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
  header.channels().insert("H", Imf::Channel(Imf::HALF));
  std::vector<uint32_t> ids(12);
  std::vector<float> ys(12);
  std::vector<Imath::half> hs(12);
  for (int i = 0; i < 12; ++i) {
    ids[i] = 4000000000u + static_cast<uint32_t>(i) * 1024u;  // exact in float (multiple of 1024)
    ys[i] = -1.5f * static_cast<float>(i) + 0.1f;
    hs[i] = Imath::half(0.25f * static_cast<float>(i));
  }
  const std::string p = path("tiled.exr");
  {
    Imf::TiledOutputFile out(p.c_str(), header);
    Imf::FrameBuffer frame;
    frame.insert("id", Imf::Slice::Make(Imf::UINT, ids.data(), dw));
    frame.insert("Y", Imf::Slice::Make(Imf::FLOAT, ys.data(), dw));
    frame.insert("H", Imf::Slice::Make(Imf::HALF, hs.data(), dw));
    out.setFrameBuffer(frame);
    out.writeTiles(0, out.numXTiles() - 1, 0, out.numYTiles() - 1);
  }
  const Image img = read_exr(p);
  ASSERT_EQ(img.width, 4);
  ASSERT_EQ(img.height, 3);
  EXPECT_EQ(img.channel_names, (std::vector<std::string>{"H", "Y", "id"}));
  for (int i = 0; i < 12; ++i) {
    EXPECT_EQ((*img.find("id"))[i], 4000000000.0f + 1024.0f * static_cast<float>(i)) << i;
    EXPECT_EQ((*img.find("Y"))[i], -1.5f * static_cast<float>(i) + 0.1f) << i;
    EXPECT_EQ((*img.find("H"))[i], 0.25f * static_cast<float>(i)) << i;
  }
  EXPECT_EQ(img.find("Z"), nullptr);
}

TEST_F(ImageFilesTest, ReadExrReplicatesSubsampledChannels) {
  const Imath::Box2i dw(Imath::V2i(0, 0), Imath::V2i(3, 3));
  Imf::Header header(dw, dw);
  header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
  header.channels().insert("C", Imf::Channel(Imf::FLOAT, 2, 2));
  std::vector<float> y(16), c = {10.0f, 20.0f, 30.0f, 40.0f};  // 2 x 2 samples
  for (int i = 0; i < 16; ++i) y[i] = static_cast<float>(i);
  const std::string p = path("sub.exr");
  {
    Imf::OutputFile out(p.c_str(), header);
    Imf::FrameBuffer frame;
    frame.insert("Y", Imf::Slice::Make(Imf::FLOAT, y.data(), dw));
    frame.insert("C", Imf::Slice::Make(Imf::FLOAT, c.data(), dw, 0, 0, 2, 2));
    out.setFrameBuffer(frame);
    out.writePixels(4);
  }
  const Image img = read_exr(p);
  const std::vector<float> want_c = {10, 10, 20, 20, 10, 10, 20, 20,
                                     30, 30, 40, 40, 30, 30, 40, 40};
  EXPECT_EQ(*img.find("C"), want_c);
  EXPECT_EQ(*img.find("Y"), y);
}

void expect_input_error_for(const std::string& p, const std::string& expected_prefix) {
  try {
    read_exr(p);
    ADD_FAILURE() << "read_exr(" << p << ") did not throw";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(expected_prefix, 0), 0u) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
}

TEST_F(ImageFilesTest, ReadExrErrorsNameTheFile) {
  expect_input_error_for(path("missing.exr"), path("missing.exr") + ": no such file");

  std::ofstream(path("text.exr")) << "this is not an image\n";
  expect_input_error_for(path("text.exr"), path("text.exr") + ": not an OpenEXR file");

  // A valid file cut short: the header survives, the pixel data does not.
  Framebuffer fb(64, 64, ColorFormat::rgba16f, DepthFormat::float32);
  for (size_t i = 0; i < fb.color.size(); ++i)
    fb.color[i] = static_cast<uint16_t>(i * 2654435761u >> 7);
  for (size_t i = 0; i < fb.depth.size(); ++i) fb.depth[i] = static_cast<uint32_t>(i * 2246822519u);
  write_frame_exr(fb, path("full.exr"));
  std::ifstream in(path("full.exr"), std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GT(bytes.size(), 4096u);
  std::ofstream(path("cut.exr"), std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  expect_input_error_for(path("cut.exr"), path("cut.exr") + ": ");

  // Garbage after a valid magic number and version.
  std::ofstream(path("garbage.exr"), std::ios::binary)
      << bytes.substr(0, 8) + std::string(200, '\xff');
  expect_input_error_for(path("garbage.exr"), path("garbage.exr") + ": ");

  expect_input_error_for(dir_.string(), dir_.string() + ": not a regular file");
}

TEST_F(ImageFilesTest, WritersRejectMissingDirectoryAndEmptyImage) {
  const Framebuffer fb = make_framebuffer(ColorFormat::rgba8, DepthFormat::unorm24);
  const std::string exr = path("no/such/dir/frame.exr");
  const std::string png = path("no/such/dir/frame.png");
  try {
    write_frame_exr(fb, exr);
    ADD_FAILURE() << "no throw";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(exr + ": ", 0), 0u) << e.what();
  }
  try {
    write_frame_png(fb, png);
    ADD_FAILURE() << "no throw";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(png + ": ", 0), 0u) << e.what();
  }
  EXPECT_THROW(write_frame_exr(Framebuffer(0, 0, ColorFormat::rgba8, DepthFormat::unorm24),
                               path("empty.exr")),
               InputError);
  EXPECT_TRUE(listing().empty());
}

// libpng's own error mid-file (its write callback's short write, here past
// a file size limit): one line naming the file, no file left behind, and the
// writer usable again (the error returns through libpng's longjmp).
TEST_F(ImageFilesTest, PngWriteErrorInLibpngIsOneLineAndLeavesNothing) {
  std::vector<uint8_t> noise(256 * 256 * 4);
  uint32_t state = 17;
  for (uint8_t& b : noise) {
    state = state * 1664525u + 1013904223u;
    b = static_cast<uint8_t>(state >> 24);
  }
  rlimit saved{};
  ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &saved), 0);
  const auto old_handler = std::signal(SIGXFSZ, SIG_IGN);
  rlimit limit = saved;
  limit.rlim_cur = 4096;  // the noise deflates to about 256 KB
  ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &limit), 0);
  const std::string p = path("noise.png");
  std::string message;
  try {
    write_png_rgba8(p, 256, 256, noise);
  } catch (const InputError& e) {
    message = e.what();
  }
  setrlimit(RLIMIT_FSIZE, &saved);
  std::signal(SIGXFSZ, old_handler);
  EXPECT_EQ(message.rfind(p + ": cannot write PNG file: ", 0), 0u) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  EXPECT_TRUE(listing().empty());
  write_png_rgba8(p, 256, 256, noise);
  EXPECT_EQ(listing(), std::set<std::string>{"noise.png"});
}

// Read a PNG with libpng, requiring 8-bit RGBA in the file itself.
std::vector<uint8_t> read_png_rgba8(const std::string& p, int* w, int* h) {
  png_image image;
  std::memset(&image, 0, sizeof image);
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, p.c_str())) {
    ADD_FAILURE() << p << ": " << image.message;
    return {};
  }
  EXPECT_EQ(image.format, static_cast<png_uint_32>(PNG_FORMAT_RGBA)) << "file is not 8-bit RGBA";
  *w = static_cast<int>(image.width);
  *h = static_cast<int>(image.height);
  std::vector<uint8_t> px(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, px.data(), 0, nullptr)) {
    ADD_FAILURE() << p << ": " << image.message;
  }
  png_image_free(&image);
  return px;
}

TEST_F(ImageFilesTest, PngOfRgba8IsTheStoredBytesTopRowFirst) {
  const Framebuffer fb = make_framebuffer(ColorFormat::rgba8, DepthFormat::unorm24);
  const std::string p = path("frame.png");
  write_frame_png(fb, p);
  EXPECT_EQ(listing(), std::set<std::string>{"frame.png"});
  int w = 0, h = 0;
  const std::vector<uint8_t> px = read_png_rgba8(p, &w, &h);
  ASSERT_EQ(w, kW);
  ASSERT_EQ(h, kH);
  ASSERT_EQ(px.size(), static_cast<size_t>(kW * kH * 4));
  for (int r = 0; r < kH; ++r) {
    for (int x = 0; x < kW; ++x) {
      for (int c = 0; c < 4; ++c) {
        EXPECT_EQ(px[(r * kW + x) * 4 + c], fb.color_at(x, kH - 1 - r)[c])
            << "png (" << x << "," << r << ") channel " << c;
      }
    }
  }
}

TEST_F(ImageFilesTest, PngOfRgba16fClampsAndRounds) {
  // half bits -> expected byte, worked out by hand: clamp to [0, 1] (NaN -> 0),
  // then round(v * 255).
  const std::vector<std::pair<uint16_t, uint8_t>> cases = {
      {0x0000, 0},    // 0
      {0x8000, 0},    // -0
      {0x3c00, 255},  // 1
      {0x4000, 255},  // 2 clamps
      {0xbc00, 0},    // -1 clamps
      {0x7c00, 255},  // +inf
      {0x7e00, 0},    // NaN
      {0x3800, 128},  // 0.5 * 255 = 127.5 rounds up
      {0x3400, 64},   // 63.75
      {0x3555, 85},   // 0.333251953125 * 255 = 84.979
      {0x2e66, 25},   // 0.0999755859375 * 255 = 25.494
      {0x1819, 1},    // 0.00200080871582 * 255 = 0.510
      {0x3bf8, 254},  // 0.99609375 * 255 = 254.0039
      {0x3bfc, 255},  // 0.998046875 * 255 = 254.502
  };
  const int n = static_cast<int>(cases.size());
  // One row of n pixels, channels rotated so every channel sees every case.
  Framebuffer fb(n, 2, ColorFormat::rgba16f, DepthFormat::float32);
  for (int y = 0; y < 2; ++y) {
    for (int x = 0; x < n; ++x) {
      for (int c = 0; c < 4; ++c) fb.color_at(x, y)[c] = cases[(x + c + 3 * y) % n].first;
    }
  }
  const std::string p = path("f16.png");
  write_frame_png(fb, p);
  int w = 0, h = 0;
  const std::vector<uint8_t> px = read_png_rgba8(p, &w, &h);
  ASSERT_EQ(w, n);
  ASSERT_EQ(h, 2);
  for (int r = 0; r < 2; ++r) {
    const int y = 1 - r;
    for (int x = 0; x < n; ++x) {
      for (int c = 0; c < 4; ++c) {
        const auto& [bits, byte] = cases[(x + c + 3 * y) % n];
        EXPECT_EQ(px[(r * n + x) * 4 + c], byte) << "half 0x" << std::hex << bits;
      }
    }
  }
}

}  // namespace
}  // namespace gpusim
