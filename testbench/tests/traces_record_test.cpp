// Recording traces (docs/traces.md): every file parses, and what it says
// agrees with stats.json, which the stages count on their own: the busy,
// stalled and starved time integrated from signals.vcd, the records per
// stage in transactions.bin, the fragments per depth test and ROP in
// fragments.bin, and the last value each pixel got in fragments.bin against
// the frame. Filters only remove records; tracing changes no cycle and no
// pixel; two traced runs give the same bytes; a failed run leaves nothing.
//
// The files are read here with code of this test's own, not the trace reader,
// so a mistake shared by the writer and the reader cannot hide.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "hw/input_error.h"
#include "hw/pixel_formats.h"
#include "testbench/io/output_file.h"
#include "testbench/scene/scene.h"
#include "testbench/sim/gpu_run.h"
#include "testbench/tests/file_bytes.h"

namespace gpusim {
namespace {

namespace fs = std::filesystem;

std::string scene_path(const std::string& name) {
  return std::string(GPUSIM_SOURCE_DIR) + "/testbench/scenes/" + name + ".json";
}

struct Filters {
  std::string stages, window, prims;
};

// A traced run of `scene` into `dir`, its files committed.
GpuRunResult traced_run(const std::string& scene, const fs::path& dir, const Filters& f = {},
                        const GpuConfig& config = GpuConfig{}) {
  OutputFiles files;
  GpuRunOptions options;
  options.trace_dir = dir.string();
  options.trace_files = &files;
  options.trace_scene = scene;
  options.trace_stages = f.stages;
  options.trace_window = f.window;
  options.trace_prims = f.prims;
  GpuRunResult r = run_gpu(load_scene(scene), config, options);
  files.commit();
  return r;
}

// --- transactions.bin and fragments.bin, read byte by byte --------------------

template <typename T>
T get(const std::string& b, size_t at) {
  T v;
  std::memcpy(&v, b.data() + at, sizeof v);  // the test runs little endian, as the files are
  return v;
}

struct Tx {
  uint64_t in, out;
  int64_t first, last;
  uint32_t draw;
  uint16_t stage;
  uint8_t kind;
  uint8_t prim_kind;
  int16_t tx, ty;
  uint32_t count;
};

struct Frag {
  uint64_t cycle;
  int64_t prim;
  uint16_t x, y;
  uint8_t stage, unit, outcome;
  float depth, old_depth, value[4];
};

void check_header(const std::string& b, const char* magic) {
  ASSERT_GE(b.size(), 16u);
  EXPECT_EQ(b.substr(0, 8), magic);
  EXPECT_EQ(get<uint32_t>(b, 8), 1u);
  EXPECT_EQ(get<uint32_t>(b, 12), 48u);
  EXPECT_EQ((b.size() - 16) % 48, 0u);
}

std::vector<Tx> read_transactions(const fs::path& dir) {
  const std::string b = file_bytes(dir / "transactions.bin");
  check_header(b, "GPUSIMTX");
  std::vector<Tx> out;
  for (size_t at = 16; at + 48 <= b.size(); at += 48) {
    out.push_back({get<uint64_t>(b, at), get<uint64_t>(b, at + 8), get<int64_t>(b, at + 16),
                   get<int64_t>(b, at + 24), get<uint32_t>(b, at + 32), get<uint16_t>(b, at + 36),
                   get<uint8_t>(b, at + 38), get<uint8_t>(b, at + 39), get<int16_t>(b, at + 40),
                   get<int16_t>(b, at + 42), get<uint32_t>(b, at + 44)});
  }
  return out;
}

std::vector<Frag> read_fragments(const fs::path& dir) {
  const std::string b = file_bytes(dir / "fragments.bin");
  check_header(b, "GPUSIMFR");
  std::vector<Frag> out;
  for (size_t at = 16; at + 48 <= b.size(); at += 48) {
    Frag f{get<uint64_t>(b, at),      get<int64_t>(b, at + 8),
           get<uint16_t>(b, at + 16), get<uint16_t>(b, at + 18),
           get<uint8_t>(b, at + 20),  get<uint8_t>(b, at + 21),
           get<uint8_t>(b, at + 22),  get<float>(b, at + 24),
           get<float>(b, at + 28),    {}};
    for (int k = 0; k < 4; ++k) f.value[k] = get<float>(b, at + 32 + 4 * k);
    out.push_back(f);
  }
  return out;
}

nlohmann::json manifest(const fs::path& dir) {
  return nlohmann::json::parse(file_bytes(dir / "manifest.json"));
}

// --- signals.vcd ------------------------------------------------------------------

struct Vcd {
  std::string timescale;
  struct Var {
    std::string scope, name;  // scope: "gpu.primitive_setup", "gpu.fifos"
    unsigned width = 1;
  };
  std::map<std::string, Var> vars;  // by identifier
  std::vector<std::string> order;   // "scope.name" in declaration order
  // Per time stamp, the values of every variable after that time's changes.
  std::vector<std::pair<uint64_t, std::map<std::string, uint64_t>>> steps;
  bool dumpvars = false;
};

Vcd parse_vcd(const fs::path& path) {
  Vcd v;
  std::istringstream in(file_bytes(path));
  std::vector<std::string> scope;
  std::string tok;
  // Header: keyword sections up to $enddefinitions.
  while (in >> tok && tok != "$enddefinitions") {
    std::vector<std::string> words;
    for (std::string w; in >> w && w != "$end";) words.push_back(w);
    if (tok == "$scope") {
      scope.push_back(words.at(1));
    } else if (tok == "$upscope") {
      scope.pop_back();
    } else if (tok == "$var") {
      std::string s;
      for (const std::string& p : scope) s += (s.empty() ? "" : ".") + p;
      v.vars[words.at(2)] = {s, words.at(3), static_cast<unsigned>(std::stoul(words.at(1)))};
      v.order.push_back(s + "." + words.at(3));
    } else if (tok == "$timescale") {
      v.timescale = words.at(0) + " " + words.at(1);
    }
  }
  EXPECT_TRUE(scope.empty()) << "unbalanced $scope";
  in >> tok;  // the $end of $enddefinitions
  std::map<std::string, uint64_t> values;
  bool have_time = false;
  uint64_t time = 0;
  const auto close_step = [&] {
    if (have_time) v.steps.push_back({time, values});
  };
  while (in >> tok) {
    if (tok == "$dumpvars") {
      v.dumpvars = true;
    } else if (tok == "$end") {
    } else if (tok[0] == '#') {
      close_step();
      const uint64_t t = std::stoull(tok.substr(1));
      EXPECT_TRUE(!have_time || t > time) << "time stamps must increase";
      time = t;
      have_time = true;
    } else if (tok[0] == 'b') {
      std::string id;
      in >> id;
      EXPECT_TRUE(v.vars.count(id)) << id;
      values[id] = std::stoull(tok.substr(1), nullptr, 2);
    } else {
      const std::string id = tok.substr(1);
      EXPECT_TRUE(v.vars.count(id)) << tok;
      EXPECT_TRUE(tok[0] == '0' || tok[0] == '1') << tok;
      values[id] = tok[0] == '1';
    }
  }
  close_step();
  return v;
}

// --- The tests --------------------------------------------------------------------

class TraceRecord : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(::testing::TempDir()) / ("gpusim_trace_" + std::to_string(getpid()));
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

// A traced FIFO's starved reader wakes in the delta after the write and then
// waits out the producer's latency; an untraced one sleeps until the item is
// ready (hw/fifo.h, wait_for_item). The two schedules must agree on the
// frame, the pipeline counters and every timing figure of stats.json.
TEST_F(TraceRecord, TracingMovesNoCycleNorPixel) {
  for (const char* name : {"default", "lines_points", "clears_samples4"}) {
    SCOPED_TRACE(name);
    const std::string scene = scene_path(name);
    const GpuRunResult traced = traced_run(scene, dir_ / name);
    const GpuRunResult plain = run_gpu(load_scene(scene), GpuConfig{}, GpuRunOptions{});
    EXPECT_EQ(traced.cycles, plain.cycles);
    EXPECT_EQ(traced.counts, plain.counts);
    EXPECT_EQ(traced.timing.dump(), plain.timing.dump());
    EXPECT_TRUE(traced.framebuffer.color == plain.framebuffer.color);
    EXPECT_TRUE(traced.framebuffer.depth == plain.framebuffer.depth);
  }
}

TEST_F(TraceRecord, VcdStatesIntegrateToTheStageCounters) {
  const GpuRunResult r = traced_run(scene_path("default"), dir_);
  const Vcd vcd = parse_vcd(dir_ / "signals.vcd");
  EXPECT_EQ(vcd.timescale, "1 ns");  // one cycle at the default 1000 MHz
  EXPECT_TRUE(vcd.dumpvars);
  ASSERT_GE(vcd.steps.size(), 2u);
  EXPECT_EQ(vcd.steps.front().first, 0u);
  EXPECT_EQ(vcd.steps.back().first, r.cycles);

  // Identifiers of each stage's three wires and each FIFO's vector.
  std::map<std::string, std::map<std::string, std::string>> stage_ids;
  std::map<std::string, std::string> fifo_ids;
  for (const auto& [id, var] : vcd.vars) {
    if (var.scope == "gpu.memory") continue;  // MemoryChannelWiresIntegrateToTheirBusyCycles
    if (var.width > 1) {
      fifo_ids[var.name] = id;
    } else {
      // gpu.<front_end|unit_u>.<stage>, wires <stage>_busy, _stalled, _starved.
      const std::string stage = var.scope.substr(var.scope.rfind('.') + 1);
      ASSERT_EQ(var.name.rfind(stage + "_", 0), 0u) << var.scope << " " << var.name;
      stage_ids[stage][var.name.substr(stage.size() + 1)] = id;
    }
  }
  const nlohmann::json& stages = r.timing["stages"];
  const nlohmann::json& fifos = r.timing["fifos"];
  ASSERT_EQ(stage_ids.size(), stages.size());
  ASSERT_EQ(fifo_ids.size(), fifos.size());

  std::map<std::string, std::map<std::string, uint64_t>> integral;
  for (size_t k = 0; k < vcd.steps.size(); ++k) {
    const auto& [time, values] = vcd.steps[k];
    for (const auto& [stage, ids] : stage_ids) {
      ASSERT_EQ(ids.size(), 3u) << stage;
      int ones = 0;
      for (const auto& [wire, id] : ids) ones += static_cast<int>(values.at(id));
      ASSERT_EQ(ones, 1) << stage << " at cycle " << time << ": not exactly one state";
      if (k + 1 == vcd.steps.size()) continue;
      for (const auto& [wire, id] : ids) {
        integral[stage][wire] += values.at(id) * (vcd.steps[k + 1].first - time);
      }
    }
    for (const auto& [fifo, id] : fifo_ids) {
      ASSERT_LE(values.at(id), fifos[fifo]["depth"].get<uint64_t>()) << fifo << " at " << time;
    }
  }
  for (const auto& [stage, wires] : integral) {
    SCOPED_TRACE(stage);
    const nlohmann::json& s = stages[stage];
    EXPECT_EQ(wires.at("busy"), s["busy_cycles"].get<uint64_t>());
    EXPECT_EQ(static_cast<double>(wires.at("stalled")), s["stalled_cycles"].get<double>());
    EXPECT_EQ(static_cast<double>(wires.at("starved")), s["starved_cycles"].get<double>());
  }
  // Grouped in pipeline order: the front end, then unit by unit, each FIFO
  // just before the stage reading it.
  std::vector<std::string> want = {"gpu.front_end.commands"};
  const auto stage = [&](const std::string& group, const std::string& name) {
    for (const char* w : {"busy", "stalled", "starved"}) {
      want.push_back("gpu." + group + "." + name + "." + name + "_" + w);
    }
  };
  stage("front_end", "command_processor");
  for (const auto& [fifo, next] : std::vector<std::pair<std::string, std::string>>{
           {"command_to_fetch", "vertex_fetch"},
           {"fetch_to_shader", "vertex_shader"},
           {"shader_to_clipper", "clipper"},
           {"clipper_to_setup", "primitive_setup"},
           {"setup_to_distributor", "tile_distributor"}}) {
    want.push_back("gpu.front_end." + fifo);
    stage("front_end", next);
  }
  for (int u = 0; u < 4; ++u) {
    const std::string g = "unit_" + std::to_string(u), n = "_" + std::to_string(u);
    for (const auto& [fifo, next] : std::vector<std::pair<std::string, std::string>>{
             {"distributor_to_rasterizer", "tile_rasterizer"},
             {"rasterizer_to_depth", "depth_test"},
             {"depth_to_interpolator", "interpolator"},
             {"interpolator_to_rop", "rop"}}) {
      want.push_back("gpu." + g + "." + fifo + n);
      stage(g, next + n);
    }
  }
  // The memory last, one wire per channel.
  for (unsigned c = 0; c < GpuConfig{}.memory.channels; ++c) {
    want.push_back("gpu.memory.channel_" + std::to_string(c) + "_busy");
  }
  EXPECT_EQ(vcd.order, want);

  // Something happened: the setup stage worked, and some FIFO filled up.
  EXPECT_GT(integral["primitive_setup"]["busy"], 0u);
  EXPECT_EQ(manifest(dir_)["records"]["vcd_changes"].get<uint64_t>() > 0, true);
}

// Each memory channel's busy wire is high exactly in the cycles its bus
// moves data: over the frame, its channel's busy_cycles in stats.json. Three
// channels interleaved every 32 bytes, so tile rows are split and every
// channel is used.
TEST_F(TraceRecord, MemoryChannelWiresIntegrateToTheirBusyCycles) {
  GpuConfig config;
  config.memory.channels = 3;
  config.memory.interleave_bytes = 32;
  const GpuRunResult r = traced_run(scene_path("default"), dir_, {}, config);
  const Vcd vcd = parse_vcd(dir_ / "signals.vcd");
  std::map<std::string, std::string> ids;  // name -> identifier
  for (const auto& [id, var] : vcd.vars) {
    if (var.scope != "gpu.memory") continue;
    EXPECT_EQ(var.width, 1u);
    ids[var.name] = id;
  }
  ASSERT_EQ(ids.size(), 3u);
  const nlohmann::json& channels = r.timing["memory"]["channels"];
  ASSERT_EQ(channels.size(), 3u);
  for (unsigned c = 0; c < 3; ++c) {
    const std::string name = "channel_" + std::to_string(c) + "_busy";
    ASSERT_TRUE(ids.count(name)) << name;
    uint64_t busy = 0;
    for (size_t k = 0; k + 1 < vcd.steps.size(); ++k) {
      busy += vcd.steps[k].second.at(ids[name]) * (vcd.steps[k + 1].first - vcd.steps[k].first);
    }
    EXPECT_GT(busy, 0u) << name;
    EXPECT_EQ(busy, channels[c]["busy_cycles"].get<uint64_t>()) << name;
  }
}

TEST_F(TraceRecord, TimelineIsTraceEventJson) {
  traced_run(scene_path("default"), dir_);
  const nlohmann::json t = nlohmann::json::parse(file_bytes(dir_ / "timeline.json"));
  EXPECT_EQ(t["displayTimeUnit"], "ns");
  ASSERT_TRUE(t["traceEvents"].is_array());
  std::map<std::string, uint64_t> by_phase;
  for (const nlohmann::json& e : t["traceEvents"]) {
    for (const char* k : {"ph", "ts", "pid", "tid", "name"}) {
      ASSERT_TRUE(e.contains(k)) << k << " missing in " << e.dump();
    }
    const std::string ph = e["ph"];
    ++by_phase[ph];
    if (ph == "X") {
      ASSERT_TRUE(e.contains("dur")) << e.dump();
      const nlohmann::json& a = e["args"];
      for (const char* k : {"cycle_in", "cycle_out", "draw", "prim_first", "prim_last", "count"}) {
        ASSERT_TRUE(a.contains(k)) << k << " missing in " << e.dump();
      }
      // Microseconds at 1000 MHz: cycles / 1000.
      EXPECT_DOUBLE_EQ(e["ts"].get<double>(), a["cycle_in"].get<double>() / 1000.0);
      EXPECT_NEAR(e["dur"].get<double>(),
                  (a["cycle_out"].get<double>() - a["cycle_in"].get<double>()) / 1000.0, 1e-9);
    } else if (ph == "C") {
      EXPECT_EQ(e["name"].get<std::string>().rfind("fifo ", 0), 0u);
      EXPECT_TRUE(e["args"].contains("occupancy"));
    } else {
      EXPECT_EQ(ph, "M");
    }
  }
  const nlohmann::json m = manifest(dir_);
  EXPECT_EQ(by_phase["X"], m["records"]["transactions"].get<uint64_t>());
  EXPECT_GT(by_phase["C"], 0u);
  EXPECT_EQ(by_phase["M"], 5u + 2u * 22u);  // 5 processes; per stage a name and a sort index
  EXPECT_EQ(t["traceEvents"].size(), m["records"]["timeline_events"].get<uint64_t>());
}

// Issue #16 item 9: at 300 MHz (a 3333 ps period) the VCD's times are
// picoseconds, whole cycles of 3333, and the timeline's slices, each end
// rounded once to a nanosecond, never overlap the next on their thread.
TEST_F(TraceRecord, At300MHzVcdTimesAreRealAndSlicesDoNotOverlap) {
  GpuConfig config;
  config.clock_mhz = 300.0;
  const GpuRunResult r = traced_run(scene_path("default"), dir_, {}, config);
  EXPECT_EQ(manifest(dir_)["cycle_ps"].get<uint64_t>(), 3333u);
  const Vcd vcd = parse_vcd(dir_ / "signals.vcd");
  EXPECT_EQ(vcd.timescale, "1 ps");
  ASSERT_GE(vcd.steps.size(), 2u);
  for (const auto& step : vcd.steps) ASSERT_EQ(step.first % 3333, 0u) << step.first;
  EXPECT_EQ(vcd.steps.back().first / 3333, r.cycles);

  // "ts": A.BCD and "dur": A.BCD as integers of nanoseconds, from the text.
  const std::regex x(
      R"re("ph": "X", .*"ts": (\d+)\.(\d{3}), "dur": (\d+)\.(\d{3}), "pid": (\d+), "tid": (\d+), "args": \{"cycle_in": (\d+), "cycle_out": (\d+))re");
  std::map<std::pair<int, int>, std::vector<std::pair<uint64_t, uint64_t>>> slices;
  std::istringstream in(file_bytes(dir_ / "timeline.json"));
  uint64_t n = 0, fractional = 0;
  for (std::string line; std::getline(in, line);) {
    std::smatch m;
    if (!std::regex_search(line, m, x)) continue;
    const uint64_t ts = std::stoull(m[1]) * 1000 + std::stoull(m[2]);
    const uint64_t dur = std::stoull(m[3]) * 1000 + std::stoull(m[4]);
    const uint64_t in_ps = std::stoull(m[7]) * 3333, out_ps = std::stoull(m[8]) * 3333;
    ASSERT_EQ(ts, (in_ps + 500) / 1000) << line;  // rounded to the nearest ns
    ASSERT_EQ(ts + dur, (out_ps + 500) / 1000) << line;
    fractional += in_ps % 1000 != 0;
    slices[{std::stoi(m[5]), std::stoi(m[6])}].push_back({ts, ts + dur});
    ++n;
  }
  EXPECT_EQ(n, manifest(dir_)["records"]["transactions"].get<uint64_t>());
  EXPECT_GT(fractional, n / 2);  // most boundaries did need rounding
  for (const auto& [thread, list] : slices) {
    for (size_t k = 0; k + 1 < list.size(); ++k) {
      ASSERT_LE(list[k].second, list[k + 1].first)
          << "thread " << thread.second << " slice " << k << " ends after the next begins";
    }
  }
}

TEST_F(TraceRecord, TransactionsCountEveryTokenOfEveryStage) {
  const GpuRunResult r = traced_run(scene_path("default"), dir_);
  const nlohmann::json m = manifest(dir_);
  EXPECT_EQ(m["format"], "gpusim-trace");
  EXPECT_EQ(m["cycles"].get<uint64_t>(), r.cycles);
  EXPECT_EQ(m["units"], 4);
  const std::vector<Tx> tx = read_transactions(dir_);
  EXPECT_EQ(tx.size(), m["records"]["transactions"].get<uint64_t>());
  std::map<uint16_t, uint64_t> per_stage;
  for (size_t k = 0; k < tx.size(); ++k) {
    ++per_stage[tx[k].stage];
    ASSERT_LE(tx[k].in, tx[k].out);
    ASSERT_LE(tx[k].out, r.cycles);
    ASSERT_LE(tx[k].kind, 2);
    if (tx[k].kind != 0) {
      EXPECT_EQ(tx[k].first, -1);
      EXPECT_EQ(tx[k].draw, 0xFFFFFFFFu);
      EXPECT_EQ(tx[k].prim_kind, 0);  // a control token carries no primitive
    } else {
      EXPECT_LE(tx[k].first, tx[k].last);
      EXPECT_EQ(tx[k].prim_kind, 3);  // default.json draws filled triangles only
    }
    if (k > 0) {  // cycle_out order, ties in stage order
      ASSERT_TRUE(tx[k - 1].out < tx[k].out ||
                  (tx[k - 1].out == tx[k].out && tx[k - 1].stage <= tx[k].stage));
    }
  }
  // Each draw's primitive type and polygon mode, as the scene resolves them.
  const Scene scene = load_scene(scene_path("default"));
  ASSERT_EQ(m["draws"].size(), scene.draws.size());
  for (size_t d = 0; d < scene.draws.size(); ++d) {
    EXPECT_EQ(m["draws"][d]["primitive"], std::string(to_string(scene.draws[d].primitive)));
    EXPECT_EQ(m["draws"][d]["polygon_mode"], "fill");
  }
  ASSERT_EQ(m["stages"].size(), 22u);
  for (const nlohmann::json& s : m["stages"]) {
    const std::string name = s["name"];
    EXPECT_EQ(per_stage[s["index"].get<uint16_t>()],
              r.timing["stages"][name]["tokens_in"].get<uint64_t>())
        << name;
  }
  // Stamp batches at the depth test carry the stamps the rasterizer made.
  uint64_t stamps = 0, raster_stamps = 0;
  for (const Tx& t : tx) {
    const std::string kind = m["stages"][t.stage]["kind"];
    if (kind == "depth_test" && t.kind == 0) stamps += t.count;
    if (kind == "tile_rasterizer" && t.kind == 0) raster_stamps += t.count;
  }
  uint64_t emitted = 0;
  for (int u = 0; u < 4; ++u) {
    emitted += r.timing["stages"]["tile_rasterizer_" + std::to_string(u)]["stamps_emitted"]
                   .get<uint64_t>();
  }
  EXPECT_EQ(stamps, emitted);
  EXPECT_EQ(raster_stamps, emitted);
}

// Scenes with depth tests off, never-passing functions, masked colour writes
// and blending, so every outcome appears.
class TraceFragments : public TraceRecord, public ::testing::WithParamInterface<const char*> {};

TEST_P(TraceFragments, MatchTheCountersAndTheFrame) {
  const GpuRunResult r = traced_run(scene_path(GetParam()), dir_);
  const unsigned units = GpuConfig{}.units;
  const std::vector<Frag> frags = read_fragments(dir_);
  EXPECT_EQ(frags.size(), manifest(dir_)["records"]["fragments"].get<uint64_t>());
  std::map<unsigned, uint64_t> depth_in, depth_passed, rop_in, rop_written;
  const Framebuffer& fb = r.framebuffer;
  // The last value stored at each pixel, in record order (a unit owns its
  // pixels, and writes them in order).
  std::map<size_t, float> last_depth;
  std::map<size_t, std::array<float, 4>> last_color;
  uint64_t stored = 0;
  for (const Frag& f : frags) {
    ASSERT_LT(f.x, fb.width);
    ASSERT_LT(f.y, fb.height);
    const size_t p = fb.pixel_index(f.x, f.y);
    if (f.stage == 0) {
      ++depth_in[f.unit];
      if (f.outcome != 0) ++depth_passed[f.unit];
      if (!std::isnan(f.value[0])) last_depth[p] = f.value[0];
      if (f.outcome == 1 && !std::isnan(f.value[0])) {
        EXPECT_EQ(f.value[0], f.depth);  // a passing fragment stores its own depth
        ++stored;
      }
      if (f.outcome == 0) {
        EXPECT_TRUE(std::isnan(f.value[0]));
      }
    } else {
      ASSERT_EQ(f.stage, 1);
      ++rop_in[f.unit];
      if (f.outcome == 1) {
        ++rop_written[f.unit];
        last_color[p] = {f.value[0], f.value[1], f.value[2], f.value[3]};
      } else {
        EXPECT_EQ(f.outcome, 3);
        EXPECT_TRUE(std::isnan(f.value[0]));
      }
      EXPECT_TRUE(std::isnan(f.depth));
    }
  }
  for (unsigned u = 0; u < units; ++u) {
    const nlohmann::json& d = r.timing["stages"]["depth_test_" + std::to_string(u)];
    const nlohmann::json& o = r.timing["stages"]["rop_" + std::to_string(u)];
    EXPECT_EQ(depth_in[u], d["fragments_in"].get<uint64_t>()) << u;
    EXPECT_EQ(depth_passed[u], d["fragments_passed"].get<uint64_t>()) << u;
    EXPECT_EQ(rop_in[u], o["fragments_in"].get<uint64_t>()) << u;
    EXPECT_EQ(rop_written[u], o["fragments_written"].get<uint64_t>()) << u;
  }
  EXPECT_EQ(stored > 0, !last_depth.empty());  // some scenes write no depth
  for (const auto& [p, z] : last_depth) {
    ASSERT_EQ(z, decode_depth(fb.depth_format, fb.depth[p])) << "pixel " << p;
  }
  ASSERT_FALSE(last_color.empty());
  for (const auto& [p, c] : last_color) {
    for (int k = 0; k < 4; ++k) {
      ASSERT_EQ(c[k], decode_color(fb.color_format, fb.color[p * 4 + k])) << "pixel " << p;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, TraceFragments,
                         ::testing::Values("default", "states", "regress/color_mask",
                                           "regress/depth_funcs", "regress/blend_rgba16f",
                                           "regress/interpenetrating_unorm16"),
                         [](const ::testing::TestParamInfo<const char*>& info) {
                           std::string n = info.param;
                           for (char& c : n)
                             c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
                           return n;
                         });

TEST_F(TraceRecord, WindowKeepsOnlyWhatIntersectsIt) {
  const uint64_t start = 10000, end = 30000;  // inside the default scene's frame
  const GpuRunResult r = traced_run(scene_path("default"), dir_ / "all");
  traced_run(scene_path("default"), dir_ / "w", {"", "10000:30000", ""});
  const std::vector<Tx> all = read_transactions(dir_ / "all"), w = read_transactions(dir_ / "w");
  uint64_t expected = 0;
  for (const Tx& t : all) expected += t.in < end && t.out > start;
  EXPECT_EQ(w.size(), expected);
  EXPECT_LT(w.size(), all.size());
  for (const Tx& t : w) ASSERT_TRUE(t.in < end && t.out > start);
  const std::vector<Frag> fa = read_fragments(dir_ / "all"), fw = read_fragments(dir_ / "w");
  uint64_t in_window = 0;
  for (const Frag& f : fa) in_window += f.cycle >= start && f.cycle < end;
  EXPECT_EQ(fw.size(), in_window);
  for (const Frag& f : fw) ASSERT_TRUE(f.cycle >= start && f.cycle < end);
  const Vcd vcd = parse_vcd(dir_ / "w" / "signals.vcd");
  EXPECT_EQ(vcd.steps.front().first, start);
  EXPECT_EQ(vcd.steps.back().first, end);
  // The values at START are the unfiltered trace's at START.
  const Vcd full = parse_vcd(dir_ / "all" / "signals.vcd");
  const std::map<std::string, uint64_t>* at_start = nullptr;
  for (const auto& step : full.steps) {
    if (step.first <= start) at_start = &step.second;
  }
  ASSERT_NE(at_start, nullptr);
  EXPECT_EQ(vcd.steps.front().second, *at_start);
  EXPECT_EQ(manifest(dir_ / "w")["filters"]["window"], nlohmann::json({start, end}));
  (void)r;
}

TEST_F(TraceRecord, PrimsKeepOnlyTheirItemsAndControlTokens) {
  traced_run(scene_path("default"), dir_ / "all");
  traced_run(scene_path("default"), dir_ / "p", {"", "", "100:199"});
  const std::vector<Tx> all = read_transactions(dir_ / "all"), p = read_transactions(dir_ / "p");
  uint64_t expected = 0;
  for (const Tx& t : all)
    expected += t.kind != 0 || (t.first >= 0 && t.first <= 199 && t.last >= 100);
  EXPECT_EQ(p.size(), expected);
  EXPECT_LT(p.size(), all.size());
  uint64_t control = 0;
  for (const Tx& t : p) {
    if (t.kind != 0) {
      ++control;
      continue;
    }
    ASSERT_TRUE(t.first <= 199 && t.last >= 100) << t.first << ".." << t.last;
  }
  EXPECT_EQ(control, 2u * 22u);  // a clear and an end of frame at every stage
  const std::vector<Frag> fp = read_fragments(dir_ / "p");
  EXPECT_GT(fp.size(), 0u);
  for (const Frag& f : fp) ASSERT_TRUE(f.prim >= 100 && f.prim <= 199);
  // Signals are not filtered by primitive.
  EXPECT_EQ(file_bytes(dir_ / "all" / "signals.vcd"), file_bytes(dir_ / "p" / "signals.vcd"));
}

TEST_F(TraceRecord, StagesKeepOnlyThose) {
  traced_run(scene_path("default"), dir_, {"primitive_setup,depth_test_1,rop", "", ""});
  const nlohmann::json m = manifest(dir_);
  std::vector<std::string> kept;
  for (const nlohmann::json& s : m["filters"]["stages"]) kept.push_back(s);
  // In stage order: unit 0's stages come before unit 1's.
  EXPECT_EQ(kept, (std::vector<std::string>{"primitive_setup", "rop_0", "depth_test_1", "rop_1",
                                            "rop_2", "rop_3"}));
  std::map<std::string, uint16_t> index;
  for (const nlohmann::json& s : m["stages"]) index[s["name"]] = s["index"];
  for (const Tx& t : read_transactions(dir_)) {
    const std::string name = m["stages"][t.stage]["name"];
    ASSERT_TRUE(std::find(kept.begin(), kept.end(), name) != kept.end()) << name;
  }
  for (const Frag& f : read_fragments(dir_)) {
    ASSERT_TRUE(f.stage == 1 || f.unit == 1) << "depth test of unit " << int(f.unit);
  }
  const Vcd vcd = parse_vcd(dir_ / "signals.vcd");
  std::set<std::string> scopes;
  for (const auto& [id, var] : vcd.vars) scopes.insert(var.scope);
  EXPECT_EQ(scopes,
            (std::set<std::string>{"gpu.front_end", "gpu.front_end.primitive_setup", "gpu.memory",
                                   "gpu.unit_0", "gpu.unit_0.rop_0", "gpu.unit_1",
                                   "gpu.unit_1.depth_test_1", "gpu.unit_1.rop_1", "gpu.unit_2",
                                   "gpu.unit_2.rop_2", "gpu.unit_3", "gpu.unit_3.rop_3"}));
}

TEST_F(TraceRecord, TracingChangesNoCycleAndNoPixel) {
  const GpuRunResult plain = run_gpu(load_scene(scene_path("default")), GpuConfig{}, {});
  const GpuRunResult traced = traced_run(scene_path("default"), dir_);
  EXPECT_EQ(plain.cycles, traced.cycles);
  EXPECT_EQ(plain.timing, traced.timing);
  EXPECT_EQ(plain.counts, traced.counts);
  EXPECT_TRUE(plain.framebuffer.color == traced.framebuffer.color);
  EXPECT_TRUE(plain.framebuffer.depth == traced.framebuffer.depth);
}

TEST_F(TraceRecord, TwoRunsGiveTheSameBytes) {
  GpuConfig config;
  config.units = 3;
  config.fifo_depth = 2;
  traced_run(scene_path("spider"), dir_ / "a", {}, config);
  traced_run(scene_path("spider"), dir_ / "b", {}, config);
  for (const char* f : {"manifest.json", "signals.vcd", "signals.gtkw", "timeline.json",
                        "transactions.bin", "fragments.bin"}) {
    const std::string a = file_bytes(dir_ / "a" / f);
    EXPECT_FALSE(a.empty()) << f;
    EXPECT_TRUE(a == file_bytes(dir_ / "b" / f)) << f << " differs between two runs";
  }
}

TEST_F(TraceRecord, BadFiltersFailBeforeAnythingIsWritten) {
  const Scene scene = load_scene(scene_path("default"));
  for (const Filters& f : std::vector<Filters>{{"setup", "", ""},
                                               {"depth_test_4", "", ""},
                                               {"", "10:5", ""},
                                               {"", "x:", ""},
                                               {"", "", "5"},
                                               {"", "", "9:2"}}) {
    OutputFiles files;
    GpuRunOptions options;
    options.trace_dir = dir_.string();
    options.trace_files = &files;
    options.trace_stages = f.stages;
    options.trace_window = f.window;
    options.trace_prims = f.prims;
    EXPECT_THROW(run_gpu(scene, GpuConfig{}, options), InputError)
        << f.stages << f.window << f.prims;
    EXPECT_FALSE(fs::exists(dir_));
  }
}

TEST_F(TraceRecord, AFailedRunLeavesAnEarlierTraceIntact) {
  traced_run(scene_path("tiny_triangles"), dir_);
  const std::string before = file_bytes(dir_ / "transactions.bin");
  {
    OutputFiles files;
    GpuRunOptions options;
    options.trace_dir = dir_.string();
    options.trace_files = &files;
    options.fault_withhold_end_of_frame = true;  // the frame never completes
    EXPECT_THROW(run_gpu(load_scene(scene_path("default")), GpuConfig{}, options), SimulationError);
  }
  EXPECT_EQ(file_bytes(dir_ / "transactions.bin"), before);
  for (const auto& e : fs::directory_iterator(dir_)) {
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
  }
}

}  // namespace
}  // namespace gpusim
