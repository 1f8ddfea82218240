#include "stages/gpu.h"

#include <functional>
#include <string>

namespace gpusim {

Gpu::Gpu(sc_core::sc_module_name name, const GpuConfig& config, const FrameState& frame,
         uint64_t memory_bytes, UnitOrder order, const Interposers* interposers)
    : sc_core::sc_module(name),
      m_config(config),
      m_memory("memory", memory_bytes, config.memory.latency, config.memory.bytes_per_cycle,
               config.cycle(), config.memory.channels, config.memory.interleave_bytes),
      m_topology(config, frame, interposers),
      m_command_processor("command_processor", config, frame),
      m_fetch("vertex_fetch", config, frame),
      m_shader("vertex_shader", config, frame),
      m_clipper("clipper", config, frame),
      m_setup("primitive_setup", config, frame),
      m_distributor("tile_distributor", config, frame) {
  Topology& t = m_topology;
  m_commands = &t.connect<Command>("commands", -1, nullptr, nullptr, m_command_processor,
                                   m_command_processor.in);
  t.connect("command_to_fetch", -1, &m_command_processor, &m_command_processor.out, m_fetch,
            m_fetch.in);
  t.connect("fetch_to_shader", -1, &m_fetch, &m_fetch.out, m_shader, m_shader.in);
  t.connect("shader_to_clipper", -1, &m_shader, &m_shader.out, m_clipper, m_clipper.in);
  t.connect("clipper_to_setup", -1, &m_clipper, &m_clipper.out, m_setup, m_setup.in);
  t.connect("setup_to_distributor", -1, &m_setup, &m_setup.out, m_distributor, m_distributor.in);

  m_units.resize(config.units);
  for (unsigned i = 0; i < config.units; ++i) {
    const unsigned u = order == UnitOrder::ascending ? i : config.units - 1 - i;
    const int n = static_cast<int>(u);
    Unit& unit = m_units[u];
    const auto named = [n](const char* kind) { return PipelineStage::instance_name(kind, n); };
    unit.rasterizer =
        std::make_unique<TileRasterizer>(named("tile_rasterizer").c_str(), config, frame, u);
    unit.depth = std::make_unique<DepthTest>(named("depth_test").c_str(), config, frame, u);
    unit.interpolator =
        std::make_unique<Interpolator>(named("interpolator").c_str(), config, frame, u);
    unit.rop = std::make_unique<Rop>(named("rop").c_str(), config, frame, u);

    if (config.hierarchical_z.enabled) {
      HzUpdateLink& hz =
          t.connect_link<HzUpdateLink>("hz_update", n, *unit.depth, *unit.rasterizer,
                                       config.hierarchical_z.update_latency, config.cycle());
      unit.rasterizer->set_hz_link(&hz);
      unit.depth->set_hz_link(&hz);
    }

    t.connect("distributor_to_rasterizer", n, &m_distributor, &m_distributor.out[u],
              *unit.rasterizer, unit.rasterizer->in);
    t.connect("rasterizer_to_depth", n, unit.rasterizer.get(), &unit.rasterizer->out, *unit.depth,
              unit.depth->in);
    t.connect("depth_to_interpolator", n, unit.depth.get(), &unit.depth->out, *unit.interpolator,
              unit.interpolator->in);
    if (frame.textured()) {
      // The ROP's FIFO keeps its name: a FIFO belongs to its reader.
      unit.texture = std::make_unique<TextureUnit>(named("texture_unit").c_str(), config, frame, u);
      t.connect("interpolator_to_texture", n, unit.interpolator.get(), &unit.interpolator->out,
                *unit.texture, unit.texture->in);
      t.connect("interpolator_to_rop", n, unit.texture.get(), &unit.texture->out, *unit.rop,
                unit.rop->in);
    } else {
      t.connect("interpolator_to_rop", n, unit.interpolator.get(), &unit.interpolator->out,
                *unit.rop, unit.rop->in);
    }
  }
  if (frame.needs_resolve()) {
    m_resolve = std::make_unique<Resolve>("resolve", config, frame);
    for (unsigned u = 0; u < config.units; ++u) {
      t.connect("rop_to_resolve", static_cast<int>(u), m_units[u].rop.get(), &m_units[u].rop->done,
                *m_resolve, m_resolve->in[u]);
    }
  }
  // Memory clients are numbered in bind order: vertex fetch, then in unit
  // order whatever order the units were elaborated in, the resolve last.
  t.connect_memory(m_fetch, m_fetch.mem, m_memory);
  for (const Unit& unit : m_units) {
    t.connect_memory(*unit.depth, unit.depth->mem, m_memory);
    t.connect_memory(*unit.rop, unit.rop->mem, m_memory);
    if (unit.texture) t.connect_memory(*unit.texture, unit.texture->mem, m_memory);
    m_done_events |= unit.rop->frame_done_event();
  }
  if (m_resolve) {
    t.connect_memory(*m_resolve, m_resolve->mem, m_memory);
    m_done_events |= m_resolve->frame_done_event();
  }
  t.finish();
  declare_stats();
}

void Gpu::reset() {
  m_topology.reset();
  m_frame_cycles = 0;
  m_reset_event.notify();
}

bool Gpu::frame_done() const {
  if (m_resolve) return m_resolve->frame_done();
  for (const Unit& u : m_units) {
    if (!u.rop->frame_done()) return false;
  }
  return true;
}

void Gpu::set_last_writer(std::vector<int64_t>* per_pixel) {
  for (Unit& u : m_units) u.rop->set_last_writer(per_pixel);
}

void Gpu::attach_trace(TraceProbes& probes) {
  m_topology.attach_trace(probes);
  m_memory.set_probe(probes.memory_probe());
}

PipelineCounts Gpu::pipeline_counts() const {
  PipelineCounts counts;
  // Counters both stages keep add up: polygon mode's triangles are
  // degenerate or culled in the clipper, filled ones in setup.
  m_clipper.add_pipeline_counts(counts);
  m_setup.add_pipeline_counts(counts);
  const FragmentCounts fragments = fragment_counts();
  counts.fragments_generated = fragments.generated;
  counts.fragments_passed_depth = fragments.passed_depth;
  counts.fragments_written = fragments.written;
  counts.samples_generated = fragments.samples_generated;
  counts.samples_passed_depth = fragments.samples_passed_depth;
  counts.samples_written = fragments.samples_written;
  // Every unit executes every clear on the tiles it owns: one unit's count
  // is the frame's.
  counts.color_clears = m_units.front().rop->color_clears();
  counts.depth_clears = m_units.front().depth->depth_clears();
  return counts;
}

Gpu::FragmentCounts Gpu::fragment_counts() const {
  FragmentCounts n;
  for (const Unit& u : m_units) {
    // Hierarchical Z's culled tiles were covered too (the golden model's count).
    n.generated += u.rasterizer->fragments() + u.rasterizer->hz_fragments_culled();
    n.passed_depth += u.depth->fragments_passed();
    n.written += u.rop->fragments_written();
    n.samples_generated += u.rasterizer->samples() + u.rasterizer->hz_samples_culled();
    n.samples_passed_depth += u.depth->samples_passed();
    n.samples_written += u.rop->samples_written();
  }
  return n;
}

void Gpu::declare_stats() {
  StatGroup& g = m_stats;
  g.gauge("cycles", "cycles", "the frame's length", [this] { return m_frame_cycles; });
  g.formula("simulated_seconds", "seconds", "cycles at the configured clock",
            [this] { return static_cast<double>(m_frame_cycles) / (m_config.clock_mhz * 1e6); });

  // Achieved over the frame (a frame of 0 cycles counts as 1) and the peak.
  const auto per_clock = [this](std::function<uint64_t()> count) {
    return [this, count] {
      return static_cast<double>(count()) / (m_frame_cycles ? m_frame_cycles : 1.0);
    };
  };
  StatGroup& rates = g.group("rates");
  rates.formula("setup_triangles_per_clock", "primitives/cycle",
                "primitives set up per cycle over the frame",
                per_clock([this] { return m_setup.tokens_in(); }));
  rates.formula("setup_triangles_per_clock_peak", "primitives/cycle", "1 / the setup's ii",
                [this] { return 1.0 / m_setup.cost().ii; });
  rates.formula("raster_pixels_per_clock", "fragments/cycle",
                "fragments rasterized per cycle over the frame, all units", per_clock([this] {
                  uint64_t n = 0;
                  for (const Unit& u : m_units) n += u.rasterizer->fragments();
                  return n;
                }));
  rates.formula("raster_pixels_per_clock_peak", "fragments/cycle",
                "units x stamp pixels / the rasterizer's ii", [this] {
                  const double stamp_pixels =
                      static_cast<double>(m_config.stamp[0]) * m_config.stamp[1];
                  return m_config.units * stamp_pixels / m_units.front().rasterizer->cost().ii;
                });

  m_topology.add_stats(g);

  StatCollection& units =
      g.collection("units", StatGroup::Layout::array, StatGroup::Describe::merged);
  for (unsigned i = 0; i < m_units.size(); ++i) {
    StatGroup& u = units.make("unit" + std::to_string(i));
    const TileRasterizer& r = *m_units[i].rasterizer;
    u.gauge("unit", "index", "the raster unit", [i] { return i; });
    u.gauge("tiles", "tiles", "tiles its rasterizer visited", [&r] { return r.tiles_visited(); });
    u.gauge("stamps", "stamps", "stamps its rasterizer emitted",
            [&r] { return r.stamps_emitted(); });
    u.gauge("fragments", "fragments", "fragments its rasterizer generated",
            [&r] { return r.fragments(); });
  }
  g.attach(m_memory.stat_group());
}

nlohmann::json Gpu::stats_json(uint64_t cycles) {
  m_frame_cycles = cycles;
  nlohmann::json j = m_stats.to_json();
  j["netlist"] = nlohmann::json::parse(to_json(m_topology.trace_tables()).dump());
  j["descriptions"] = m_stats.descriptions();
  return j;
}

}  // namespace gpusim
