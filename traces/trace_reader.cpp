#include "traces/trace_reader.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "hw/input_error.h"

namespace gpusim {
namespace {

constexpr size_t kHeaderBytes = 16;
constexpr size_t kTransactionBytes = 48;
constexpr size_t kFragmentBytes = 48;
constexpr uint32_t kVersion = 1;  // of the binary record files
// Of manifest.json; 2: stages list their `inputs`, FIFOs their `kind`.
constexpr uint32_t kManifestVersion = 2;
// Records per read: 48 KiB buffers keep streaming cheap and memory flat.
constexpr size_t kChunkRecords = 1024;

// The manifest's fields, each failure naming the file and the JSON path.
class ManifestParser {
 public:
  explicit ManifestParser(std::string file) : m_file(std::move(file)) {}

  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw InputError(m_file + ": " + where + ": " + what);
  }
  const nlohmann::json& field(const nlohmann::json& j, const std::string& where,
                              const char* key) const {
    if (!j.is_object()) fail(where, "expected an object");
    const auto it = j.find(key);
    if (it == j.end()) fail(where.empty() ? key : where + "." + key, "missing");
    return *it;
  }
  std::string string(const nlohmann::json& j, const std::string& where) const {
    if (!j.is_string()) fail(where, "expected a string, got " + j.dump());
    return j.get<std::string>();
  }
  uint64_t unsigned_int(const nlohmann::json& j, const std::string& where) const {
    if (!j.is_number_unsigned()) fail(where, "expected a non-negative integer, got " + j.dump());
    return j.get<uint64_t>();
  }
  int64_t integer(const nlohmann::json& j, const std::string& where) const {
    if (!j.is_number_integer()) fail(where, "expected an integer, got " + j.dump());
    return j.get<int64_t>();
  }
  double number(const nlohmann::json& j, const std::string& where) const {
    if (!j.is_number()) fail(where, "expected a number, got " + j.dump());
    return j.get<double>();
  }
  const nlohmann::json& array(const nlohmann::json& j, const std::string& where,
                              const char* key) const {
    const nlohmann::json& a = field(j, where, key);
    if (!a.is_array()) fail(where.empty() ? key : where + "." + key, "expected an array");
    return a;
  }
  // The strings of array `key` of `j`.
  std::vector<std::string> strings(const nlohmann::json& j, const std::string& where,
                                   const char* key) const {
    const nlohmann::json& a = array(j, where, key);
    std::vector<std::string> out;
    for (size_t k = 0; k < a.size(); ++k) {
      out.push_back(string(a[k], where + "." + key + "[" + std::to_string(k) + "]"));
    }
    return out;
  }
  // The `index` of entry i of a table the binary records index: it must be
  // the entry's position.
  size_t position(const nlohmann::json& entry, const std::string& where, size_t i) const {
    const uint64_t index = unsigned_int(field(entry, where, "index"), where + ".index");
    if (index != i) {
      fail(where + ".index", "is " + std::to_string(index) + ", expected " + std::to_string(i));
    }
    return i;
  }
  int optional_unit(const nlohmann::json& j, const std::string& where) const {
    if (j.is_null()) return -1;
    return static_cast<int>(unsigned_int(j, where));
  }

 private:
  std::string m_file;
};

std::string join(const std::vector<std::string>& v, const char* sep) {
  std::string out;
  for (size_t i = 0; i < v.size(); ++i) out += (i ? sep : "") + v[i];
  return out;
}

// The netlist's tables (hw/netlist_tables.h) at `where` ("" or "timing.netlist").
void read_netlist(const ManifestParser& p, const nlohmann::json& j, const std::string& where,
                  TraceManifest& m) {
  const std::string prefix = where.empty() ? "" : where + ".";
  const nlohmann::json& stages = p.array(j, where, "stages");
  for (size_t i = 0; i < stages.size(); ++i) {
    const std::string w = prefix + "stages[" + std::to_string(i) + "]";
    const nlohmann::json& s = stages[i];
    TraceStage st;
    st.index = p.position(s, w, i);
    st.name = p.string(p.field(s, w, "name"), w + ".name");
    st.kind = p.string(p.field(s, w, "kind"), w + ".kind");
    st.unit = p.optional_unit(p.field(s, w, "unit"), w + ".unit");
    st.inputs = p.strings(s, w, "inputs");
    st.outputs = p.strings(s, w, "outputs");
    if (s.contains("item")) st.item = p.string(s["item"], w + ".item");
    if (s.contains("drops")) {
      if (!s["drops"].is_object()) p.fail(w + ".drops", "expected an object");
      for (const auto& d : s["drops"].items()) {
        st.drops[d.key()] = p.string(d.value(), w + ".drops." + d.key());
      }
    }
    if (s.contains("fragments") && !s["fragments"].is_null()) {
      st.fragments = p.string(s["fragments"], w + ".fragments");
    }
    m.stages.push_back(std::move(st));
  }
  const nlohmann::json& fifos = p.array(j, where, "fifos");
  for (size_t i = 0; i < fifos.size(); ++i) {
    const std::string w = prefix + "fifos[" + std::to_string(i) + "]";
    const nlohmann::json& f = fifos[i];
    TraceFifo fi;
    fi.index = p.position(f, w, i);
    fi.name = p.string(p.field(f, w, "name"), w + ".name");
    fi.kind = p.string(p.field(f, w, "kind"), w + ".kind");
    fi.depth = p.unsigned_int(p.field(f, w, "depth"), w + ".depth");
    fi.writer = p.string(p.field(f, w, "writer"), w + ".writer");
    fi.reader = p.string(p.field(f, w, "reader"), w + ".reader");
    fi.unit = p.optional_unit(p.field(f, w, "unit"), w + ".unit");
    m.fifos.push_back(std::move(fi));
  }
}

TraceManifest parse_manifest(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file + ": cannot open: " + std::strerror(errno));
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file + ": not valid JSON: " + e.what());
  }
  const ManifestParser p(file);
  TraceManifest m;
  if (p.string(p.field(j, "", "format"), "format") != "gpusim-trace") {
    p.fail("format", "expected \"gpusim-trace\", got " + j["format"].dump());
  }
  const uint64_t version = p.unsigned_int(p.field(j, "", "version"), "version");
  if (version != kManifestVersion) {
    p.fail("version", std::to_string(version) + " (this reader knows version " +
                          std::to_string(kManifestVersion) + ")");
  }
  m.scene = p.string(p.field(j, "", "scene"), "scene");
  // Optional: traces written before --trace-formats have every format.
  if (j.is_object() && j.contains("formats")) {
    const nlohmann::json& formats = p.array(j, "", "formats");
    for (size_t i = 0; i < formats.size(); ++i) {
      const std::string where = "formats[" + std::to_string(i) + "]";
      const std::string f = p.string(formats[i], where);
      if (f != "vcd" && f != "timeline" && f != "transactions" && f != "fragments") {
        p.fail(where, "\"" + f + "\" is not vcd, timeline, transactions or fragments");
      }
      m.formats.push_back(f);
    }
  } else {
    m.formats = {"vcd", "timeline", "transactions", "fragments"};
  }
  m.config = p.field(j, "", "config");
  m.clock_mhz = p.number(p.field(j, "", "clock_mhz"), "clock_mhz");
  m.cycle_ps = p.unsigned_int(p.field(j, "", "cycle_ps"), "cycle_ps");
  m.cycles = p.unsigned_int(p.field(j, "", "cycles"), "cycles");
  const nlohmann::json& fb = p.field(j, "", "framebuffer");
  const auto fb_int = [&](const char* key) {
    return static_cast<int>(
        p.unsigned_int(p.field(fb, "framebuffer", key), std::string("framebuffer.") + key));
  };
  m.width = fb_int("width");
  m.height = fb_int("height");
  m.tile_size = fb_int("tile_size");
  m.tiles_x = fb_int("tiles_x");
  m.tiles_y = fb_int("tiles_y");
  m.units = static_cast<unsigned>(p.unsigned_int(p.field(j, "", "units"), "units"));

  const nlohmann::json& filters = p.field(j, "", "filters");
  const nlohmann::json& stages_filter = p.field(filters, "filters", "stages");
  if (!stages_filter.is_null()) {
    if (!stages_filter.is_array()) p.fail("filters.stages", "expected null or an array");
    std::vector<std::string> kept;
    for (size_t i = 0; i < stages_filter.size(); ++i) {
      kept.push_back(p.string(stages_filter[i], "filters.stages[" + std::to_string(i) + "]"));
    }
    m.filters.stages = kept;
  }
  const nlohmann::json& window = p.field(filters, "filters", "window");
  if (!window.is_null()) {
    if (!window.is_array() || window.size() != 2) {
      p.fail("filters.window", "expected null or [start, end], got " + window.dump());
    }
    std::pair<std::optional<uint64_t>, std::optional<uint64_t>> w;
    if (!window[0].is_null()) w.first = p.unsigned_int(window[0], "filters.window[0]");
    if (!window[1].is_null()) w.second = p.unsigned_int(window[1], "filters.window[1]");
    m.filters.window = w;
  }
  const nlohmann::json& prims = p.field(filters, "filters", "prims");
  if (!prims.is_null()) {
    if (!prims.is_array() || prims.size() != 2) {
      p.fail("filters.prims", "expected null or [a, b], got " + prims.dump());
    }
    m.filters.prims = std::make_pair(p.integer(prims[0], "filters.prims[0]"),
                                     p.integer(prims[1], "filters.prims[1]"));
  }

  read_netlist(p, j, "", m);
  const nlohmann::json& draws = p.array(j, "", "draws");
  for (size_t i = 0; i < draws.size(); ++i) {
    const std::string w = "draws[" + std::to_string(i) + "]";
    TraceManifest::Draw d;
    d.first_primitive_id =
        p.integer(p.field(draws[i], w, "first_primitive_id"), w + ".first_primitive_id");
    d.primitives = p.unsigned_int(p.field(draws[i], w, "primitives"), w + ".primitives");
    // Optional: traces written before lines and points lack them.
    if (draws[i].is_object() && draws[i].contains("primitive")) {
      d.primitive = p.string(p.field(draws[i], w, "primitive"), w + ".primitive");
    }
    if (draws[i].is_object() && draws[i].contains("polygon_mode")) {
      d.polygon_mode = p.string(p.field(draws[i], w, "polygon_mode"), w + ".polygon_mode");
    }
    m.draws.push_back(d);
  }
  const nlohmann::json& records = p.field(j, "", "records");
  m.transaction_records =
      p.unsigned_int(p.field(records, "records", "transactions"), "records.transactions");
  m.fragment_records =
      p.unsigned_int(p.field(records, "records", "fragments"), "records.fragments");
  return m;
}

// Checks a record file's header and length; returns nothing, throws on any
// mismatch with one line naming the file.
void check_record_file(const std::string& file, const char* magic, size_t record_size,
                       uint64_t expected_records) {
  std::ifstream in(file, std::ios::binary | std::ios::ate);
  if (!in) throw InputError(file + ": cannot open: " + std::strerror(errno));
  const uint64_t bytes = static_cast<uint64_t>(in.tellg());
  if (bytes < kHeaderBytes) {
    throw InputError(file + ": truncated: " + std::to_string(bytes) +
                     " bytes, shorter than the 16-byte header");
  }
  in.seekg(0);
  std::array<uint8_t, kHeaderBytes> h{};
  in.read(reinterpret_cast<char*>(h.data()), kHeaderBytes);
  if (!in) throw InputError(file + ": cannot read the header");
  if (std::memcmp(h.data(), magic, 8) != 0) {
    std::string got;
    for (int i = 0; i < 8; ++i) {
      const char c = static_cast<char>(h[i]);
      if (c >= 0x20 && c < 0x7F) {
        got += c;
      } else {
        char buf[8];
        std::snprintf(buf, sizeof buf, "\\x%02X", h[i]);
        got += buf;
      }
    }
    throw InputError(file + ": bad magic \"" + got + "\", expected \"" + magic + "\"");
  }
  uint32_t version = 0, size = 0;
  record_codec::Decoder d{h.data() + 8};
  d(version);
  d(size);
  if (version != kVersion) {
    throw InputError(file + ": version " + std::to_string(version) +
                     ", this reader knows version 1");
  }
  if (size != record_size) {
    throw InputError(file + ": record size " + std::to_string(size) + ", expected " +
                     std::to_string(record_size));
  }
  const uint64_t body = bytes - kHeaderBytes;
  if (body % record_size != 0) {
    throw InputError(file + ": truncated: " + std::to_string(body) +
                     " bytes after the header is not a whole number of " +
                     std::to_string(record_size) + "-byte records");
  }
  if (body / record_size != expected_records) {
    throw InputError(file + ": holds " + std::to_string(body / record_size) +
                     " records, manifest.json says " + std::to_string(expected_records) +
                     (body / record_size < expected_records ? " (truncated)" : ""));
  }
}

}  // namespace

void read_netlist(const nlohmann::json& netlist, const std::string& source,
                  const std::string& where, TraceManifest& m) {
  read_netlist(ManifestParser(source), netlist, where, m);
}

std::string TraceFilters::describe() const {
  std::vector<std::string> parts;
  if (stages) parts.push_back("--trace-stages " + join(*stages, ","));
  if (window) {
    parts.push_back("--trace-window " +
                    (window->first ? std::to_string(*window->first) : std::string()) + ":" +
                    (window->second ? std::to_string(*window->second) : std::string()));
  }
  if (prims) {
    parts.push_back("--trace-prims " + std::to_string(prims->first) + ":" +
                    std::to_string(prims->second));
  }
  return parts.empty() ? "none" : join(parts, " ");
}

bool TraceFilters::keeps_stage(const std::string& name) const {
  return !stages || std::find(stages->begin(), stages->end(), name) != stages->end();
}

std::pair<uint64_t, uint64_t> TraceManifest::window() const {
  uint64_t start = 0, end = cycles;
  if (filters.window) {
    if (filters.window->first) start = std::min(*filters.window->first, cycles);
    if (filters.window->second) end = std::min(*filters.window->second, cycles);
  }
  return {start, std::max(start, end)};
}

uint64_t TraceManifest::primitives() const {
  uint64_t n = 0;
  for (const Draw& d : draws) {
    n = std::max<uint64_t>(n, static_cast<uint64_t>(d.first_primitive_id) + d.primitives);
  }
  return n;
}

int64_t TraceManifest::draw_of(int64_t prim) const {
  for (size_t i = 0; i < draws.size(); ++i) {
    const Draw& d = draws[i];
    if (prim >= d.first_primitive_id &&
        static_cast<uint64_t>(prim - d.first_primitive_id) < d.primitives) {
      return static_cast<int64_t>(i);
    }
  }
  return -1;
}

std::string TraceManifest::prim_word(int64_t prim) const {
  const int64_t i = draw_of(prim);
  if (i < 0) return "primitive";
  const std::string& t = draws[static_cast<size_t>(i)].primitive;
  if (t == "points") return "point";
  if (t == "lines" || t == "line_strip" || t == "line_loop") return "line";
  if (t.rfind("triangle", 0) == 0) return "triangle";
  return "primitive";  // a trace written before the field
}

const TraceStage* TraceManifest::stage(const std::string& name) const {
  for (const TraceStage& s : stages) {
    if (s.name == name) return &s;
  }
  return nullptr;
}

const TraceFifo* TraceManifest::fifo(const std::string& name) const {
  for (const TraceFifo& f : fifos) {
    if (f.name == name) return &f;
  }
  return nullptr;
}

int TraceManifest::pipeline_rank(const std::string& kind) const {
  for (size_t i = 0; i < stages.size(); ++i) {
    if (stages[i].kind == kind) return static_cast<int>(i);
  }
  return static_cast<int>(stages.size());
}

std::vector<std::string> TraceManifest::unit_kinds() const {
  std::vector<std::string> kinds;
  for (const TraceStage& s : stages) {
    if (s.unit == 0) kinds.push_back(s.kind);
  }
  return kinds;
}

// A directory without manifest.json is not a trace; the likeliest mix-up,
// a run's --out directory (stats.json, frame.exr), is named as such. The
// same words as scripts/gpusim_trace.py's Trace.
static void check_trace_directory(const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(dir, ec);
  if (!fs::exists(st)) throw InputError(dir + ": no such directory");
  if (!fs::is_directory(st)) throw InputError(dir + ": not a directory");
  if (fs::exists(fs::path(dir) / "manifest.json", ec)) return;
  std::string what = dir +
                     ": not a trace directory (no manifest.json; write one with gpusim run SCENE "
                     "--trace DIR)";
  if (fs::exists(fs::path(dir) / "stats.json", ec) || fs::exists(fs::path(dir) / "frame.exr", ec))
    what += " (this looks like a run's --out directory)";
  throw InputError(what);
}

TraceReader::TraceReader(const std::string& dir) : m_dir(dir) {
  while (m_dir.size() > 1 && m_dir.back() == '/') m_dir.pop_back();
  check_trace_directory(m_dir);
  m_manifest = parse_manifest(path("manifest.json"));
  if (m_manifest.recorded("transactions")) {
    check_record_file(path("transactions.bin"), "GPUSIMTX", kTransactionBytes,
                      m_manifest.transaction_records);
  }
  if (m_manifest.recorded("fragments")) {
    check_record_file(path("fragments.bin"), "GPUSIMFR", kFragmentBytes,
                      m_manifest.fragment_records);
  }
}

bool TraceManifest::recorded(const std::string& format) const {
  return std::find(formats.begin(), formats.end(), format) != formats.end();
}

void TraceReader::require(const std::string& format) const {
  if (m_manifest.recorded(format)) return;
  const std::string file = format == "vcd"        ? "signals.vcd"
                           : format == "timeline" ? "timeline.json"
                                                  : format + ".bin";
  throw InputError(m_dir + ": " + file + " was not recorded (--trace-formats " +
                   join(m_manifest.formats, ",") + "); rerun gpusim run --trace with " + format +
                   " in --trace-formats");
}

void TraceReader::for_each_record(const std::string& file, uint64_t count, size_t size,
                                  const std::function<void(const uint8_t*, uint64_t)>& fn) const {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file + ": cannot open: " + std::strerror(errno));
  in.seekg(kHeaderBytes);
  std::vector<uint8_t> chunk(kChunkRecords * size);
  for (uint64_t done = 0; done < count;) {
    const uint64_t n = std::min<uint64_t>(kChunkRecords, count - done);
    in.read(reinterpret_cast<char*>(chunk.data()), static_cast<std::streamsize>(n * size));
    // The length was checked on open; a short read means the file changed.
    if (!in) throw InputError(file + ": truncated while reading record " + std::to_string(done));
    for (uint64_t i = 0; i < n; ++i) fn(chunk.data() + i * size, done + i);
    done += n;
  }
}

void TraceReader::for_each_transaction(
    const std::function<void(const TransactionRecord&)>& fn) const {
  require("transactions");
  const std::string file = path("transactions.bin");
  const size_t stages = m_manifest.stages.size();
  for_each_record(
      file, m_manifest.transaction_records, kTransactionBytes, [&](const uint8_t* p, uint64_t i) {
        const TransactionRecord r = decode<TransactionRecord>(p);
        if (r.stage >= stages || r.kind > TransactionRecord::end_of_frame) {
          throw InputError(file + ": record " + std::to_string(i) + ": " +
                           (r.stage >= stages
                                ? "stage " + std::to_string(r.stage) +
                                      " is not in manifest.json's " + std::to_string(stages) +
                                      " stages"
                                : "kind " + std::to_string(r.kind) + " is not 0, 1 or 2"));
        }
        if (r.prim_kind > TransactionRecord::prim_triangle) {
          throw InputError(file + ": record " + std::to_string(i) + ": primitive kind " +
                           std::to_string(r.prim_kind) + " is not 0, 1, 2 or 3");
        }
        fn(r);
      });
}

void TraceReader::for_each_fragment(const std::function<void(const FragmentRecord&)>& fn) const {
  require("fragments");
  const std::string file = path("fragments.bin");
  for_each_record(file, m_manifest.fragment_records, kFragmentBytes,
                  [&](const uint8_t* p, uint64_t i) {
                    const FragmentRecord r = decode<FragmentRecord>(p);
                    if (r.stage > FragmentRecord::at_write) {
                      throw InputError(file + ": record " + std::to_string(i) + ": stage " +
                                       std::to_string(r.stage) + " is not 0 or 1");
                    }
                    fn(r);
                  });
}

nlohmann::json TraceReader::stats() const {
  const std::string file = path("stats.json");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file + ": cannot open: " + std::strerror(errno));
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file + ": not valid JSON: " + e.what());
  }
}

}  // namespace gpusim
