#include "stages/gpu.h"

#include <algorithm>
#include <climits>
#include <sstream>
#include <stdexcept>
#include <string>

namespace gpusim {
namespace {

std::string unit_name(const char* what, unsigned u) {
  return std::string(what) + "_" + std::to_string(u);
}

template <typename T>
double blocked_cycles(const Fifo<T>& f, bool writer, sc_core::sc_time cycle) {
  const FifoStats s = f.stats();
  return (writer ? s.writer_blocked : s.reader_blocked) / cycle;
}

uint64_t counter(const StatGroup& g, const char* name) {
  const nlohmann::json j = g.to_json();
  return j.contains(name) ? j.at(name).get<uint64_t>() : 0;
}

}  // namespace

Gpu::Gpu(sc_core::sc_module_name name, const GpuConfig& config, const FrameState& frame,
         uint64_t memory_bytes, const Faults& faults)
    : sc_core::sc_module(name),
      m_config(config),
      m_frame(frame),
      m_memory("memory", memory_bytes, config.memory.latency, config.memory.bytes_per_cycle,
               config.cycle()),
      m_commands("commands", config.fifo_depth),
      m_command_processor("command_processor", config, frame),
      m_command_to_fetch("command_to_fetch", config.fifo_depth_of("command_to_fetch")),
      m_fetch("vertex_fetch", config, frame),
      m_fetch_to_shader("fetch_to_shader", config.fifo_depth_of("fetch_to_shader")),
      m_shader("vertex_shader", config, frame),
      m_shader_to_clipper("shader_to_clipper", config.fifo_depth_of("shader_to_clipper")),
      m_clipper("clipper", config, frame),
      m_clipper_to_setup("clipper_to_setup", config.fifo_depth_of("clipper_to_setup")),
      m_setup("triangle_setup", config, frame),
      m_setup_to_distributor("setup_to_distributor", config.fifo_depth_of("setup_to_distributor")),
      m_distributor("tile_distributor", config, frame) {
  m_faults = faults;
  // Stages read through reader_side(): the FIFO itself unless a test fault
  // disconnects it.
  m_command_processor.in(reader_side(m_commands));
  m_command_processor.out(m_command_to_fetch);
  m_fetch.in(reader_side(m_command_to_fetch));
  m_fetch.out(m_fetch_to_shader);
  m_fetch.mem.bind(m_memory);
  m_shader.in(reader_side(m_fetch_to_shader));
  m_shader.out(m_shader_to_clipper);
  m_clipper.in(reader_side(m_shader_to_clipper));
  m_clipper.out(m_clipper_to_setup);
  m_setup.in(reader_side(m_clipper_to_setup));
  m_setup.out(m_setup_to_distributor);
  m_distributor.in(reader_side(m_setup_to_distributor));

  m_units.resize(config.units);
  for (unsigned u = 0; u < config.units; ++u) {
    Unit& unit = m_units[u];
    unit.jobs =
        std::make_unique<Fifo<SetupPacket>>(unit_name("distributor_to_rasterizer", u).c_str(),
                                            config.fifo_depth_of("distributor_to_rasterizer"));
    unit.rasterizer =
        std::make_unique<TileRasterizer>(unit_name("tile_rasterizer", u).c_str(), config, frame, u);
    unit.stamps = std::make_unique<Fifo<StampBatch>>(unit_name("rasterizer_to_depth", u).c_str(),
                                                     config.fifo_depth_of("rasterizer_to_depth"));
    unit.depth = std::make_unique<DepthTest>(unit_name("depth_test", u).c_str(), config, frame, u);
    unit.visible =
        std::make_unique<Fifo<StampBatch>>(unit_name("depth_to_interpolator", u).c_str(),
                                           config.fifo_depth_of("depth_to_interpolator"));
    unit.interpolator =
        std::make_unique<Interpolator>(unit_name("interpolator", u).c_str(), config, frame, u);
    unit.shaded = std::make_unique<Fifo<ShadedStampBatch>>(
        unit_name("interpolator_to_rop", u).c_str(), config.fifo_depth_of("interpolator_to_rop"));
    unit.rop = std::make_unique<Rop>(unit_name("rop", u).c_str(), config, frame, u);

    m_distributor.out[u](*unit.jobs);
    unit.rasterizer->in(reader_side(*unit.jobs));
    unit.rasterizer->out(*unit.stamps);
    unit.depth->in(reader_side(*unit.stamps));
    unit.depth->out(*unit.visible);
    unit.depth->mem.bind(m_memory);
    unit.interpolator->in(reader_side(*unit.visible));
    unit.interpolator->out(*unit.shaded);
    unit.rop->in(reader_side(*unit.shaded));
    unit.rop->mem.bind(m_memory);
    m_done_events |= unit.rop->frame_done_event();
  }
  build_views();
  if (!m_faults.disconnected_fifo.empty() && m_stand_in_view.empty()) {
    throw std::invalid_argument("Gpu: no FIFO named '" + m_faults.disconnected_fifo + "'");
  }
  apply_stall_fault();
  SC_HAS_PROCESS(Gpu);
  SC_THREAD(watchdog);
}

bool Gpu::frame_done() const {
  for (const Unit& u : m_units) {
    if (!u.rop->frame_done()) return false;
  }
  return true;
}

void Gpu::set_last_writer(std::vector<int64_t>* per_pixel) {
  for (Unit& u : m_units) u.rop->set_last_writer(per_pixel);
}

void Gpu::inject_random_stalls(uint64_t seed, double probability, unsigned max_cycles) {
  const sc_core::sc_time cycle = m_config.cycle();
  uint64_t n = 0;
  const auto stall = [&](auto& fifo) {
    fifo.inject_random_stalls(seed + 0x9E3779B97F4A7C15ull * ++n, probability, max_cycles, cycle);
  };
  stall(m_commands);
  stall(m_command_to_fetch);
  stall(m_fetch_to_shader);
  stall(m_shader_to_clipper);
  stall(m_clipper_to_setup);
  stall(m_setup_to_distributor);
  for (Unit& u : m_units) {
    stall(*u.jobs);
    stall(*u.stamps);
    stall(*u.visible);
    stall(*u.shaded);
  }
}

uint64_t Gpu::triangles_assembled() const {
  return counter(m_clipper.stats(), "triangles_in");
}

nlohmann::json Gpu::pipeline_counts() const {
  nlohmann::json counts;
  for (const char* k : {"triangles_in", "triangles_invalid", "triangles_clipped_away",
                        "triangles_clipped", "triangles_after_clip"}) {
    counts[k] = counter(m_clipper.stats(), k);
  }
  for (const char* k : {"triangles_degenerate", "triangles_culled", "triangles_rasterized"}) {
    counts[k] = counter(m_setup.stats(), k);
  }
  uint64_t generated = 0, passed = 0, written = 0;
  for (const Unit& u : m_units) {
    generated += counter(u.rasterizer->stats(), "fragments");
    passed += counter(u.depth->stats(), "fragments_passed");
    written += counter(u.rop->stats(), "fragments_written");
  }
  counts["fragments_generated"] = generated;
  counts["fragments_passed_depth"] = passed;
  counts["fragments_written"] = written;
  return counts;
}

nlohmann::json Gpu::stats_json(uint64_t cycles) const {
  const sc_core::sc_time cycle = m_config.cycle();
  nlohmann::json stages = nlohmann::json::object();
  // busy: cycles the stage spent working; stalled: blocked writing a full
  // output FIFO; starved: blocked reading an empty (or not yet ready) input.
  const auto stage = [&](const StatGroup& g, double stalled, double starved) {
    nlohmann::json s = g.to_json();
    s["stalled_cycles"] = stalled;
    s["starved_cycles"] = starved;
    return s;
  };
  stages["command_processor"] =
      stage(m_command_processor.stats(), blocked_cycles(m_command_to_fetch, true, cycle),
            blocked_cycles(m_commands, false, cycle));
  stages["vertex_fetch"] = stage(m_fetch.stats(), blocked_cycles(m_fetch_to_shader, true, cycle),
                                 blocked_cycles(m_command_to_fetch, false, cycle));
  stages["vertex_shader"] =
      stage(m_shader.stats(), blocked_cycles(m_shader_to_clipper, true, cycle),
            blocked_cycles(m_fetch_to_shader, false, cycle));
  stages["clipper"] = stage(m_clipper.stats(), blocked_cycles(m_clipper_to_setup, true, cycle),
                            blocked_cycles(m_shader_to_clipper, false, cycle));
  stages["triangle_setup"] =
      stage(m_setup.stats(), blocked_cycles(m_setup_to_distributor, true, cycle),
            blocked_cycles(m_clipper_to_setup, false, cycle));
  double distributor_stalled = 0.0;
  for (const Unit& u : m_units) distributor_stalled += blocked_cycles(*u.jobs, true, cycle);
  stages["tile_distributor"] = stage(m_distributor.stats(), distributor_stalled,
                                     blocked_cycles(m_setup_to_distributor, false, cycle));

  nlohmann::json fifos = nlohmann::json::object();
  fifos["commands"] = m_commands.stats_json(cycle);
  fifos["command_to_fetch"] = m_command_to_fetch.stats_json(cycle);
  fifos["fetch_to_shader"] = m_fetch_to_shader.stats_json(cycle);
  fifos["shader_to_clipper"] = m_shader_to_clipper.stats_json(cycle);
  fifos["clipper_to_setup"] = m_clipper_to_setup.stats_json(cycle);
  fifos["setup_to_distributor"] = m_setup_to_distributor.stats_json(cycle);

  nlohmann::json units = nlohmann::json::array();
  uint64_t fragments = 0;
  for (unsigned i = 0; i < m_units.size(); ++i) {
    const Unit& u = m_units[i];
    const std::string n = std::to_string(i);
    stages["tile_rasterizer_" + n] =
        stage(u.rasterizer->stats(), blocked_cycles(*u.stamps, true, cycle),
              blocked_cycles(*u.jobs, false, cycle));
    stages["depth_test_" + n] = stage(u.depth->stats(), blocked_cycles(*u.visible, true, cycle),
                                      blocked_cycles(*u.stamps, false, cycle));
    stages["interpolator_" + n] =
        stage(u.interpolator->stats(), blocked_cycles(*u.shaded, true, cycle),
              blocked_cycles(*u.visible, false, cycle));
    stages["rop_" + n] = stage(u.rop->stats(), 0.0, blocked_cycles(*u.shaded, false, cycle));
    fifos["distributor_to_rasterizer_" + n] = u.jobs->stats_json(cycle);
    fifos["rasterizer_to_depth_" + n] = u.stamps->stats_json(cycle);
    fifos["depth_to_interpolator_" + n] = u.visible->stats_json(cycle);
    fifos["interpolator_to_rop_" + n] = u.shaded->stats_json(cycle);
    const StatGroup& r = u.rasterizer->stats();
    units.push_back({{"unit", i},
                     {"tiles", counter(r, "tiles_visited")},
                     {"stamps", counter(r, "stamps_emitted")},
                     {"fragments", counter(r, "fragments")}});
    fragments += counter(r, "fragments");
  }

  const double c = cycles ? static_cast<double>(cycles) : 1.0;
  const double setup_ii = m_config.stage("triangle_setup").ii;
  const double raster_ii = m_config.stage("rasterizer").ii;
  const double stamp_pixels = static_cast<double>(m_config.stamp[0]) * m_config.stamp[1];
  const uint64_t setup_triangles = counter(m_setup.stats(), "tokens_in");
  nlohmann::json rates = {
      {"setup_triangles_per_clock", static_cast<double>(setup_triangles) / c},
      {"setup_triangles_per_clock_peak", 1.0 / setup_ii},
      {"raster_pixels_per_clock", static_cast<double>(fragments) / c},
      {"raster_pixels_per_clock_peak", m_config.units * stamp_pixels / raster_ii},
  };

  return {{"cycles", cycles},
          {"simulated_seconds", static_cast<double>(cycles) / (m_config.clock_mhz * 1e6)},
          {"rates", rates},
          {"stages", stages},
          {"fifos", fifos},
          {"units", units},
          {"memory", m_memory.stats_json()}};
}

}  // namespace gpusim

namespace gpusim {

// --- Watchdog ---------------------------------------------------------------

template <typename T>
size_t Gpu::add_fifo_view(Fifo<T>& fifo, const std::string& name) {
  FifoView v;
  v.name = name;
  v.stats = [&fifo] { return fifo.stats(); };
  v.occupancy = [&fifo] { return fifo.depth() - fifo.num_free(); };
  v.depth = fifo.depth();
  v.attach = [&fifo](TraceProbes& probes, size_t index) {
    fifo.set_probe(probes.fifo_probe(index, ProbeTag<T>{}));
  };
  m_fifo_views.push_back(std::move(v));
  m_activity_events |= fifo.data_written_event();
  m_activity_events |= fifo.data_read_event();
  return m_fifo_views.size() - 1;
}

template <typename T>
Fifo<T>& Gpu::reader_side(Fifo<T>& fifo) {
  // The FIFO's own name is its SystemC basename ("clipper_to_setup",
  // "rasterizer_to_depth_0").
  if (m_faults.disconnected_fifo != fifo.basename()) return fifo;
  const std::string name = std::string(fifo.basename()) + "_disconnected";
  auto stand_in = std::make_unique<Fifo<T>>(name.c_str(), fifo.depth());
  Fifo<T>& ref = *stand_in;
  m_stand_in_view[fifo.basename()] = add_fifo_view(ref, name);
  m_stand_ins.push_back(std::shared_ptr<void>(std::move(stand_in)));
  return ref;
}

void Gpu::build_views() {
  // The view a stage reads: the FIFO's, or its stand-in's when disconnected.
  const auto input = [&](size_t view) {
    const auto it = m_stand_in_view.find(m_fifo_views[view].name);
    return it == m_stand_in_view.end() ? view : it->second;
  };
  const size_t commands = add_fifo_view(m_commands, "commands");
  const size_t to_fetch = add_fifo_view(m_command_to_fetch, "command_to_fetch");
  const size_t to_shader = add_fifo_view(m_fetch_to_shader, "fetch_to_shader");
  const size_t to_clipper = add_fifo_view(m_shader_to_clipper, "shader_to_clipper");
  const size_t to_setup = add_fifo_view(m_clipper_to_setup, "clipper_to_setup");
  const size_t to_distributor = add_fifo_view(m_setup_to_distributor, "setup_to_distributor");
  m_stage_views.push_back(
      {"command_processor", &m_command_processor.stats(), {input(commands)}, {to_fetch}});
  m_stage_views.push_back({"vertex_fetch", &m_fetch.stats(), {input(to_fetch)}, {to_shader}});
  m_stage_views.push_back({"vertex_shader", &m_shader.stats(), {input(to_shader)}, {to_clipper}});
  m_stage_views.push_back({"clipper", &m_clipper.stats(), {input(to_clipper)}, {to_setup}});
  m_stage_views.push_back(
      {"triangle_setup", &m_setup.stats(), {input(to_setup)}, {to_distributor}});
  const size_t distributor = m_stage_views.size();
  m_stage_views.push_back(
      {"tile_distributor", &m_distributor.stats(), {input(to_distributor)}, {}});
  for (unsigned u = 0; u < m_units.size(); ++u) {
    Unit& unit = m_units[u];
    const std::string n = std::to_string(u);
    const size_t jobs = add_fifo_view(*unit.jobs, "distributor_to_rasterizer_" + n);
    const size_t stamps = add_fifo_view(*unit.stamps, "rasterizer_to_depth_" + n);
    const size_t visible = add_fifo_view(*unit.visible, "depth_to_interpolator_" + n);
    const size_t shaded = add_fifo_view(*unit.shaded, "interpolator_to_rop_" + n);
    m_stage_views[distributor].outputs.push_back(jobs);
    m_stage_views.push_back(
        {"tile_rasterizer_" + n, &unit.rasterizer->stats(), {input(jobs)}, {stamps}});
    m_stage_views.push_back({"depth_test_" + n, &unit.depth->stats(), {input(stamps)}, {visible}});
    m_stage_views.push_back(
        {"interpolator_" + n, &unit.interpolator->stats(), {input(visible)}, {shaded}});
    m_stage_views.push_back({"rop_" + n, &unit.rop->stats(), {input(shaded)}, {}});
  }
}

TraceTables Gpu::trace_tables() const {
  // Views are numbered in creation order; fault stand-ins (created first)
  // are left out and a stage reading one is shown reading the real FIFO.
  std::map<size_t, std::string> stand_in_of;
  for (const auto& [name, view] : m_stand_in_view) stand_in_of[view] = name;
  std::vector<int> index(m_fifo_views.size(), -1);
  std::map<std::string, int> by_name;
  TraceTables t;
  for (size_t v = 0; v < m_fifo_views.size(); ++v) {
    if (stand_in_of.count(v)) continue;
    index[v] = static_cast<int>(t.fifos.size());
    by_name[m_fifo_views[v].name] = index[v];
    TraceTables::Fifo f;
    f.name = m_fifo_views[v].name;
    f.depth = m_fifo_views[v].depth;
    t.fifos.push_back(f);
  }
  const auto fifo_index = [&](size_t v) {
    const auto it = stand_in_of.find(v);
    return it == stand_in_of.end() ? index[v] : by_name.at(it->second);
  };
  for (const StageView& v : m_stage_views) {
    TraceTables::Stage s;
    s.name = v.name;
    // A unit's stages are named <kind>_<unit> (build_views); front-end names
    // end in a letter.
    const size_t us = v.name.rfind('_');
    const bool in_unit = us != std::string::npos && us + 1 < v.name.size() &&
                         v.name.find_first_not_of("0123456789", us + 1) == std::string::npos;
    s.kind = in_unit ? v.name.substr(0, us) : v.name;
    s.unit = in_unit ? std::stoi(v.name.substr(us + 1)) : -1;
    const int me = static_cast<int>(t.stages.size());
    for (size_t in : v.inputs) {
      s.input = fifo_index(in);
      t.fifos[s.input].reader = me;
      t.fifos[s.input].unit = s.unit;
    }
    for (size_t out : v.outputs) {
      s.outputs.push_back(fifo_index(out));
      t.fifos[s.outputs.back()].writer = me;
    }
    t.stages.push_back(std::move(s));
  }
  return t;
}

void Gpu::attach_trace(TraceProbes& probes) {
  size_t index = 0;
  for (size_t v = 0; v < m_fifo_views.size(); ++v) {
    bool stand_in = false;
    for (const auto& entry : m_stand_in_view) stand_in = stand_in || entry.second == v;
    if (!stand_in) m_fifo_views[v].attach(probes, index++);
  }
  for (Unit& u : m_units) {
    u.depth->set_fragment_probe(probes.fragment_probe());
    u.rop->set_fragment_probe(probes.fragment_probe());
  }
}

void Gpu::apply_stall_fault() {
  if (m_faults.stalled_fifo.empty()) return;
  const sc_core::sc_time cycle = m_config.cycle();
  const auto stall = [&](auto& fifo) {
    if (m_faults.stalled_fifo != fifo.basename()) return false;
    fifo.inject_random_stalls(0x5EED, 1.0, UINT_MAX, cycle);
    return true;
  };
  bool found = stall(m_commands) || stall(m_command_to_fetch) || stall(m_fetch_to_shader) ||
               stall(m_shader_to_clipper) || stall(m_clipper_to_setup) ||
               stall(m_setup_to_distributor);
  for (Unit& u : m_units) {
    found = stall(*u.jobs) || stall(*u.stamps) || stall(*u.visible) || stall(*u.shaded) || found;
  }
  if (!found) throw std::invalid_argument("Gpu: no FIFO named '" + m_faults.stalled_fifo + "'");
}

uint64_t Gpu::progress_count() const {
  uint64_t n = 0;
  for (const FifoView& f : m_fifo_views) {
    const FifoStats s = f.stats();
    n += s.written + s.read;
  }
  for (unsigned i = 0; i < m_memory.num_clients(); ++i) n += m_memory.client_stats(i).requests;
  return n;
}

Gpu::Sample Gpu::sample() const {
  Sample s;
  for (const FifoView& f : m_fifo_views) {
    const FifoStats st = f.stats();
    s.reader_blocked.push_back(st.reader_blocked);
    s.writer_blocked.push_back(st.writer_blocked);
  }
  s.at = sc_core::sc_time_stamp();
  return s;
}

std::vector<Gpu::StageState> Gpu::stage_states(const Sample& before, const Sample& after) const {
  const auto grew = [](const std::vector<sc_core::sc_time>& a,
                       const std::vector<sc_core::sc_time>& b,
                       size_t i) { return i < a.size() && i < b.size() && b[i] > a[i]; };
  std::vector<StageState> states;
  for (const StageView& v : m_stage_views) {
    StageState state = StageState::busy;
    // Blocked reading an empty FIFO: only a write can wake it. (Blocked on a
    // FIFO that holds items: waiting for one still in flight, so busy.)
    for (size_t f : v.inputs) {
      if (grew(before.reader_blocked, after.reader_blocked, f) &&
          m_fifo_views[f].occupancy() == 0) {
        state = StageState::waiting_on_input;
      }
    }
    for (size_t f : v.outputs) {
      if (grew(before.writer_blocked, after.writer_blocked, f))
        state = StageState::waiting_on_output;
    }
    states.push_back(state);
  }
  return states;
}

std::string Gpu::fifo_report() const {
  std::ostringstream os;
  os << "  FIFOs (items held/depth; items written, read):";
  for (const FifoView& f : m_fifo_views) {
    const FifoStats s = f.stats();
    os << "\n    " << f.name << ": " << f.occupancy() << "/" << f.depth << "; " << s.written
       << " written, " << s.read << " read";
    if (s.injected_stalls > 0) os << "; " << s.injected_stalls << " injected stalls";
  }
  return os.str();
}

std::string Gpu::state_report(const Sample& before, const Sample& after) const {
  const std::vector<StageState> states = stage_states(before, after);
  const auto held = [&](size_t f) {
    return m_fifo_views[f].name + " (" + std::to_string(m_fifo_views[f].occupancy()) + "/" +
           std::to_string(m_fifo_views[f].depth) + ")";
  };
  std::string busy;
  bool all_on_input = true;
  std::ostringstream lines;
  lines << "  stages:";
  for (size_t s = 0; s < m_stage_views.size(); ++s) {
    const StageView& v = m_stage_views[s];
    std::string text = "busy";
    for (size_t f : v.inputs) {
      // Blocked on a FIFO that holds items: the next one is still in flight.
      if (after.reader_blocked.size() > f && after.reader_blocked[f] > before.reader_blocked[f] &&
          m_fifo_views[f].occupancy() > 0) {
        text = "busy (receiving: the next item in " + held(f) + " is in flight)";
      }
    }
    if (states[s] == StageState::waiting_on_input) {
      for (size_t f : v.inputs) text = "waiting on input " + held(f);
    } else if (states[s] == StageState::waiting_on_output) {
      for (size_t f : v.outputs) {
        if (m_fifo_views[f].occupancy() == m_fifo_views[f].depth)
          text = "waiting on output " + held(f);
      }
      if (text == "busy") text = "waiting on output";
    }
    if (states[s] == StageState::busy) busy += (busy.empty() ? "" : ", ") + v.name;
    if (states[s] != StageState::waiting_on_input) all_on_input = false;
    const nlohmann::json c = v.stats->to_json();
    lines << "\n    " << v.name << ": " << text << "; " << c.value("tokens_in", uint64_t{0})
          << " tokens in, " << c.value("tokens_out", uint64_t{0}) << " out";
  }
  bool all_empty = true;
  for (const FifoView& f : m_fifo_views) all_empty = all_empty && f.occupancy() == 0;

  std::string verdict;
  if (!busy.empty()) {
    verdict = "busy without moving an item: " + busy +
              " (a stage stuck, or one item costing more than watchdog_cycles, which the "
              "configuration can raise)";
  } else if (all_on_input && all_empty) {
    verdict =
        "every stage waits for input and every FIFO is empty: an item was lost (the "
        "frame's end never reached every ROP)";
  } else {
    verdict =
        "every stage waits on a FIFO, readers on empty ones and writers on full ones: a "
        "deadlock";
  }
  return verdict + "\n" + lines.str() + "\n" + fifo_report();
}

void Gpu::watchdog() {
  if (!m_watchdog_on) return;
  const uint64_t limit = m_config.watchdog_cycles;
  const sc_core::sc_time cycle = m_config.cycle();
  const sc_core::sc_time window = m_config.cycles(limit);
  const sc_core::sc_time period = m_config.cycles(std::max<uint64_t>(1, limit / 4));
  const sc_core::sc_time memory_latency = m_config.cycles(m_config.memory.latency);
  uint64_t last = progress_count();
  sc_core::sc_time last_progress = sc_core::sc_time_stamp();
  Sample previous = sample();
  for (;;) {
    sc_core::wait(period, m_done_events);
    if (frame_done()) return;
    const sc_core::sc_time now = sc_core::sc_time_stamp();
    const Sample current = sample();
    const uint64_t count = progress_count();
    // Progress: an item moved, a memory request was made, or transfers are
    // still in flight (a tile cache's write-back of a whole frame is issued
    // at once and takes the bus for long after).
    if (count != last || m_memory.bus_free() + memory_latency > now) {
      last = count;
      last_progress = now;
      previous = current;
      continue;
    }
    const std::vector<StageState> states = stage_states(previous, current);
    const bool any_busy = std::find(states.begin(), states.end(), StageState::busy) != states.end();
    if (!any_busy) {
      // Every stage waits on a FIFO: only an item moving could change that,
      // and nothing is left to move one. Stop counting so the kernel runs
      // out of events (run_gpu reports the deadlock); resume if one moves.
      sc_core::wait(m_activity_events | m_done_events);
      if (frame_done()) return;
      last = progress_count();
      last_progress = sc_core::sc_time_stamp();
      previous = sample();
      continue;
    }
    if (now - last_progress < window) {
      previous = current;
      continue;
    }
    std::ostringstream head;
    head << "watchdog: no item moved through any FIFO or the memory for "
         << static_cast<uint64_t>((now - last_progress) / cycle) << " cycles (watchdog_cycles "
         << limit << "; last progress by cycle " << static_cast<uint64_t>(last_progress / cycle)
         << ", now cycle " << static_cast<uint64_t>(now / cycle) << "): ";
    m_watchdog_report = head.str() + state_report(previous, current);
    // SystemC reports every sc_stop() as an info line on stdout ("Simulation
    // stopped by user."); the report above says why it stopped.
    sc_core::sc_report_handler::set_actions("/OSCI/SystemC", sc_core::SC_INFO,
                                            sc_core::SC_DO_NOTHING);
    sc_core::sc_stop();
    return;
  }
}

// --- Conservation -------------------------------------------------------------

namespace {

uint64_t assembled_triangles(PrimitiveType type, uint64_t slots) {
  if (slots < 3) return 0;
  return type == PrimitiveType::triangles ? slots / 3 : slots - 2;
}

// Reads counters out of a stats_json() dump and collects violated rules.
class Ledger {
 public:
  explicit Ledger(const nlohmann::json& stats) : m_stats(stats) {}

  uint64_t stage(const std::string& name, const std::string& counter) {
    return read({"stages", name, counter});
  }
  uint64_t fifo(const std::string& name, const std::string& field) {
    return read({"fifos", name, field});
  }
  // "where: <a> = <va>, but <b> = <vb>" unless va == vb.
  void equal(const std::string& where, const std::string& a, uint64_t va, const std::string& b,
             uint64_t vb) {
    if (va != vb)
      fail(where, a + " = " + std::to_string(va) + ", but " + b + " = " + std::to_string(vb));
  }
  void at_most(const std::string& where, const std::string& a, uint64_t va, const std::string& b,
               uint64_t vb) {
    if (va > vb)
      fail(where, a + " = " + std::to_string(va) + " exceeds " + b + " = " + std::to_string(vb));
  }
  void fail(const std::string& where, const std::string& what) {
    m_errors.push_back(where + ": " + what);
  }
  const nlohmann::json& stats() const { return m_stats; }
  std::vector<std::string> take() { return std::move(m_errors); }

 private:
  uint64_t read(std::initializer_list<std::string> path) {
    const nlohmann::json* j = &m_stats;
    std::string where;
    for (const std::string& key : path) {
      where += (where.empty() ? "" : ".") + key;
      if (!j->is_object() || !j->contains(key)) {
        fail(where, "missing from the statistics");
        return 0;
      }
      j = &(*j)[key];
    }
    if (j->is_number_unsigned()) return j->get<uint64_t>();
    if (j->is_number_integer() && j->get<int64_t>() >= 0) return j->get<uint64_t>();
    if (j->is_number_float() && j->get<double>() >= 0.0)
      return static_cast<uint64_t>(j->get<double>());
    fail(where, "not a count: " + j->dump());
    return 0;
  }

  const nlohmann::json& m_stats;
  std::vector<std::string> m_errors;
};

}  // namespace

std::vector<std::string> conservation_errors(const nlohmann::json& stats, const FrameState& frame) {
  Ledger l(stats);
  if (!stats.contains("units") || !stats["units"].is_array() || stats["units"].empty()) {
    l.fail("units", "missing from the statistics");
    return l.take();
  }
  const size_t units = stats["units"].size();
  uint64_t slots = 0, triangles = 0;
  for (const DrawState& d : frame.draws) {
    slots += d.buffers.slot_count;
    triangles += assembled_triangles(d.primitive, d.buffers.slot_count);
  }

  // Every FIFO delivered every item it took, and holds none at the end.
  if (stats.contains("fifos") && stats["fifos"].is_object()) {
    for (const auto& item : stats["fifos"].items()) {
      l.equal("fifo " + item.key(), "items read", l.fifo(item.key(), "read"), "items written",
              l.fifo(item.key(), "written"));
    }
  } else {
    l.fail("fifos", "missing from the statistics");
  }
  // Producer's count of items written and consumer's count of items read
  // against the FIFO between them.
  const auto link = [&](const std::string& producer, const std::string& fifo,
                        const std::string& consumer) {
    if (!producer.empty()) {
      l.equal(producer, "tokens_out", l.stage(producer, "tokens_out"), fifo + ".written",
              l.fifo(fifo, "written"));
    }
    l.equal(consumer, "tokens_in", l.stage(consumer, "tokens_in"), fifo + ".read",
            l.fifo(fifo, "read"));
  };
  link("", "commands", "command_processor");
  link("command_processor", "command_to_fetch", "vertex_fetch");
  link("vertex_fetch", "fetch_to_shader", "vertex_shader");
  link("vertex_shader", "shader_to_clipper", "clipper");
  link("clipper", "clipper_to_setup", "triangle_setup");
  link("triangle_setup", "setup_to_distributor", "tile_distributor");

  // Command processor: commands in = commands out.
  const std::string cp = "command_processor";
  const uint64_t draws = l.stage(cp, "draws"), clears = l.stage(cp, "clears"),
                 frames = l.stage(cp, "frames");
  const uint64_t control = clears + frames;  // control tokens, forwarded by every stage
  l.equal(cp, "draws", draws, "draws in the frame", frame.draws.size());
  l.equal(cp, "frames", frames, "frames run", 1);
  l.equal(cp, "tokens_in", l.stage(cp, "tokens_in"), "draws + clears + frames",
          draws + clears + frames);
  l.equal(cp, "tokens_out", l.stage(cp, "tokens_out"), "tokens_in", l.stage(cp, "tokens_in"));

  // Vertex fetch: draws become batches of slots; every slot is invalid, a
  // cache hit or fetched.
  const std::string vf = "vertex_fetch";
  const uint64_t batches = l.stage(vf, "batches");
  l.equal(vf, "draws", l.stage(vf, "draws"), "command_processor.draws", draws);
  l.equal(vf, "tokens_in", l.stage(vf, "tokens_in"), "draws + control tokens", draws + control);
  l.equal(vf, "tokens_out", l.stage(vf, "tokens_out"), "batches + control tokens",
          batches + control);
  l.equal(vf, "slots", l.stage(vf, "slots"), "slots of the frame's draws", slots);
  l.equal(
      vf, "slots", l.stage(vf, "slots"), "invalid_slots + cache_hits + vertices_fetched",
      l.stage(vf, "invalid_slots") + l.stage(vf, "cache_hits") + l.stage(vf, "vertices_fetched"));

  // Vertex shader: every fetched vertex is shaded.
  const std::string vs = "vertex_shader";
  l.equal(vs, "tokens_out", l.stage(vs, "tokens_out"), "tokens_in", l.stage(vs, "tokens_in"));
  l.equal(vs, "vertices_shaded", l.stage(vs, "vertices_shaded"), "vertex_fetch.vertices_fetched",
          l.stage(vf, "vertices_fetched"));

  // Clipper: triangles in = invalid + clipped away + survivors; every
  // survivor leaves as one triangle or more.
  const std::string cl = "clipper";
  const uint64_t tri_in = l.stage(cl, "triangles_in");
  const uint64_t dropped = l.stage(cl, "triangles_invalid") + l.stage(cl, "triangles_clipped_away");
  const uint64_t after_clip = l.stage(cl, "triangles_after_clip");
  l.equal(cl, "triangles_in", tri_in, "triangles assembled from the frame's draws", triangles);
  l.at_most(cl, "triangles_invalid + triangles_clipped_away", dropped, "triangles_in", tri_in);
  const uint64_t survivors = tri_in >= dropped ? tri_in - dropped : 0;
  l.at_most(cl, "survivors (triangles_in - invalid - clipped_away)", survivors,
            "triangles_after_clip", after_clip);
  l.at_most(cl, "triangles_clipped", l.stage(cl, "triangles_clipped"), "survivors", survivors);
  l.equal(cl, "cache_reads", l.stage(cl, "cache_reads"), "vertex_fetch.cache_hits",
          l.stage(vf, "cache_hits"));
  l.equal(cl, "tokens_in", l.stage(cl, "tokens_in"), "vertex_fetch batches + control tokens",
          batches + control);
  l.equal(cl, "tokens_out", l.stage(cl, "tokens_out"), "triangles_after_clip + control tokens",
          after_clip + control);

  // Triangle setup: triangles in = degenerate + culled + rasterized; the
  // rasterized ones leave unless their box holds no pixel centre.
  const std::string ts = "triangle_setup";
  const uint64_t rasterized = l.stage(ts, "triangles_rasterized");
  const uint64_t offscreen = l.stage(ts, "triangles_offscreen");
  l.equal(ts, "tokens_in", l.stage(ts, "tokens_in"),
          "clipper.triangles_after_clip + control tokens", after_clip + control);
  l.equal(ts, "clipper.triangles_after_clip", after_clip,
          "triangles_degenerate + triangles_culled + triangles_rasterized",
          l.stage(ts, "triangles_degenerate") + l.stage(ts, "triangles_culled") + rasterized);
  l.at_most(ts, "triangles_offscreen", offscreen, "triangles_rasterized", rasterized);
  l.equal(ts, "tokens_out", l.stage(ts, "tokens_out"),
          "triangles_rasterized - triangles_offscreen + control tokens",
          (rasterized >= offscreen ? rasterized - offscreen : 0) + control);

  // Tile distributor: each triangle goes to one unit or more; control
  // tokens to every unit.
  const std::string td = "tile_distributor";
  const uint64_t td_in = l.stage(td, "tokens_in");
  const uint64_t work_in = td_in >= control ? td_in - control : 0;
  const uint64_t sent = l.stage(td, "triangles_sent");
  l.equal(td, "tokens_out", l.stage(td, "tokens_out"), "triangles_sent + control tokens x units",
          sent + control * units);
  l.at_most(td, "triangles read", work_in, "triangles_sent", sent);
  l.at_most(td, "triangles_sent", sent, "triangles read x units", work_in * units);
  uint64_t sent_sum = 0, out_sum = 0;
  for (size_t u = 0; u < units; ++u) {
    const std::string n = std::to_string(u);
    const std::string jobs = "distributor_to_rasterizer_" + n;
    const uint64_t sent_u = l.stage(td, "triangles_sent_unit" + n);
    sent_sum += sent_u;
    out_sum += l.fifo(jobs, "written");
    l.equal(td, jobs + ".written", l.fifo(jobs, "written"),
            "triangles_sent_unit" + n + " + control tokens", sent_u + control);

    // Rasterizer: every triangle sent to the unit is walked.
    const std::string tr = "tile_rasterizer_" + n, dt = "depth_test_" + n, ip = "interpolator_" + n,
                      rop = "rop_" + n;
    link("", jobs, tr);
    l.equal(tr, "triangles", l.stage(tr, "triangles"), td + ".triangles_sent_unit" + n, sent_u);
    l.at_most(tr, "stamps_emitted", l.stage(tr, "stamps_emitted"),
              "stamps_evaluated + stamps_accepted",
              l.stage(tr, "stamps_evaluated") + l.stage(tr, "stamps_accepted"));
    l.at_most(tr, "control tokens", control, "tokens_out", l.stage(tr, "tokens_out"));
    link(tr, "rasterizer_to_depth_" + n, dt);

    // Depth test: stamps and pixels in are the rasterizer's; the ones that
    // fail are dropped, so at most as many pass.
    l.equal(dt, "stamps", l.stage(dt, "stamps"), tr + ".stamps_emitted",
            l.stage(tr, "stamps_emitted"));
    l.equal(dt, "fragments_in", l.stage(dt, "fragments_in"), tr + ".fragments",
            l.stage(tr, "fragments"));
    l.at_most(dt, "fragments_passed", l.stage(dt, "fragments_passed"), "fragments_in",
              l.stage(dt, "fragments_in"));
    l.at_most(dt, "stamps_passed", l.stage(dt, "stamps_passed"), "stamps", l.stage(dt, "stamps"));
    l.at_most(dt, "tokens_out", l.stage(dt, "tokens_out"), "tokens_in", l.stage(dt, "tokens_in"));
    l.at_most(dt, "control tokens", control, "tokens_out", l.stage(dt, "tokens_out"));
    link(dt, "depth_to_interpolator_" + n, ip);

    // Interpolator: shades exactly the pixels that passed.
    l.equal(ip, "tokens_out", l.stage(ip, "tokens_out"), "tokens_in", l.stage(ip, "tokens_in"));
    l.equal(ip, "stamps", l.stage(ip, "stamps"), dt + ".stamps_passed",
            l.stage(dt, "stamps_passed"));
    l.equal(ip, "fragments", l.stage(ip, "fragments"), dt + ".fragments_passed",
            l.stage(dt, "fragments_passed"));
    link(ip, "interpolator_to_rop_" + n, rop);

    // ROP: retires every token; writes at most the pixels it received.
    l.equal(rop, "tokens_out", l.stage(rop, "tokens_out"), "tokens_in", l.stage(rop, "tokens_in"));
    l.equal(rop, "stamps", l.stage(rop, "stamps"), ip + ".stamps", l.stage(ip, "stamps"));
    l.equal(rop, "fragments_in", l.stage(rop, "fragments_in"), ip + ".fragments",
            l.stage(ip, "fragments"));
    l.at_most(rop, "fragments_written", l.stage(rop, "fragments_written"), "fragments_in",
              l.stage(rop, "fragments_in"));
    l.equal(rop, "frames", l.stage(rop, "frames"), "frames run", 1);
  }
  l.equal(td, "sum of triangles_sent_unit*", sent_sum, "triangles_sent", sent);
  l.equal(td, "sum of distributor_to_rasterizer_*.written", out_sum, "tokens_out",
          l.stage(td, "tokens_out"));

  // Memory: no request was answered with an error.
  if (stats.contains("memory") && stats["memory"].contains("clients") &&
      stats["memory"]["clients"].is_object()) {
    for (const auto& c : stats["memory"]["clients"].items()) {
      const uint64_t errors = c.value().value("errors", uint64_t{0});
      if (errors != 0) {
        l.fail("memory client " + c.key(),
               std::to_string(errors) + " requests answered with an error");
      }
    }
  } else {
    l.fail("memory.clients", "missing from the statistics");
  }
  return l.take();
}

std::vector<std::string> Gpu::conservation_errors(uint64_t cycles) const {
  return gpusim::conservation_errors(stats_json(cycles), m_frame);
}

}  // namespace gpusim
