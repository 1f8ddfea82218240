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

void write_frame_exr(const Framebuffer& fb, const std::string& path) {
  check_framebuffer(fb, path);
  const int w = fb.width;
  const int h = fb.height;
  const size_t pixels = static_cast<size_t>(w) * h;

  // Planar buffers in file order: file row r is framebuffer row h - 1 - r.
  std::vector<Imath::half> rgba[4];
  for (auto& c : rgba) c.resize(pixels);
  std::vector<float> z(pixels);
  for (int r = 0; r < h; ++r) {
    const int y = h - 1 - r;
    for (int x = 0; x < w; ++x) {
      const size_t i = static_cast<size_t>(r) * w + x;
      const ColorChannel* c = fb.color_at(x, y);
      for (int k = 0; k < 4; ++k) {
        if (fb.color_format == ColorFormat::rgba16f) {
          // The stored bits themselves: going through float would quiet
          // signalling NaNs and so change their bits.
          rgba[k][i].setBits(c[k]);
        } else {
          rgba[k][i] = Imath::half(decode_color(fb.color_format, c[k]));
        }
      }
      z[i] = decode_depth(fb.depth_format, fb.depth[fb.pixel_index(x, y)]);
    }
  }

  OutputFiles files;
  const std::string temp = files.add(path);
  try {
    Imf::Header header(w, h);
    header.compression() = Imf::ZIP_COMPRESSION;  // lossless
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
  // libpng's simplified API catches its own errors (its internal setjmp never
  // crosses our frames) and reports them in image.message, so no longjmp or
  // exception ever unwinds through C code.
  png_image image;
  std::memset(&image, 0, sizeof image);
  image.version = PNG_IMAGE_VERSION;
  image.width = static_cast<png_uint_32>(width);
  image.height = static_cast<png_uint_32>(height);
  image.format = PNG_FORMAT_RGBA;
  const int ok = png_image_write_to_stdio(&image, f, 0, rgba.data(), 0, nullptr);
  const std::string message = image.message;
  png_image_free(&image);
  const bool closed = std::fclose(f) == 0;
  if (!ok) throw InputError(path + ": cannot write PNG file: " + one_line(message));
  if (!closed) throw InputError(path + ": cannot write: " + std::strerror(errno));
  files.commit();
}

void write_frame_png(const Framebuffer& fb, const std::string& path) {
  check_framebuffer(fb, path);
  const int w = fb.width;
  const int h = fb.height;
  std::vector<uint8_t> rgba(static_cast<size_t>(w) * h * 4);
  for (int r = 0; r < h; ++r) {
    const int y = h - 1 - r;
    for (int x = 0; x < w; ++x) {
      const ColorChannel* c = fb.color_at(x, y);
      for (int k = 0; k < 4; ++k) {
        const float v = clamp01(decode_color(fb.color_format, c[k]));
        rgba[(static_cast<size_t>(r) * w + x) * 4 + k] =
            static_cast<uint8_t>(std::round(v * 255.0f));
      }
    }
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
