#include "hw/gpu_config.h"

#include <filesystem>
#include <fstream>
#include <iostream>
#include <regex>
#include <sstream>
#include <stdexcept>

#include "hw/stage_spec.h"
#include "hw/texture_state.h"

namespace gpusim {
namespace {

// Upper bounds keep every product of the model (cycles x items, bytes x
// requests) far from overflow and catch typos such as a missing decimal point.
constexpr double kMaxClockMhz = 10000.0;
constexpr unsigned kMaxUnits = 64;
constexpr unsigned kMinTile = 8;
constexpr unsigned kMaxTile = 256;
constexpr unsigned kMaxFifoDepth = 65536;
constexpr unsigned kMaxStageCycles = 1000000;
constexpr unsigned kMaxMemoryLatency = 1000000;
constexpr unsigned kMaxBytesPerCycle = 65536;
constexpr unsigned kMaxChannels = 64;
constexpr unsigned kMaxInterleave = 1u << 20;
constexpr unsigned kMaxVertexCache = 65536;
constexpr unsigned kMaxTileCache = 1024;
constexpr uint64_t kMaxWatchdog = 1000000000000ull;

bool is_power_of_two(uint64_t v) {
  return v != 0 && (v & (v - 1)) == 0;
}

// A validation error, with the JSON path at fault and the problem apart so
// that gpu_config_with_overrides can name the override responsible.
class ConfigError : public InputError {
 public:
  ConfigError(const std::string& source, const std::string& path, const std::string& problem)
      : InputError(source + ": " + path + ": " + problem), path(path), problem(problem) {}
  std::string path, problem;
};

// Walks one JSON document, carrying the source name for error messages.
class Reader {
 public:
  explicit Reader(const std::string& source) : m_source(source) {}

  [[noreturn]] void fail(const std::string& path, const std::string& problem) const {
    throw ConfigError(m_source, path.empty() ? "(root)" : path, problem);
  }

  static std::string join(const std::string& path, const std::string& key) {
    return path.empty() ? key : path + "." + key;
  }

  void expect_object(const nlohmann::json& j, const std::string& path) const {
    if (!j.is_object()) fail(path, std::string("expected an object, got ") + j.type_name());
  }

  // Every key of `j` must be one of `known`; the error lists them, as the
  // scene loader's do.
  void check_keys(const nlohmann::json& j, const std::string& path,
                  const std::vector<std::string>& known) const {
    for (const auto& item : j.items()) {
      bool found = false;
      for (const auto& k : known) found = found || k == item.key();
      if (found) continue;
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      fail(join(path, item.key()), "unknown key (allowed: " + list + ")");
    }
  }

  uint64_t get_uint(const nlohmann::json& j, const std::string& path, uint64_t lo,
                    uint64_t hi) const {
    if (j.is_number_float()) fail(path, "expected an integer, got " + j.dump());
    if (!j.is_number_integer())
      fail(path, std::string("expected an integer, got ") + j.type_name());
    // Parsed non-negative numbers are number_unsigned, but ones built in C++
    // from an int are signed.
    if (j.is_number_unsigned() || j.get<int64_t>() >= 0) {
      const uint64_t v = j.get<uint64_t>();
      if (v >= lo && v <= hi) return v;
    }
    fail(path, j.dump() + " is out of range " + std::to_string(lo) + ".." + std::to_string(hi));
  }

  bool get_bool(const nlohmann::json& j, const std::string& path) const {
    if (!j.is_boolean()) fail(path, std::string("expected true or false, got ") + j.type_name());
    return j.get<bool>();
  }

  unsigned get_unsigned(const nlohmann::json& j, const std::string& path, unsigned lo,
                        unsigned hi) const {
    return static_cast<unsigned>(get_uint(j, path, lo, hi));
  }

 private:
  std::string m_source;
};

}  // namespace

// The stage and FIFO kinds are the registered stages' (hw/stage_spec.h): the
// stages linked into the program declare them, each in its own files.
std::vector<std::string> GpuConfig::stage_names() {
  std::vector<std::string> names;
  for (const StageSpec* s : StageRegistry::all()) names.push_back(s->kind);
  return names;
}

std::vector<std::string> GpuConfig::fifo_names() {
  return StageRegistry::fifo_kinds();
}

std::map<std::string, StageCost, std::less<>> GpuConfig::default_stage_costs() {
  std::map<std::string, StageCost, std::less<>> costs;
  for (const StageSpec* s : StageRegistry::all()) costs[s->kind] = s->cost;
  return costs;
}

const StageCost& GpuConfig::stage(std::string_view name) const {
  const auto it = stages.find(name);
  if (it == stages.end()) {
    throw std::invalid_argument("GpuConfig::stage: unknown stage '" + std::string(name) + "'");
  }
  return it->second;
}

unsigned GpuConfig::fifo_depth_of(std::string_view name) const {
  const auto it = fifo_depths.find(name);
  if (it != fifo_depths.end()) return it->second;
  for (const auto& n : fifo_names()) {
    if (n == name) return fifo_depth;
  }
  throw std::invalid_argument("GpuConfig::fifo_depth_of: unknown FIFO '" + std::string(name) + "'");
}

sc_core::sc_time GpuConfig::cycle() const {
  return sc_core::sc_time(1000.0 / clock_mhz, sc_core::SC_NS);
}

sc_core::sc_time GpuConfig::cycles(uint64_t n) const {
  return sc_core::sc_time::from_value(cycle().value() * n);
}

GpuConfig GpuConfig::baseline() {
  GpuConfig c;
  c.memory.channels = 1;
  c.memory.interleave_bytes = 256;
  c.surfaces = SurfaceConfig{false, 1024, false};
  c.compression.depth = c.compression.colour = false;
  c.hierarchical_z.enabled = false;
  c.tile_test_overlap = false;
  return c;
}

bool GpuConfig::operator==(const GpuConfig& o) const {
  if (clock_mhz != o.clock_mhz || units != o.units || tile_size != o.tile_size ||
      stamp != o.stamp || fifo_depth != o.fifo_depth || stages != o.stages || memory != o.memory ||
      surfaces != o.surfaces || compression != o.compression ||
      vertex_cache_entries != o.vertex_cache_entries ||
      tile_cache_entries != o.tile_cache_entries || samples_per_pass != o.samples_per_pass ||
      tile_test_overlap != o.tile_test_overlap ||
      lighting_cycles_per_pixel != o.lighting_cycles_per_pixel ||
      lighting_cycles_per_light != o.lighting_cycles_per_light ||
      watchdog_cycles != o.watchdog_cycles || hierarchical_z != o.hierarchical_z ||
      texture != o.texture) {
    return false;
  }
  for (const auto& n : fifo_names()) {
    if (fifo_depth_of(n) != o.fifo_depth_of(n)) return false;
  }
  return true;
}

GpuConfig gpu_config_from_json(const nlohmann::json& j, const std::string& source_name) {
  const Reader r(source_name);
  GpuConfig c;
  r.expect_object(j, "");
  r.check_keys(
      j, "",
      {"clock_mhz", "units", "tile_size", "stamp", "fifo_depth", "fifo_depths", "stages", "memory",
       "surfaces", "compression", "hierarchical_z", "texture", "vertex_cache_entries",
       "tile_cache_entries", "samples_per_pass", "tile_test_overlap", "lighting_cycles_per_pixel",
       "lighting_cycles_per_light", "watchdog_cycles"});

  if (j.contains("clock_mhz")) {
    const auto& v = j["clock_mhz"];
    if (!v.is_number()) r.fail("clock_mhz", std::string("expected a number, got ") + v.type_name());
    const double mhz = v.get<double>();
    if (!(mhz > 0.0 && mhz <= kMaxClockMhz)) {
      r.fail("clock_mhz", v.dump() + " is out of range (0, " +
                              std::to_string(static_cast<unsigned>(kMaxClockMhz)) + "]");
    }
    c.clock_mhz = mhz;
  }
  if (j.contains("units")) c.units = r.get_unsigned(j["units"], "units", 1, kMaxUnits);
  if (j.contains("tile_size")) {
    c.tile_size = r.get_unsigned(j["tile_size"], "tile_size", kMinTile, kMaxTile);
    if (!is_power_of_two(c.tile_size)) {
      r.fail("tile_size", std::to_string(c.tile_size) + " is not a power of two");
    }
  }
  if (j.contains("stamp")) {
    const auto& s = j["stamp"];
    if (!s.is_array() || s.size() != 2) r.fail("stamp", "expected an array of 2 integers");
    for (size_t i = 0; i < 2; ++i) {
      const std::string path = "stamp[" + std::to_string(i) + "]";
      const unsigned v = r.get_unsigned(s[i], path, 1, kMaxTile);
      if (!is_power_of_two(v)) r.fail(path, std::to_string(v) + " is not a power of two");
      // tile_size is read first; the default stamp fits the smallest tile.
      if (v > c.tile_size) {
        r.fail(path, std::to_string(v) + " exceeds tile_size " + std::to_string(c.tile_size));
      }
      c.stamp[i] = v;
    }
    // A stamp's coverage is one 64-bit mask (hw/packets.h).
    if (c.stamp[0] * c.stamp[1] > 64) {
      r.fail("stamp", std::to_string(c.stamp[0]) + "x" + std::to_string(c.stamp[1]) +
                          " has more than 64 pixels");
    }
  }
  if (j.contains("fifo_depth")) {
    c.fifo_depth = r.get_unsigned(j["fifo_depth"], "fifo_depth", 1, kMaxFifoDepth);
  }
  if (j.contains("fifo_depths")) {
    const auto& f = j["fifo_depths"];
    r.expect_object(f, "fifo_depths");
    r.check_keys(f, "fifo_depths", GpuConfig::fifo_names());
    for (const auto& item : f.items()) {
      c.fifo_depths[item.key()] =
          r.get_unsigned(item.value(), "fifo_depths." + item.key(), 1, kMaxFifoDepth);
    }
  }
  if (j.contains("stages")) {
    r.expect_object(j["stages"], "stages");
    // A renamed stage's former key is read as its current one.
    nlohmann::json st = nlohmann::json::object();
    for (const auto& item : j["stages"].items()) {
      std::string key = item.key();
      const std::string current = StageRegistry::current_name(key);
      if (!current.empty()) {
        if (j["stages"].contains(current)) {
          r.fail("stages." + key, "given together with stages." + current + ", its new name");
        }
        warn_former_name(source_name + ": stages", key, current);
        key = current;
      }
      st[key] = item.value();
    }
    r.check_keys(st, "stages", GpuConfig::stage_names());
    for (const auto& item : st.items()) {
      const std::string path = "stages." + item.key();
      const auto& s = item.value();
      r.expect_object(s, path);
      r.check_keys(s, path, {"ii", "latency"});
      StageCost& cost = c.stages[item.key()];
      if (s.contains("ii")) cost.ii = r.get_unsigned(s["ii"], path + ".ii", 1, kMaxStageCycles);
      if (s.contains("latency")) {
        cost.latency = r.get_unsigned(s["latency"], path + ".latency", 0, kMaxStageCycles);
      }
    }
  }
  if (j.contains("memory")) {
    const auto& m = j["memory"];
    r.expect_object(m, "memory");
    r.check_keys(m, "memory", {"latency", "bytes_per_cycle", "channels", "interleave_bytes"});
    if (m.contains("latency")) {
      c.memory.latency = r.get_unsigned(m["latency"], "memory.latency", 0, kMaxMemoryLatency);
    }
    if (m.contains("bytes_per_cycle")) {
      c.memory.bytes_per_cycle =
          r.get_unsigned(m["bytes_per_cycle"], "memory.bytes_per_cycle", 1, kMaxBytesPerCycle);
    }
    if (m.contains("channels")) {
      c.memory.channels = r.get_unsigned(m["channels"], "memory.channels", 1, kMaxChannels);
    }
    if (m.contains("interleave_bytes")) {
      c.memory.interleave_bytes =
          r.get_unsigned(m["interleave_bytes"], "memory.interleave_bytes", 32, kMaxInterleave);
      if (c.memory.interleave_bytes & (c.memory.interleave_bytes - 1)) {
        r.fail("memory.interleave_bytes",
               "must be a power of two, got " + std::to_string(c.memory.interleave_bytes));
      }
    }
  }
  if (j.contains("surfaces")) {
    const auto& s = j["surfaces"];
    r.expect_object(s, "surfaces");
    r.check_keys(s, "surfaces", {"tiled", "max_burst_bytes", "skip_overwritten_fill"});
    if (s.contains("tiled")) c.surfaces.tiled = r.get_bool(s["tiled"], "surfaces.tiled");
    if (s.contains("max_burst_bytes")) {
      c.surfaces.max_burst_bytes =
          r.get_unsigned(s["max_burst_bytes"], "surfaces.max_burst_bytes", 1, 1u << 24);
    }
    if (s.contains("skip_overwritten_fill")) {
      c.surfaces.skip_overwritten_fill =
          r.get_bool(s["skip_overwritten_fill"], "surfaces.skip_overwritten_fill");
    }
  }
  if (j.contains("compression")) {
    const auto& m = j["compression"];
    r.expect_object(m, "compression");
    r.check_keys(m, "compression",
                 {"depth", "colour", "compressor_latency", "decompressor_latency"});
    if (m.contains("depth")) c.compression.depth = r.get_bool(m["depth"], "compression.depth");
    if (m.contains("colour")) c.compression.colour = r.get_bool(m["colour"], "compression.colour");
    if (m.contains("compressor_latency")) {
      c.compression.compressor_latency = r.get_unsigned(
          m["compressor_latency"], "compression.compressor_latency", 0, kMaxStageCycles);
    }
    if (m.contains("decompressor_latency")) {
      c.compression.decompressor_latency = r.get_unsigned(
          m["decompressor_latency"], "compression.decompressor_latency", 0, kMaxStageCycles);
    }
  }
  // A compressed tile is one variable-size block: only a tiled layout has
  // one. The error names the key the file set: compression turned on, or
  // (compression being on by default) tiled surfaces turned off.
  if ((c.compression.depth || c.compression.colour) && !c.surfaces.tiled) {
    const auto set_on = [&](const char* k) {
      return j.contains("compression") && j["compression"].contains(k) &&
             j["compression"][k] == true;
    };
    if (set_on("depth") || set_on("colour")) {
      r.fail(set_on("depth") ? "compression.depth" : "compression.colour",
             "compression needs surfaces.tiled true");
    }
    r.fail("surfaces.tiled",
           "false needs compression.depth and compression.colour false (compression needs tiled "
           "surfaces)");
  }
  if (j.contains("hierarchical_z")) {
    const auto& h = j["hierarchical_z"];
    r.expect_object(h, "hierarchical_z");
    r.check_keys(h, "hierarchical_z", {"enabled", "access_latency", "update_latency"});
    if (h.contains("enabled")) {
      if (!h["enabled"].is_boolean()) {
        r.fail("hierarchical_z.enabled",
               std::string("expected true or false, got ") + h["enabled"].dump());
      }
      c.hierarchical_z.enabled = h["enabled"].get<bool>();
    }
    if (h.contains("access_latency")) {
      c.hierarchical_z.access_latency =
          r.get_unsigned(h["access_latency"], "hierarchical_z.access_latency", 0, kMaxStageCycles);
    }
    if (h.contains("update_latency")) {
      c.hierarchical_z.update_latency =
          r.get_unsigned(h["update_latency"], "hierarchical_z.update_latency", 0, kMaxStageCycles);
    }
  }
  if (j.contains("texture")) {
    const auto& t = j["texture"];
    r.expect_object(t, "texture");
    r.check_keys(t, "texture",
                 {"cache_sets", "cache_ways", "cache_line_bytes", "prefetch_fragments"});
    const auto power_of_two = [&](const char* key, unsigned lo, unsigned hi, unsigned& out) {
      if (!t.contains(key)) return;
      const std::string path = std::string("texture.") + key;
      out = r.get_unsigned(t[key], path, lo, hi);
      if (!is_power_of_two(out)) r.fail(path, std::to_string(out) + " is not a power of two");
    };
    power_of_two("cache_sets", 1, 4096, c.texture.cache_sets);
    // A line holds at least one texel of every format (4 bytes) and a texel
    // of 3 bytes straddles at most two lines.
    power_of_two("cache_line_bytes", 16, kMaxTextureCacheLine, c.texture.cache_line_bytes);
    if (t.contains("cache_ways")) {
      c.texture.cache_ways = r.get_unsigned(t["cache_ways"], "texture.cache_ways", 1, 64);
    }
    if (t.contains("prefetch_fragments")) {
      c.texture.prefetch_fragments =
          r.get_unsigned(t["prefetch_fragments"], "texture.prefetch_fragments", 1, 4096);
    }
  }
  if (j.contains("vertex_cache_entries")) {
    c.vertex_cache_entries =
        r.get_unsigned(j["vertex_cache_entries"], "vertex_cache_entries", 0, kMaxVertexCache);
  }
  if (j.contains("tile_cache_entries")) {
    c.tile_cache_entries =
        r.get_unsigned(j["tile_cache_entries"], "tile_cache_entries", 1, kMaxTileCache);
  }
  if (j.contains("samples_per_pass")) {
    c.samples_per_pass = r.get_unsigned(j["samples_per_pass"], "samples_per_pass", 1, 16);
  }
  if (j.contains("tile_test_overlap")) {
    c.tile_test_overlap = r.get_bool(j["tile_test_overlap"], "tile_test_overlap");
  }
  if (j.contains("lighting_cycles_per_pixel")) {
    c.lighting_cycles_per_pixel =
        r.get_unsigned(j["lighting_cycles_per_pixel"], "lighting_cycles_per_pixel", 0, 1024);
  }
  if (j.contains("lighting_cycles_per_light")) {
    c.lighting_cycles_per_light =
        r.get_unsigned(j["lighting_cycles_per_light"], "lighting_cycles_per_light", 0, 1024);
  }
  if (j.contains("watchdog_cycles")) {
    c.watchdog_cycles = r.get_uint(j["watchdog_cycles"], "watchdog_cycles", 1, kMaxWatchdog);
  }
  return c;
}

nlohmann::json load_gpu_config_json(const std::string& path) {
  // "-": standard input, named so in messages.
  const bool from_stdin = path == "-";
  const std::string name = from_stdin ? "standard input" : path;
  std::ostringstream text;
  if (from_stdin) {
    text << std::cin.rdbuf();
    if (std::cin.bad()) throw InputError(name + ": read error");
  } else {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) {
      throw InputError(path + ": is a directory, not a configuration file");
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path + ": cannot open file");
    text << in.rdbuf();
    if (in.bad()) throw InputError(path + ": read error");
  }
  const std::string& t = text.str();
  if (t.size() >= 2 && ((t[0] == '\xFE' && t[1] == '\xFF') || (t[0] == '\xFF' && t[1] == '\xFE'))) {
    throw InputError(name + ": is UTF-16 encoded; configuration files are UTF-8 JSON");
  }
  const size_t nul = t.find('\0');
  if (nul != std::string::npos) {
    throw InputError(name + ": byte " + std::to_string(nul) + " is NUL: not a JSON text file");
  }
  try {
    return nlohmann::json::parse(t, nullptr, /*allow_exceptions=*/true,
                                 /*ignore_comments=*/true);
  } catch (const nlohmann::json::parse_error& e) {
    // nlohmann's message reads "[json.exception.parse_error.101] parse error at
    // line L, column C: <message>"; keep the position and the message.
    static const std::regex pattern(R"(line (\d+), column (\d+): (.*))");
    std::smatch m;
    const std::string what = e.what();
    if (std::regex_search(what, m, pattern)) {
      throw InputError(name + ": line " + m[1].str() + ", column " + m[2].str() + ": " +
                       m[3].str());
    }
    throw InputError(name + ": byte " + std::to_string(e.byte) + ": " + what);
  }
}

GpuConfig load_gpu_config(const std::string& path) {
  return gpu_config_from_json(load_gpu_config_json(path), path == "-" ? "standard input" : path);
}

namespace {

// KEY=VALUE's key split at the dots; empty when malformed.
std::vector<std::string> override_key(const std::string& key) {
  std::vector<std::string> parts;
  size_t start = 0;
  for (;;) {
    const size_t dot = key.find('.', start);
    parts.push_back(key.substr(start, dot == std::string::npos ? std::string::npos : dot - start));
    if (parts.back().empty()) return {};
    if (dot == std::string::npos) return parts;
    start = dot + 1;
  }
}

// Whether an error at JSON path `error` (stages.clipper.ii, stamp[0]) is
// about the value set at dotted key `key`: the same, inside it, or one of
// the objects on its way.
bool override_concerns(const std::string& key, const std::string& error) {
  const auto starts = [](const std::string& s, const std::string& prefix) {
    return s.compare(0, prefix.size(), prefix) == 0;
  };
  return error == key || starts(error, key + ".") || starts(error, key + "[") ||
         starts(key, error + ".");
}

}  // namespace

void apply_config_override(nlohmann::json& j, const std::string& assignment,
                           const std::string& source) {
  const size_t eq = assignment.find('=');
  if (eq == std::string::npos) {
    throw InputError(source + ": expected KEY=VALUE, e.g. stages.primitive_setup.ii=2");
  }
  const std::string key = assignment.substr(0, eq);
  const std::string text = assignment.substr(eq + 1);
  const std::vector<std::string> parts = override_key(key);
  if (parts.empty()) {
    throw InputError(source + ": expected KEY=VALUE with KEY a dotted configuration key, e.g. " +
                     "stages.primitive_setup.ii=2");
  }
  nlohmann::json value = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (value.is_discarded()) value = text;  // not JSON: a string
  nlohmann::json* at = &j;
  for (size_t i = 0; i + 1 < parts.size(); ++i) {
    if (!at->is_object()) *at = nlohmann::json::object();
    at = &(*at)[parts[i]];
  }
  if (!at->is_object()) *at = nlohmann::json::object();
  (*at)[parts.back()] = std::move(value);
}

GpuConfig gpu_config_with_overrides(nlohmann::json base,
                                    const std::vector<ConfigOverride>& overrides) {
  if (!base.is_object()) base = nlohmann::json::object();
  for (const ConfigOverride& o : overrides) {
    apply_config_override(base, o.assignment, o.source);
  }
  try {
    return gpu_config_from_json(base, "overrides");
  } catch (const ConfigError& e) {
    std::string source;
    for (const ConfigOverride& o : overrides) {
      if (override_concerns(o.assignment.substr(0, o.assignment.find('=')), e.path)) {
        source = o.source;
      }
    }
    if (source.empty()) {
      for (const ConfigOverride& o : overrides) source += (source.empty() ? "" : " ") + o.source;
    }
    throw InputError(source + ": " + e.path + ": " + e.problem);
  }
}

namespace {

// Keys in the order of the file format (docs/gpu-config.md).
template <typename Json>
Json config_json(const GpuConfig& c) {
  Json j;
  j["clock_mhz"] = c.clock_mhz;
  j["units"] = c.units;
  j["tile_size"] = c.tile_size;
  j["stamp"] = {c.stamp[0], c.stamp[1]};
  j["fifo_depth"] = c.fifo_depth;
  Json depths = Json::object();
  for (const auto& n : GpuConfig::fifo_names()) depths[n] = c.fifo_depth_of(n);
  j["fifo_depths"] = depths;
  Json stages = Json::object();
  for (const auto& n : GpuConfig::stage_names()) {
    const StageCost& s = c.stage(n);
    stages[n] = {{"ii", s.ii}, {"latency", s.latency}};
  }
  j["stages"] = stages;
  j["memory"] = {{"latency", c.memory.latency},
                 {"bytes_per_cycle", c.memory.bytes_per_cycle},
                 {"channels", c.memory.channels},
                 {"interleave_bytes", c.memory.interleave_bytes}};
  j["surfaces"] = {{"tiled", c.surfaces.tiled},
                   {"max_burst_bytes", c.surfaces.max_burst_bytes},
                   {"skip_overwritten_fill", c.surfaces.skip_overwritten_fill}};
  j["compression"] = {{"depth", c.compression.depth},
                      {"colour", c.compression.colour},
                      {"compressor_latency", c.compression.compressor_latency},
                      {"decompressor_latency", c.compression.decompressor_latency}};
  j["hierarchical_z"] = {{"enabled", c.hierarchical_z.enabled},
                         {"access_latency", c.hierarchical_z.access_latency},
                         {"update_latency", c.hierarchical_z.update_latency}};
  j["texture"] = {{"cache_sets", c.texture.cache_sets},
                  {"cache_ways", c.texture.cache_ways},
                  {"cache_line_bytes", c.texture.cache_line_bytes},
                  {"prefetch_fragments", c.texture.prefetch_fragments}};
  j["vertex_cache_entries"] = c.vertex_cache_entries;
  j["tile_cache_entries"] = c.tile_cache_entries;
  j["samples_per_pass"] = c.samples_per_pass;
  j["tile_test_overlap"] = c.tile_test_overlap;
  j["lighting_cycles_per_pixel"] = c.lighting_cycles_per_pixel;
  j["lighting_cycles_per_light"] = c.lighting_cycles_per_light;
  j["watchdog_cycles"] = c.watchdog_cycles;
  return j;
}

}  // namespace

nlohmann::json to_json(const GpuConfig& c) {
  return config_json<nlohmann::json>(c);
}

nlohmann::ordered_json to_ordered_json(const GpuConfig& c) {
  return config_json<nlohmann::ordered_json>(c);
}

}  // namespace gpusim
