#include "stages/tile_distributor.h"

#include <algorithm>
#include <string>

namespace gpusim {

namespace {

// Conservation (testbench/sim/conservation.h): how its counters balance.
void conserve(ConservationLedger& l) {
  const ConservationLedger::Frame& f = l.frame();
  // Each triangle goes to one unit or more; control tokens to every
  // unit, so each output carries its unit's triangles and them all.
  const uint64_t in = l.get("tokens_in");
  const uint64_t work_in = in >= f.control ? in - f.control : 0;
  const uint64_t sent = l.get("triangles_sent");
  l.equal("tokens_out", l.get("tokens_out"), "triangles_sent + control tokens x units",
          sent + f.control * f.units);
  l.at_most("triangles read", work_in, "triangles_sent", sent);
  l.at_most("triangles_sent", sent, "triangles read x units", work_in * f.units);
  uint64_t sum = 0;
  for (const ConservationLedger::Output& out : l.outputs()) {
    const std::string u = std::to_string(out.unit);
    const uint64_t sent_u = l.get("triangles_sent_unit" + u);
    sum += sent_u;
    l.equal(out.fifo + ".written", l.fifo(out.fifo, "written"),
            "triangles_sent_unit" + u + " + control tokens", sent_u + f.control);
    // Every primitive sent to a unit (triangles_sent counts every
    // kind) is received by its rasterizer, which counts them by kind.
    const std::string& tr = out.reader;
    l.check_equal(tr, "triangles + lines + points",
                  l.stage(tr, "triangles") + l.stage(tr, "lines") + l.stage(tr, "points"),
                  l.name() + ".triangles_sent_unit" + u, sent_u);
  }
  l.equal("sum of triangles_sent_unit*", sum, "triangles_sent", sent);
}

}  // namespace

const StageSpec& TileDistributor::spec() {
  static const StageSpec s{
      "tile_distributor",
      StagePlacement::front_end,
      /*optional=*/false,
      {/*ii=*/1, /*latency=*/2},
      "primitive sent to a unit",
      "one unit's FIFO written per cycle; a control token is broadcast in one",
      "setup packets read",
      "packets written, summed over units",
      {"setup_to_distributor"},
      &conserve,
      StageTrace{TraceItem::primitive, {}, FragmentSite::none},
      {{"", "`ii` × units the primitive goes to",
        "A unit gets a primitive when its box touches a tile the unit owns. Units are written in "
        "order; a full unit FIFO blocks it (head of line)."}}};
  return s;
}
GPUSIM_REGISTER_STAGE(TileDistributor);

TileDistributor::TileDistributor(sc_core::sc_module_name name, const GpuConfig& config,
                                 const FrameState& frame)
    : PipelineStage(name, spec(), -1, config, frame),
      in("in"),
      out("out", config.units),
      m_tile_shift(log2_side(config.tile_size)),
      m_targets(config.units, false) {
  for (unsigned u = 0; u < config.units; ++u) {
    const std::string n = std::to_string(u);
    m_unit_triangles.push_back(
        &m_stats.counter("triangles_sent_unit" + n, "triangles", "triangles sent to unit " + n));
  }
  SC_HAS_PROCESS(TileDistributor);
  SC_THREAD(run);
}

unsigned TileDistributor::target_units(const RasterPrimitive& t, std::vector<bool>& targets) const {
  const unsigned units = m_config.units;
  targets.assign(units, false);
  if (t.x0 > t.x1 || t.y0 > t.y1) return 0;
  // The box is inside the framebuffer, so tile indices are non-negative.
  const int tx0 = t.x0 >> m_tile_shift, tx1 = t.x1 >> m_tile_shift;
  const int ty0 = t.y0 >> m_tile_shift, ty1 = t.y1 >> m_tile_shift;
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

void TileDistributor::reset_state() {
  m_targets.clear();
}

void TileDistributor::run() {
  const unsigned units = m_config.units;
  for (;;) {
    SetupPacket p = receive(in);
    const PacketKind kind = p.kind;
    unsigned sends = units;
    if (kind == PacketKind::work) {
      sends = target_units(*p.primitive, m_targets);
    } else {
      m_targets.assign(units, true);
    }
    const uint64_t busy =
        uint64_t{m_cost.ii} * (kind == PacketKind::work ? std::max(1u, sends) : 1u);
    work(busy);
    const sc_core::sc_time ready = local_time() + m_latency;
    // The last unit sent to takes the packet itself (a moving write leaves p
    // stale), the others a copy: one reference count update less.
    unsigned last = 0;
    for (unsigned u = 0; u < units; ++u) {
      if (m_targets[u]) last = u;
    }
    for (unsigned u = 0; u < units; ++u) {
      if (!m_targets[u]) continue;
      // Every copy is ready at the same time: a unit's full FIFO delays only
      // the copies after it, by the time it blocked (Fifo::write).
      if (u == last) {
        emit_at(out[u], std::move(p), ready);
      } else {
        emit_at(out[u], p, ready);
      }
      if (kind == PacketKind::work) {
        ++m_triangles_sent;
        ++*m_unit_triangles[u];
      }
    }
  }
}

}  // namespace gpusim
