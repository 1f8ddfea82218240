#include "stages/tile_distributor.h"

#include <algorithm>
#include <string>

namespace gpusim {

TileDistributor::TileDistributor(sc_core::sc_module_name name, const GpuConfig& config,
                                 const FrameState& frame)
    : sc_core::sc_module(name),
      in("in"),
      out("out", config.units),
      m_config(config),
      m_frame(frame),
      m_cost(config.stage("tile_distributor")),
      m_targets(config.units, false) {
  for (unsigned u = 0; u < config.units; ++u) {
    const std::string n = std::to_string(u);
    m_unit_triangles.push_back(
        &m_stats.counter("triangles_sent_unit" + n, "triangles sent to unit " + n));
  }
  SC_HAS_PROCESS(TileDistributor);
  SC_THREAD(run);
}

unsigned TileDistributor::target_units(const RasterTriangle& t, std::vector<bool>& targets) const {
  const unsigned units = m_config.units;
  targets.assign(units, false);
  if (t.x0 > t.x1 || t.y0 > t.y1) return 0;
  // The box is inside the framebuffer, so tile indices are non-negative.
  const int ts = static_cast<int>(m_config.tile_size);
  const int tx0 = t.x0 / ts, tx1 = t.x1 / ts, ty0 = t.y0 / ts, ty1 = t.y1 / ts;
  unsigned found = 0;
  // Stops as soon as every unit is found: a large box finds them all within
  // its first few tiles whatever the ownership pattern spreads like.
  for (int ty = ty0; ty <= ty1 && found < units; ++ty) {
    for (int tx = tx0; tx <= tx1 && found < units; ++tx) {
      const unsigned u = tile_owner(tx, ty, units);
      if (!targets[u]) {
        targets[u] = true;
        ++found;
      }
    }
  }
  return found;
}

void TileDistributor::run() {
  const unsigned units = m_config.units;
  for (;;) {
    const SetupPacket p = in->read();
    ++m_tokens_in;
    unsigned sends = units;
    if (p.kind == PacketKind::work) {
      sends = target_units(*p.triangle, m_targets);
    } else {
      m_targets.assign(units, true);
    }
    const uint64_t busy =
        uint64_t{m_cost.ii} * (p.kind == PacketKind::work ? std::max(1u, sends) : 1u);
    sc_core::wait(m_config.cycles(busy));
    m_busy_cycles += busy;
    const sc_core::sc_time ready = sc_core::sc_time_stamp() + m_config.cycles(m_cost.latency);
    for (unsigned u = 0; u < units; ++u) {
      if (!m_targets[u]) continue;
      out[u]->write(p, ready);
      ++m_tokens_out;
      if (p.kind == PacketKind::work) {
        ++m_triangles_sent;
        ++*m_unit_triangles[u];
      }
    }
  }
}

}  // namespace gpusim
