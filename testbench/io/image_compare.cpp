#include "testbench/io/image_compare.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "hw/pixel_formats.h"

namespace gpusim {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr const char* kColorChannels = "RGBA";
constexpr const char* kGroupLetters = "RGBAZ";

std::string size_text(const Image& i) {
  return std::to_string(i.width) + "x" + std::to_string(i.height);
}

std::string join(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ",") + n;
  return s.empty() ? "(none)" : s;
}

std::string names_text(std::vector<std::string> names) {
  std::sort(names.begin(), names.end());
  return join(names);
}

void check_image(const Image& i) {
  // Images come from read_image or from code; a malformed one is a bug.
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

bool bits_differ(float a, float b) {
  if (std::isnan(a) && std::isnan(b)) return false;
  return bits_from_float(a) != bits_from_float(b);
}

bool is_group(const std::string& name) {
  return name.size() > 1 && name.find_first_not_of(kGroupLetters) == std::string::npos;
}

// The compared channels of a and b, each with its thresholds, validated.
struct Plan {
  std::vector<std::string> names;
  std::vector<const std::vector<float>*> a;
  std::vector<const std::vector<float>*> b;
  std::vector<double> fail;
  std::vector<double> warn;
  std::vector<bool> color;  // R, G, B or A
  std::vector<std::string> only_in_a, only_in_b;
  bool exact = false;
};

void check_threshold(double v, const std::string& what) {
  if (!(v >= 0.0)) throw InputError(what + " must be a non-negative number");  // also NaN
}

Plan make_plan(const Image& a, const Image& b, const CompareOptions& options,
               const std::string& a_name, const std::string& b_name) {
  check_image(a);
  check_image(b);
  if (a.width != b.width || a.height != b.height) {
    throw ImageMismatch(a_name + " and " + b_name + " differ in size: " + size_text(a) + " vs " +
                        size_text(b));
  }
  Plan plan;
  plan.exact = options.exact;
  for (const std::string& name : a.channel_names) {
    (b.find(name) != nullptr ? plan.names : plan.only_in_a).push_back(name);
  }
  for (const std::string& name : b.channel_names) {
    if (a.find(name) == nullptr) plan.only_in_b.push_back(name);
  }
  const bool same_set = plan.only_in_a.empty() && plan.only_in_b.empty();
  if ((!same_set && !options.common_channels) || plan.names.empty()) {
    throw ImageMismatch(
        a_name + " and " + b_name + " differ in channels: " + names_text(a.channel_names) + " vs " +
        names_text(b.channel_names) + (plan.names.empty() ? " (none in common)" : ""));
  }
  check_threshold(options.fail, "fail threshold (--fail, --tolerance)");
  if (options.warn >= 0.0 || std::isnan(options.warn)) {
    check_threshold(options.warn, "warn threshold (--warn)");
  }
  for (const double p : {options.fail_percent, options.warn_percent}) {
    if (!(p >= 0.0 && p <= 100.0)) {
      throw InputError("--failpercent and --warnpercent must be between 0 and 100");
    }
  }
  check_threshold(options.hard_fail, "--hardfail");
  check_threshold(options.hard_warn, "--hardwarn");
  plan.fail.assign(plan.names.size(), options.fail);
  for (const auto& [name, value] : options.channel_fail) {
    check_threshold(value, "threshold for " + name);
    bool used = false;
    for (size_t c = 0; c < plan.names.size(); ++c) {
      const std::string& n = plan.names[c];
      if (n == name || (is_group(name) && n.size() == 1 && name.find(n[0]) != std::string::npos)) {
        plan.fail[c] = value;
        used = true;
      }
    }
    if (!used) {
      throw InputError("threshold given for channel " + name + ", which " + a_name + " and " +
                       b_name + " do not both have (channels compared: " + names_text(plan.names) +
                       ")");
    }
  }
  for (size_t c = 0; c < plan.names.size(); ++c) {
    const std::string& n = plan.names[c];
    plan.a.push_back(a.find(n));
    plan.b.push_back(b.find(n));
    plan.warn.push_back(options.warn >= 0.0 ? options.warn : plan.fail[c]);
    plan.color.push_back(n.size() == 1 && std::strchr(kColorChannels, n[0]) != nullptr);
  }
  return plan;
}

// One pixel (file index i): each channel's error and whether it fails or
// warns, and the pixel's largest error.
struct PixelErrors {
  std::vector<double> error;
  std::vector<bool> fails, warns;
  bool any_fails = false, any_warns = false;
  double max_error = 0.0;
};

void evaluate(const Plan& plan, size_t i, PixelErrors& p) {
  const size_t nc = plan.names.size();
  p.error.resize(nc);
  p.fails.resize(nc);
  p.warns.resize(nc);
  p.any_fails = p.any_warns = false;
  p.max_error = 0.0;
  for (size_t c = 0; c < nc; ++c) {
    const float va = (*plan.a[c])[i];
    const float vb = (*plan.b[c])[i];
    const double e = abs_error(va, vb);
    p.error[c] = e;
    p.max_error = std::max(p.max_error, e);
    if (plan.exact) {
      p.fails[c] = p.warns[c] = bits_differ(va, vb);
    } else {
      p.fails[c] = e > plan.fail[c];
      p.warns[c] = e > plan.warn[c];
    }
    p.any_fails = p.any_fails || p.fails[c];
    p.any_warns = p.any_warns || p.warns[c];
  }
}

// Sums of one channel or group while scanning.
struct Accumulator {
  double sum = 0.0, sum_sq = 0.0;
  long long values = 0;
  void add(double e, int x, int y, ErrorStats& s) {
    sum += e;
    sum_sq += e * e;
    ++values;
    if (e > s.max_error) {
      s.max_error = e;
      s.has_max = true;
      s.max_x = x;
      s.max_y = y;
    }
  }
  void finish(ErrorStats& s) const {
    if (values == 0) return;
    s.mean_error = sum / values;
    s.rms_error = std::sqrt(sum_sq / values);
    s.psnr = s.rms_error == 0.0 ? kInf : 20.0 * std::log10(1.0 / s.rms_error);
  }
};

// %.9g tells any two floats apart; thresholds, typed by a person, read
// better with the default 6 digits (1e-06 rather than 9.99999997e-07).
std::string number_text(double v, const char* format = "%.9g") {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

std::string pad(const std::string& s, size_t width) {
  return s.size() >= width ? s + " " : s + std::string(width - s.size(), ' ');
}

std::string percent_text(long long n, long long total) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4f%%", total > 0 ? 100.0 * n / total : 0.0);
  return buf;
}

}  // namespace

std::pair<std::string, double> parse_channel_threshold(const std::string& spec) {
  const size_t eq = spec.find('=');
  double value = 0.0;
  size_t used = 0;
  try {
    if (eq != std::string::npos) value = std::stod(spec.substr(eq + 1), &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (eq == std::string::npos || eq == 0 || used == 0 || used != spec.size() - eq - 1 ||
      !(value >= 0.0)) {
    throw InputError("--channel-tolerance " + spec +
                     ": expected CHANNEL=VALUE or GROUP=VALUE with VALUE >= 0, e.g. Z=1e-6 or "
                     "RGBA=0.004");
  }
  return {spec.substr(0, eq), value};
}

const char* to_string(Verdict v) {
  switch (v) {
    case Verdict::pass:
      return "PASS";
    case Verdict::warning:
      return "WARNING";
    case Verdict::failure:
      return "FAILURE";
  }
  return "?";
}

void heat_color(double t, uint8_t rgb[3]) {
  t = std::clamp(t, 0.0, 1.0);
  double v[3];
  if (t < 0.5) {
    v[0] = 2.0 * t, v[1] = 0.0, v[2] = 1.0 - 2.0 * t;  // blue -> red
  } else {
    v[0] = 1.0, v[1] = 2.0 * t - 1.0, v[2] = 0.0;  // red -> yellow
  }
  for (int k = 0; k < 3; ++k) rgb[k] = static_cast<uint8_t>(std::lround(v[k] * 255.0));
}

CompareResult compare_images(const Image& a, const Image& b, const CompareOptions& options,
                             const std::string& a_name, const std::string& b_name) {
  const Plan plan = make_plan(a, b, options, a_name, b_name);
  CompareResult r;
  r.width = a.width;
  r.height = a.height;
  r.exact = options.exact;
  r.only_in_a = plan.only_in_a;
  r.only_in_b = plan.only_in_b;
  r.fail_percent = options.fail_percent;
  r.warn_percent = options.warn_percent;
  r.hard_fail = options.hard_fail;
  r.hard_warn = options.hard_warn;
  const size_t nc = plan.names.size();
  for (size_t c = 0; c < nc; ++c) {
    ErrorStats s;
    s.name = plan.names[c];
    s.fail = plan.fail[c];
    s.warn = plan.warn[c];
    r.channels.push_back(s);
    if (plan.color[c]) r.has_color = true;
  }
  for (const char* l = kColorChannels; *l != '\0'; ++l) {
    if (std::find(plan.names.begin(), plan.names.end(), std::string(1, *l)) != plan.names.end()) {
      r.color.name += *l;
    }
  }
  std::vector<Accumulator> acc(nc);
  Accumulator color_acc;
  PixelErrors p;
  // Scan in window order (y up from the bottom row, which is the last file
  // row) so the first pixel found is the one to report.
  for (int wy = 0; wy < a.height; ++wy) {
    const size_t row = static_cast<size_t>(a.height - 1 - wy) * a.width;
    for (int x = 0; x < a.width; ++x) {
      const size_t i = row + x;
      evaluate(plan, i, p);
      bool color_fails = false, color_warns = false;
      for (size_t c = 0; c < nc; ++c) {
        ErrorStats& s = r.channels[c];
        acc[c].add(p.error[c], x, wy, s);
        s.failing_pixels += p.fails[c];
        s.warning_pixels += p.warns[c];
        if (plan.color[c]) {
          color_acc.add(p.error[c], x, wy, r.color);
          color_fails = color_fails || p.fails[c];
          color_warns = color_warns || p.warns[c];
        }
      }
      r.color.failing_pixels += color_fails;
      r.color.warning_pixels += color_warns;
      r.failing_pixels += p.any_fails;
      r.warning_pixels += p.any_warns;
      // The first failing pixel, else the first warning one.
      if ((p.any_fails && !r.first_fails) || (p.any_warns && !r.has_first)) {
        r.has_first = true;
        r.first_fails = p.any_fails;
        r.first_x = x;
        r.first_y = wy;
        r.first_a.clear();
        r.first_b.clear();
        for (size_t c = 0; c < nc; ++c) {
          r.first_a.push_back((*plan.a[c])[i]);
          r.first_b.push_back((*plan.b[c])[i]);
        }
      }
    }
  }
  double max_error = 0.0;
  for (size_t c = 0; c < nc; ++c) {
    acc[c].finish(r.channels[c]);
    max_error = std::max(max_error, r.channels[c].max_error);
  }
  color_acc.finish(r.color);
  // As idiff decides: more than the allowed share, or one error too large.
  const double pixels = static_cast<double>(a.width) * a.height;
  if (r.failing_pixels > options.fail_percent / 100.0 * pixels || max_error > options.hard_fail) {
    r.verdict = Verdict::failure;
  } else if (r.warning_pixels > options.warn_percent / 100.0 * pixels ||
             max_error > options.hard_warn) {
    r.verdict = Verdict::warning;
  }
  return r;
}

namespace {

// A 3x5 bitmap font for the legend's numbers: each glyph five rows of three
// bits, most significant bit leftmost.
const char kGlyphChars[] = "0123456789.-+e";
const uint8_t kGlyphs[][5] = {
    {7, 5, 5, 5, 7}, {2, 6, 2, 2, 7}, {7, 1, 7, 4, 7}, {7, 1, 7, 1, 7}, {5, 5, 7, 1, 1},
    {7, 4, 7, 1, 7}, {7, 4, 7, 5, 7}, {7, 1, 1, 1, 1}, {7, 5, 7, 5, 7}, {7, 5, 7, 1, 7},
    {0, 0, 0, 0, 2}, {0, 0, 7, 0, 0}, {0, 2, 7, 2, 0}, {7, 4, 7, 4, 7},
};
constexpr int kGlyphAdvance = 4;  // 3 columns and a blank one

int text_width(const std::string& s, int scale) {
  return s.empty() ? 0 : (static_cast<int>(s.size()) * kGlyphAdvance - 1) * scale;
}

// White text with its top left at (x, y) in an RGBA image `width` wide.
void draw_text(std::vector<uint8_t>& rgba, int width, int height, int x, int y,
               const std::string& s, int scale) {
  for (size_t k = 0; k < s.size(); ++k) {
    const char* at = std::strchr(kGlyphChars, s[k]);
    if (at == nullptr || *at == '\0') continue;
    const uint8_t* glyph = kGlyphs[at - kGlyphChars];
    for (int gy = 0; gy < 5 * scale; ++gy) {
      for (int gx = 0; gx < 3 * scale; ++gx) {
        if (!(glyph[gy / scale] & (4 >> (gx / scale)))) continue;
        const int px = x + static_cast<int>(k) * kGlyphAdvance * scale + gx;
        const int py = y + gy;
        if (px < 0 || px >= width || py < 0 || py >= height) continue;
        uint8_t* dst = &rgba[(static_cast<size_t>(py) * width + px) * 4];
        dst[0] = dst[1] = dst[2] = 255;
      }
    }
  }
}

}  // namespace

double write_diff_heatmap(const Image& a, const Image& b, const std::string& png_path,
                          const CompareOptions& options) {
  const Plan plan = make_plan(a, b, options, "first image", "second image");
  const int w = a.width;
  const size_t pixels = static_cast<size_t>(w) * a.height;
  // Per pixel: -1 where it does not fail, else the largest channel error.
  std::vector<double> error(pixels, -1.0);
  double scale = 0.0;  // largest finite error among failing pixels
  PixelErrors p;
  for (size_t i = 0; i < pixels; ++i) {
    evaluate(plan, i, p);
    if (!p.any_fails) continue;
    error[i] = p.max_error;
    if (std::isfinite(p.max_error)) scale = std::max(scale, p.max_error);
  }
  const int h = a.height + kLegendHeight;
  std::vector<uint8_t> rgba(static_cast<size_t>(w) * h * 4, 0);
  for (size_t i = 0; i < static_cast<size_t>(w) * h; ++i) rgba[i * 4 + 3] = 255;
  for (size_t i = 0; i < pixels; ++i) {
    if (error[i] < 0.0) continue;
    // t in [0, 1]: 0 is the smallest visible difference (blue, never black).
    heat_color(std::isfinite(error[i]) && scale > 0.0 ? error[i] / scale : 1.0, &rgba[i * 4]);
  }
  // Legend: the ramp across the width, then 0, max/2 and max under its ends
  // and middle, each drawn only where it fits without overlapping.
  for (int x = 0; x < w; ++x) {
    uint8_t rgb[3];
    heat_color(w > 1 ? static_cast<double>(x) / (w - 1) : 1.0, rgb);
    for (int y = 0; y < kLegendBarHeight; ++y) {
      std::memcpy(&rgba[(static_cast<size_t>(a.height + kLegendBarTop + y) * w + x) * 4], rgb, 3);
    }
  }
  const std::string lo = "0", mid = number_text(scale / 2.0, "%.3g"),
                    hi = number_text(scale, "%.3g");
  const int text_y = a.height + kLegendBarTop + kLegendBarHeight + 2;
  // How many labels fit at a text scale: 3 (all), 2 (the ends) or 0.
  auto labels_fitting = [&](int ts) {
    const int lo_w = text_width(lo, ts), mid_w = text_width(mid, ts), hi_w = text_width(hi, ts);
    const int gap = kGlyphAdvance * ts, mid_x = (w - mid_w) / 2;
    if (lo_w + gap + hi_w > w) return 0;
    return mid_x >= lo_w + gap && mid_x + mid_w + gap <= w - hi_w ? 3 : 2;
  };
  // The most labels, then the larger text.
  int text_scale = 2;
  if (labels_fitting(1) > labels_fitting(2)) text_scale = 1;
  const int n_labels = labels_fitting(text_scale);
  if (n_labels >= 2) {
    draw_text(rgba, w, h, 0, text_y, lo, text_scale);
    draw_text(rgba, w, h, w - text_width(hi, text_scale), text_y, hi, text_scale);
  }
  if (n_labels == 3) {
    draw_text(rgba, w, h, (w - text_width(mid, text_scale)) / 2, text_y, mid, text_scale);
  }
  write_png_rgba8(png_path, w, h, rgba);
  return scale;
}

void print_compare_report(std::ostream& os, const CompareResult& r, const std::string& a_path,
                          const std::string& b_path) {
  std::vector<std::string> names;
  for (const ErrorStats& s : r.channels) names.push_back(s.name);
  os << "compare " << a_path << " " << b_path << ": " << r.width << "x" << r.height
     << ", channels compared: " << join(names);
  if (!r.only_in_a.empty()) os << "; only in " << a_path << ": " << join(r.only_in_a);
  if (!r.only_in_b.empty()) os << "; only in " << b_path << ": " << join(r.only_in_b);
  os << (r.exact ? "; exact (bitwise)" : "") << "\n";
  size_t name_w = 7;  // "channel"
  for (const std::string& n : names) name_w = std::max(name_w, n.size());
  if (r.has_color) name_w = std::max(name_w, r.color.name.size());
  name_w += 2;
  os << pad("channel", name_w) << pad("fail", 9) << pad("warn", 9) << pad("max error", 15)
     << pad("at x,y", 9) << pad("mean error", 13) << pad("RMS error", 13) << pad("PSNR dB", 8)
     << pad("failing", 8) << "warning\n";
  auto row = [&](const ErrorStats& s, bool group) {
    os << pad(s.name, name_w)
       << pad(group     ? "-"
              : r.exact ? "bits"
                        : number_text(s.fail, "%g"),
              9)
       << pad(group     ? "-"
              : r.exact ? "bits"
                        : number_text(s.warn, "%g"),
              9)
       << pad(number_text(s.max_error), 15)
       << pad(s.has_max ? std::to_string(s.max_x) + "," + std::to_string(s.max_y) : "-", 9)
       << pad(number_text(s.mean_error, "%.6g"), 13) << pad(number_text(s.rms_error, "%.6g"), 13)
       << pad(number_text(s.psnr, "%.2f"), 8) << pad(std::to_string(s.failing_pixels), 8)
       << s.warning_pixels << "\n";
  };
  for (const ErrorStats& s : r.channels) row(s, false);
  if (r.has_color) row(r.color, true);
  const long long pixels = static_cast<long long>(r.width) * r.height;
  os << "failing pixels: " << r.failing_pixels << " of " << pixels << " ("
     << percent_text(r.failing_pixels, pixels) << "), FAILURE above "
     << number_text(r.fail_percent, "%g") << "% (--failpercent)";
  if (std::isfinite(r.hard_fail)) os << " or any error above " << number_text(r.hard_fail, "%g");
  os << "\nwarning pixels: " << r.warning_pixels << " of " << pixels << " ("
     << percent_text(r.warning_pixels, pixels) << "), WARNING above "
     << number_text(r.warn_percent, "%g") << "% (--warnpercent)";
  if (std::isfinite(r.hard_warn)) os << " or any error above " << number_text(r.hard_warn, "%g");
  os << "\n";
  if (r.has_first) {
    os << "first " << (r.first_fails ? "failing" : "warning") << " pixel: x=" << r.first_x
       << " y=" << r.first_y << " (window coordinates, origin lower left)\n";
    const size_t val_w = std::max<size_t>(16, a_path.size() + 1);
    os << "  " << pad("channel", name_w) << pad(a_path, val_w) << b_path << "\n";
    for (size_t c = 0; c < r.channels.size() && c < r.first_a.size() && c < r.first_b.size(); ++c) {
      os << "  " << pad(r.channels[c].name, name_w) << pad(number_text(r.first_a[c]), val_w)
         << number_text(r.first_b[c]) << "\n";
    }
  }
  os << to_string(r.verdict) << "\n";
}

}  // namespace gpusim
