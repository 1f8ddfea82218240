#include "testbench/io/image_compare.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "hw/input_error.h"
#include "hw/pixel_formats.h"

namespace gpusim {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::string size_text(const Image& i) {
  return std::to_string(i.width) + "x" + std::to_string(i.height);
}

std::string names_text(std::vector<std::string> names) {
  std::sort(names.begin(), names.end());
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ",") + n;
  return s.empty() ? "(none)" : s;
}

void check_image(const Image& i) {
  // Images come from read_exr or from code; a malformed one is a bug.
  if (i.width < 0 || i.height < 0 || i.channel_names.size() != i.channels.size()) {
    throw std::invalid_argument("malformed Image");
  }
  for (const auto& c : i.channels) {
    if (c.size() != static_cast<size_t>(i.width) * i.height) {
      throw std::invalid_argument("Image channel does not match its size");
    }
  }
}

// |a - b| with the NaN and infinity rules of CompareResult, in double so that
// the difference of two large floats does not overflow.
double abs_error(float a, float b) {
  const bool na = std::isnan(a);
  const bool nb = std::isnan(b);
  if (na || nb) return na && nb ? 0.0 : kInf;
  if (a == b) return 0.0;  // also equal infinities, whose difference is NaN
  return std::fabs(static_cast<double>(a) - static_cast<double>(b));
}

bool channel_differs(float a, float b, double error, double tolerance, bool exact) {
  if (exact) {
    if (std::isnan(a) && std::isnan(b)) return false;
    return bits_from_float(a) != bits_from_float(b);
  }
  return error > tolerance;
}

// The pairing of a's and b's channels and the tolerance of each, validated.
struct Plan {
  std::vector<const std::vector<float>*> a;
  std::vector<const std::vector<float>*> b;
  std::vector<double> tolerance;
};

Plan make_plan(const Image& a, const Image& b, const CompareOptions& options,
               const std::string& a_name, const std::string& b_name) {
  check_image(a);
  check_image(b);
  if (a.width != b.width || a.height != b.height) {
    throw InputError(a_name + " and " + b_name + " differ in size: " + size_text(a) + " vs " +
                     size_text(b));
  }
  const std::string a_names = names_text(a.channel_names);
  const std::string b_names = names_text(b.channel_names);
  if (a_names != b_names) {
    throw InputError(a_name + " and " + b_name + " differ in channels: " + a_names + " vs " +
                     b_names);
  }
  auto bad_tolerance = [](float t) { return !(t >= 0.0f); };  // also NaN
  if (bad_tolerance(options.default_tolerance)) {
    throw InputError("tolerance must be a non-negative number");
  }
  for (const auto& [name, t] : options.tolerance) {
    if (a.find(name) == nullptr) {
      throw InputError("tolerance given for channel " + name + ", which " + a_name + " and " +
                       b_name + " do not have (channels: " + a_names + ")");
    }
    if (bad_tolerance(t)) {
      throw InputError("tolerance for channel " + name + " must be a non-negative number");
    }
  }
  Plan plan;
  for (size_t c = 0; c < a.channel_names.size(); ++c) {
    const std::string& name = a.channel_names[c];
    plan.a.push_back(&a.channels[c]);
    plan.b.push_back(b.find(name));
    const auto it = options.tolerance.find(name);
    plan.tolerance.push_back(it != options.tolerance.end() ? it->second
                                                           : options.default_tolerance);
  }
  return plan;
}

// %.9g tells any two floats apart; tolerances, typed by a person, read
// better with the default 6 digits (1e-06 rather than 9.99999997e-07).
std::string number_text(double v, const char* format = "%.9g") {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

std::string pad(const std::string& s, size_t width) {
  return s.size() >= width ? s : s + std::string(width - s.size(), ' ');
}

}  // namespace

CompareResult compare_images(const Image& a, const Image& b, const CompareOptions& options,
                             const std::string& a_name, const std::string& b_name) {
  const Plan plan = make_plan(a, b, options, a_name, b_name);
  CompareResult r;
  r.width = a.width;
  r.height = a.height;
  r.exact = options.exact;
  const size_t nc = plan.a.size();
  for (size_t c = 0; c < nc; ++c) {
    ChannelDiff d;
    d.name = a.channel_names[c];
    d.tolerance = options.exact ? 0.0 : plan.tolerance[c];
    r.channels.push_back(d);
  }
  // Scan in window order (y up from the bottom row, which is the last file
  // row) so the first differing pixel found is the one to report.
  for (int wy = 0; wy < a.height; ++wy) {
    const size_t row = static_cast<size_t>(a.height - 1 - wy) * a.width;
    for (int x = 0; x < a.width; ++x) {
      const size_t i = row + x;
      bool pixel_differs = false;
      for (size_t c = 0; c < nc; ++c) {
        const float va = (*plan.a[c])[i];
        const float vb = (*plan.b[c])[i];
        const double e = abs_error(va, vb);
        ChannelDiff& d = r.channels[c];
        d.max_abs_error = std::max(d.max_abs_error, e);
        if (channel_differs(va, vb, e, plan.tolerance[c], options.exact)) {
          ++d.differing_pixels;
          pixel_differs = true;
        }
      }
      if (!pixel_differs) continue;
      ++r.differing_pixels;
      if (!r.has_first) {
        r.has_first = true;
        r.first_x = x;
        r.first_y = wy;
        for (size_t c = 0; c < nc; ++c) {
          r.first_a.push_back((*plan.a[c])[i]);
          r.first_b.push_back((*plan.b[c])[i]);
        }
      }
    }
  }
  const long long pixels = static_cast<long long>(a.width) * a.height;
  r.differing_share = pixels > 0 ? static_cast<double>(r.differing_pixels) / pixels : 0.0;
  return r;
}

void write_diff_heatmap(const Image& a, const Image& b, const std::string& png_path,
                        const CompareOptions& options) {
  const Plan plan = make_plan(a, b, options, "first image", "second image");
  const size_t pixels = static_cast<size_t>(a.width) * a.height;
  const size_t nc = plan.a.size();
  // Per pixel: -1 where it does not differ, else the largest channel error.
  std::vector<double> error(pixels, -1.0);
  double scale = 0.0;  // largest finite error among differing pixels
  for (size_t i = 0; i < pixels; ++i) {
    bool differs = false;
    double e_max = 0.0;
    for (size_t c = 0; c < nc; ++c) {
      const float va = (*plan.a[c])[i];
      const float vb = (*plan.b[c])[i];
      const double e = abs_error(va, vb);
      e_max = std::max(e_max, e);
      differs |= channel_differs(va, vb, e, plan.tolerance[c], options.exact);
    }
    if (!differs) continue;
    error[i] = e_max;
    if (std::isfinite(e_max)) scale = std::max(scale, e_max);
  }
  std::vector<uint8_t> rgba(pixels * 4, 0);
  for (size_t i = 0; i < pixels; ++i) {
    rgba[i * 4 + 3] = 255;
    if (error[i] < 0.0) continue;
    // t in [0, 1]: 0 is the smallest visible difference (blue, never black).
    const double t = std::isfinite(error[i]) && scale > 0.0 ? error[i] / scale : 1.0;
    double rgb[3];
    if (t < 0.5) {
      rgb[0] = 2.0 * t, rgb[1] = 0.0, rgb[2] = 1.0 - 2.0 * t;  // blue -> red
    } else {
      rgb[0] = 1.0, rgb[1] = 2.0 * t - 1.0, rgb[2] = 0.0;  // red -> yellow
    }
    for (int k = 0; k < 3; ++k) rgba[i * 4 + k] = static_cast<uint8_t>(std::lround(rgb[k] * 255.0));
  }
  write_png_rgba8(png_path, a.width, a.height, rgba);
}

void print_compare_report(std::ostream& os, const CompareResult& r, const std::string& a_path,
                          const std::string& b_path) {
  os << "compare " << a_path << " " << b_path << ": " << r.width << "x" << r.height << ", "
     << r.channels.size() << " channels" << (r.exact ? ", exact (bitwise)" : "") << "\n";
  size_t name_w = 7;  // "channel"
  for (const ChannelDiff& d : r.channels) name_w = std::max(name_w, d.name.size());
  name_w += 2;
  const size_t num_w = 16;
  os << pad("channel", name_w);
  if (!r.exact) os << pad("tolerance", num_w);
  os << pad("max abs error", num_w) << "differing pixels\n";
  for (const ChannelDiff& d : r.channels) {
    os << pad(d.name, name_w);
    if (!r.exact) os << pad(number_text(d.tolerance, "%g"), num_w);
    os << pad(number_text(d.max_abs_error), num_w) << d.differing_pixels << "\n";
  }
  const long long pixels = static_cast<long long>(r.width) * r.height;
  char share[32];
  std::snprintf(share, sizeof share, "%.4f%%", r.differing_share * 100.0);
  os << "differing pixels: " << r.differing_pixels << " of " << pixels << " (" << share << ")\n";
  if (r.has_first) {
    os << "first differing pixel: x=" << r.first_x << " y=" << r.first_y
       << " (window coordinates, origin lower left)\n";
    const size_t val_w = std::max<size_t>(num_w, a_path.size() + 2);
    os << "  " << pad("channel", name_w) << pad(a_path, val_w) << b_path << "\n";
    for (size_t c = 0; c < r.channels.size() && c < r.first_a.size() && c < r.first_b.size(); ++c) {
      os << "  " << pad(r.channels[c].name, name_w) << pad(number_text(r.first_a[c]), val_w)
         << number_text(r.first_b[c]) << "\n";
    }
  }
  os << (r.pass() ? "PASS" : "FAIL") << "\n";
}

}  // namespace gpusim
