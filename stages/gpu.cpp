#include "stages/gpu.h"

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
         uint64_t memory_bytes)
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
  m_command_processor.in(m_commands);
  m_command_processor.out(m_command_to_fetch);
  m_fetch.in(m_command_to_fetch);
  m_fetch.out(m_fetch_to_shader);
  m_fetch.mem.bind(m_memory);
  m_shader.in(m_fetch_to_shader);
  m_shader.out(m_shader_to_clipper);
  m_clipper.in(m_shader_to_clipper);
  m_clipper.out(m_clipper_to_setup);
  m_setup.in(m_clipper_to_setup);
  m_setup.out(m_setup_to_distributor);
  m_distributor.in(m_setup_to_distributor);

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
    unit.rasterizer->in(*unit.jobs);
    unit.rasterizer->out(*unit.stamps);
    unit.depth->in(*unit.stamps);
    unit.depth->out(*unit.visible);
    unit.depth->mem.bind(m_memory);
    unit.interpolator->in(*unit.visible);
    unit.interpolator->out(*unit.shaded);
    unit.rop->in(*unit.shaded);
    unit.rop->mem.bind(m_memory);
    m_done_events |= unit.rop->frame_done_event();
  }
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
