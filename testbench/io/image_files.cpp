#include "testbench/io/image_files.h"

#include <ImathBox.h>
#include <ImfChannelList.h>
#include <ImfCompression.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>
#include <ImfTestFile.h>
#include <png.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <new>
#include <stdexcept>

#include "hw/input_error.h"
#include "testbench/io/output_file.h"

namespace gpusim {

namespace {

// Library messages may span lines; InputError's contract is one line.
std::string one_line(std::string s) {
  for (char& c : s) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

void check_framebuffer(const Framebuffer& fb, const std::string& path) {
  if (fb.width <= 0 || fb.height <= 0) {
    throw InputError(path + ": cannot write an empty image (" + std::to_string(fb.width) + "x" +
                     std::to_string(fb.height) + ")");
  }
  const size_t pixels = static_cast<size_t>(fb.width) * fb.height;
  // A mis-sized buffer is a bug in the caller, not bad input.
  if (fb.color.size() != pixels * 4 || fb.depth.size() != pixels) {
    throw std::invalid_argument("Framebuffer buffers do not match its size");
  }
}

}  // namespace

const std::vector<float>* Image::find(const std::string& name) const {
  for (size_t i = 0; i < channel_names.size() && i < channels.size(); ++i) {
    if (channel_names[i] == name) return &channels[i];
  }
  return nullptr;
}

namespace {

// zlib level of frame.exr's ZIP blocks. OpenEXR 3.1 defaults to 4; level 2
// (zlib's fast matcher) writes a 4K frame's 100 MB of samples about 25%
// faster for a file about 10% larger (up to a third larger for flat frames).
// The level is not stored in the file: any OpenEXR reader decodes it.
constexpr int kExrZipLevel = 2;

// frame.png's deflate: zlib level 4 and the Up filter on every row. libpng's
// default (level 6, each row's best of the five filters by a heuristic) costs
// about four times as much for files only 3-30% smaller on gpusim's frames.
constexpr int kPngZlibLevel = 4;
constexpr int kPngFilters = PNG_FILTER_UP;

// Every stored colour channel value's half, or its 8-bit preview value: the
// same conversions as a per-sample call, looked up instead of recomputed.
std::vector<Imath::half> half_table(ColorFormat f) {
  std::vector<Imath::half> t(size_t{1} << 16);
  for (size_t v = 0; v < t.size(); ++v) {
    const auto c = static_cast<ColorChannel>(v);
    if (f == ColorFormat::rgba16f) {
      // The stored bits themselves: going through float would quiet
      // signalling NaNs and so change their bits.
      t[v].setBits(c);
    } else {
      t[v] = Imath::half(decode_color(f, c));
    }
  }
  return t;
}

std::vector<uint8_t> preview_table(ColorFormat f) {
  std::vector<uint8_t> t(size_t{1} << 16);
  for (size_t v = 0; v < t.size(); ++v) {
    const float c = clamp01(decode_color(f, static_cast<ColorChannel>(v)));
    t[v] = static_cast<uint8_t>(std::round(c * 255.0f));
  }
  return t;
}

}  // namespace

void write_frame_exr(const Framebuffer& fb, const std::string& path) {
  check_framebuffer(fb, path);
  const int w = fb.width;
  const int h = fb.height;
  const size_t pixels = static_cast<size_t>(w) * h;

  // Planar buffers in file order: file row r is framebuffer row h - 1 - r.
  const std::vector<Imath::half> to_half = half_table(fb.color_format);
  std::vector<Imath::half> rgba[4];
  for (auto& c : rgba) c.resize(pixels);
  std::vector<float> z(pixels);
  for (int r = 0; r < h; ++r) {
    const int y = h - 1 - r;
    const size_t row = static_cast<size_t>(r) * w;
    const ColorChannel* c = fb.color_at(0, y);
    for (int x = 0; x < w; ++x, c += 4) {
      for (int k = 0; k < 4; ++k) rgba[k][row + x] = to_half[c[k]];
    }
    const DepthValue* d = &fb.depth[fb.pixel_index(0, y)];
    float* zr = &z[row];
    for (int x = 0; x < w; ++x) zr[x] = decode_depth(fb.depth_format, d[x]);
  }

  OutputFiles files;
  const std::string temp = files.add(path);
  try {
    Imf::Header header(w, h);
    header.compression() = Imf::ZIP_COMPRESSION;  // lossless
    header.zipCompressionLevel() = kExrZipLevel;
    static const char* const kColorNames[4] = {"R", "G", "B", "A"};
    for (const char* name : kColorNames) header.channels().insert(name, Imf::Channel(Imf::HALF));
    header.channels().insert("Z", Imf::Channel(Imf::FLOAT));
    header.insert("gpusim:color_format",
                  Imf::StringAttribute(std::string(to_string(fb.color_format))));
    header.insert("gpusim:depth_format",
                  Imf::StringAttribute(std::string(to_string(fb.depth_format))));

    Imf::FrameBuffer frame;
    for (int k = 0; k < 4; ++k) {
      frame.insert(kColorNames[k], Imf::Slice(Imf::HALF, reinterpret_cast<char*>(rgba[k].data()),
                                              sizeof(Imath::half), sizeof(Imath::half) * w));
    }
    frame.insert("Z", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(z.data()), sizeof(float),
                                 sizeof(float) * w));
    // The file must be closed (OutputFile destroyed) before the rename.
    Imf::OutputFile out(temp.c_str(), header);
    out.setFrameBuffer(frame);
    out.writePixels(h);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(path + ": cannot write OpenEXR file: " + one_line(e.what()));
  }
  files.commit();
}

namespace {

// libpng's error message, copied out before its longjmp.
struct PngError {
  char message[256];
};

// libpng reports an error by calling this and must not return to it: it
// records the message and longjmps back to png_write_rgba8's setjmp.
[[noreturn]] void png_error_to_message(png_structp png, png_const_charp message) {
  auto* error = static_cast<PngError*>(png_get_error_ptr(png));
  std::snprintf(error->message, sizeof error->message, "%s", message);
  png_longjmp(png, 1);
}

void png_ignore_warning(png_structp, png_const_charp) {}

// The whole libpng write between setjmp and the last libpng call, in a frame
// with only trivially destructible locals, so the longjmp of an error skips
// no destructor and never crosses a C++ frame. Returns false with
// error->message set on failure.
bool png_write_rgba8(std::FILE* f, png_uint_32 width, png_uint_32 height, const uint8_t* rgba,
                     PngError* error) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, error, png_error_to_message,
                                            png_ignore_warning);
  if (png == nullptr) {
    std::snprintf(error->message, sizeof error->message, "out of memory");
    return false;
  }
  // Before the setjmp: neither call longjmps (the info struct's allocation
  // failure returns null), and no local changes between setjmp and longjmp.
  png_infop info = png_create_info_struct(png);
  if (info == nullptr) {
    png_destroy_write_struct(&png, nullptr);
    std::snprintf(error->message, sizeof error->message, "out of memory");
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_init_io(png, f);
  png_set_IHDR(png, info, width, height, 8, PNG_COLOR_TYPE_RGB_ALPHA, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  // The chunk libpng's simplified API wrote before: 8-bit samples are sRGB.
  png_set_sRGB(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
  png_set_compression_level(png, kPngZlibLevel);
  png_set_filter(png, PNG_FILTER_TYPE_BASE, kPngFilters);
  png_write_info(png, info);
  const size_t stride = static_cast<size_t>(width) * 4;
  for (png_uint_32 y = 0; y < height; ++y) png_write_row(png, rgba + y * stride);
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  return true;
}

}  // namespace

void write_png_rgba8(const std::string& path, int width, int height,
                     const std::vector<uint8_t>& rgba) {
  if (width <= 0 || height <= 0) {
    throw InputError(path + ": cannot write an empty image (" + std::to_string(width) + "x" +
                     std::to_string(height) + ")");
  }
  if (rgba.size() != static_cast<size_t>(width) * height * 4) {
    throw std::invalid_argument("write_png_rgba8: pixel buffer does not match the size");
  }
  OutputFiles files;
  const std::string temp = files.add(path);

  std::FILE* f = std::fopen(temp.c_str(), "wb");
  if (f == nullptr) throw InputError(path + ": cannot write: " + std::strerror(errno));
  PngError error{};
  const bool ok = png_write_rgba8(f, static_cast<png_uint_32>(width),
                                  static_cast<png_uint_32>(height), rgba.data(), &error);
  const bool closed = std::fclose(f) == 0;
  if (!ok) throw InputError(path + ": cannot write PNG file: " + one_line(error.message));
  if (!closed) throw InputError(path + ": cannot write: " + std::strerror(errno));
  files.commit();
}

void write_frame_png(const Framebuffer& fb, const std::string& path) {
  check_framebuffer(fb, path);
  const int w = fb.width;
  const int h = fb.height;
  const std::vector<uint8_t> to_preview = preview_table(fb.color_format);
  std::vector<uint8_t> rgba(static_cast<size_t>(w) * h * 4);
  for (int r = 0; r < h; ++r) {
    const int y = h - 1 - r;
    const ColorChannel* c = fb.color_at(0, y);
    uint8_t* out = &rgba[static_cast<size_t>(r) * w * 4];
    for (size_t i = 0; i < static_cast<size_t>(w) * 4; ++i) out[i] = to_preview[c[i]];
  }
  write_png_rgba8(path, w, h, rgba);
}

namespace {

void check_regular_file(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(path + ": no such file");
  if (!fs::is_regular_file(path, ec)) throw InputError(path + ": not a regular file");
}

// A corrupt header can claim an absurd size; refuse before allocating.
void check_size(const std::string& path, long long w, long long h, long long n_channels) {
  constexpr long long kMaxSamples = 1LL << 30;
  if (w > kMaxSamples || h > kMaxSamples || w * h > kMaxSamples / n_channels) {
    throw InputError(path + ": image too large (" + std::to_string(w) + "x" + std::to_string(h) +
                     ", " + std::to_string(n_channels) + " channels)");
  }
}

}  // namespace

Image read_exr(const std::string& path) {
  check_regular_file(path);
  Image img;
  try {
    if (!Imf::isOpenExrFile(path.c_str())) throw InputError(path + ": not an OpenEXR file");
    if (Imf::isDeepOpenExrFile(path.c_str())) {
      throw InputError(path + ": deep OpenEXR images are not supported");
    }
    // InputFile also reads tiled files (as scanlines) and the first part of a
    // multi-part file, converting HALF and UINT samples to FLOAT.
    Imf::InputFile in(path.c_str());
    const Imath::Box2i dw = in.header().dataWindow();
    const long long w = static_cast<long long>(dw.max.x) - dw.min.x + 1;
    const long long h = static_cast<long long>(dw.max.y) - dw.min.y + 1;
    if (w <= 0 || h <= 0) throw InputError(path + ": empty data window");
    const Imf::ChannelList& list = in.header().channels();
    long long n_channels = 0;
    for (auto it = list.begin(); it != list.end(); ++it) ++n_channels;
    if (n_channels == 0) throw InputError(path + ": no channels");
    check_size(path, w, h, n_channels);
    img.width = static_cast<int>(w);
    img.height = static_cast<int>(h);

    // Subsampled channels are read at their own resolution, then replicated to
    // full resolution so every channel is width * height.
    std::vector<std::vector<float>> sampled;
    std::vector<std::pair<int, int>> sampling;
    Imf::FrameBuffer frame;
    for (auto it = list.begin(); it != list.end(); ++it) {
      const int xs = it.channel().xSampling;
      const int ys = it.channel().ySampling;
      if (xs < 1 || ys < 1 || w % xs != 0 || h % ys != 0) {
        throw InputError(path + ": channel " + it.name() + " has invalid sampling");
      }
      img.channel_names.push_back(it.name());
      sampled.emplace_back(static_cast<size_t>(w / xs) * static_cast<size_t>(h / ys));
      sampling.emplace_back(xs, ys);
      frame.insert(it.name(),
                   Imf::Slice::Make(Imf::FLOAT, sampled.back().data(), dw, 0, 0, xs, ys));
    }
    in.setFrameBuffer(frame);
    in.readPixels(dw.min.y, dw.max.y);

    for (size_t c = 0; c < sampled.size(); ++c) {
      const auto [xs, ys] = sampling[c];
      if (xs == 1 && ys == 1) {
        img.channels.push_back(std::move(sampled[c]));
        continue;
      }
      const size_t sw = static_cast<size_t>(w / xs);
      std::vector<float> full(static_cast<size_t>(w) * h);
      for (long long y = 0; y < h; ++y) {
        for (long long x = 0; x < w; ++x) {
          full[static_cast<size_t>(y * w + x)] =
              sampled[c][static_cast<size_t>(y / ys) * sw + x / xs];
        }
      }
      img.channels.push_back(std::move(full));
    }
  } catch (const InputError&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw InputError(path + ": out of memory reading the image");
  } catch (const std::exception& e) {
    throw InputError(path + ": cannot read OpenEXR file: " + one_line(e.what()));
  }
  return img;
}

Image read_png(const std::string& path) {
  check_regular_file(path);
  // The simplified API, as in write_png_rgba8: its errors come back in
  // image.message, never as a longjmp through our frames.
  png_image image;
  std::memset(&image, 0, sizeof image);
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str())) {
    const std::string message = image.message;
    png_image_free(&image);
    throw InputError(path + ": cannot read PNG file: " + one_line(message));
  }
  if ((image.format & PNG_FORMAT_FLAG_LINEAR) != 0) {
    png_image_free(&image);
    // libpng would convert 16-bit samples to 8-bit sRGB or premultiply them.
    throw InputError(path + ": 16-bit PNG files are not supported (8-bit only)");
  }
  const bool alpha = (image.format & PNG_FORMAT_FLAG_ALPHA) != 0;
  const int n = alpha ? 4 : 3;
  try {
    check_size(path, image.width, image.height, n);
  } catch (const InputError&) {
    png_image_free(&image);
    throw;
  }
  image.format = alpha ? PNG_FORMAT_RGBA : PNG_FORMAT_RGB;
  std::vector<uint8_t> samples(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, samples.data(), 0, nullptr)) {
    const std::string message = image.message;
    png_image_free(&image);
    throw InputError(path + ": cannot read PNG file: " + one_line(message));
  }
  png_image_free(&image);
  Image img;
  img.png = true;
  img.width = static_cast<int>(image.width);
  img.height = static_cast<int>(image.height);
  const size_t pixels = static_cast<size_t>(img.width) * img.height;
  static const char* const kNames[4] = {"R", "G", "B", "A"};
  for (int c = 0; c < n; ++c) {
    img.channel_names.push_back(kNames[c]);
    std::vector<float> v(pixels);
    for (size_t i = 0; i < pixels; ++i) v[i] = samples[i * n + c] / 255.0f;
    img.channels.push_back(std::move(v));
  }
  return img;
}

Image read_image(const std::string& path) {
  check_regular_file(path);
  png_byte signature[8] = {};
  size_t got = 0;
  if (std::FILE* f = std::fopen(path.c_str(), "rb")) {
    got = std::fread(signature, 1, sizeof signature, f);
    std::fclose(f);
  } else {
    throw InputError(path + ": cannot read: " + std::strerror(errno));
  }
  if (got == sizeof signature && png_sig_cmp(signature, 0, sizeof signature) == 0) {
    return read_png(path);
  }
  if (got < sizeof signature || !Imf::isOpenExrFile(path.c_str())) {
    throw InputError(path + ": not an OpenEXR or PNG file");
  }
  return read_exr(path);
}

}  // namespace gpusim
