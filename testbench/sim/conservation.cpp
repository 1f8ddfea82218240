#include "testbench/sim/conservation.h"

#include <algorithm>

#include "hw/stage_spec.h"
#include "testbench/sim/gpu_run.h"

namespace gpusim {
namespace {

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

// A stage's view of the ledger, for its spec's rules (hw/stage_spec.h).
class StageLedger : public ConservationLedger {
 public:
  StageLedger(Ledger& l, const NetlistTables& netlist, const NetlistTables::Stage& stage,
              const Frame& frame)
      : m_l(l), m_netlist(netlist), m_stage(stage), m_frame(frame) {}

  const std::string& name() const override { return m_stage.name; }
  const Frame& frame() const override { return m_frame; }
  uint64_t get(const std::string& counter) override { return m_l.stage(m_stage.name, counter); }
  uint64_t stage(const std::string& stage, const std::string& counter) override {
    return m_l.stage(stage, counter);
  }
  uint64_t fifo(const std::string& fifo, const std::string& field) override {
    return m_l.fifo(fifo, field);
  }
  std::string upstream(const std::string& kind) const override {
    const NetlistTables::Stage* s = &m_stage;
    while (!s->inputs.empty()) {
      const int w = m_netlist.fifos[s->inputs[0]].writer;
      if (w < 0) break;
      s = &m_netlist.stages[w];
      if (s->kind == kind) return s->name;
    }
    return "host";
  }
  std::vector<Output> outputs() const override {
    std::vector<Output> out;
    for (int f : m_stage.outputs) {
      const NetlistTables::Fifo& fifo = m_netlist.fifos[f];
      out.push_back({fifo.name, m_netlist.stages[fifo.reader].name, fifo.unit});
    }
    return out;
  }
  void check_equal(const std::string& where, const std::string& a, uint64_t va,
                   const std::string& b, uint64_t vb) override {
    m_l.equal(where, a, va, b, vb);
  }
  void check_at_most(const std::string& where, const std::string& a, uint64_t va,
                     const std::string& b, uint64_t vb) override {
    m_l.at_most(where, a, va, b, vb);
  }

 private:
  Ledger& m_l;
  const NetlistTables& m_netlist;
  const NetlistTables::Stage& m_stage;
  const Frame& m_frame;
};

}  // namespace

std::vector<std::string> conservation_errors(const nlohmann::json& stats,
                                             const NetlistTables& netlist,
                                             const FrameState& frame) {
  Ledger l(stats);
  if (!stats.contains("fifos") || !stats["fifos"].is_object()) {
    l.fail("fifos", "missing from the statistics");
    return l.take();
  }

  // Every FIFO delivered every item it took, and holds none at the end.
  for (const NetlistTables::Fifo& f : netlist.fifos) {
    l.equal("fifo " + f.name, "items read", l.fifo(f.name, "read"), "items written",
            l.fifo(f.name, "written"));
  }
  // Every stage read what its inputs delivered and wrote what its outputs
  // took.
  for (const NetlistTables::Stage& s : netlist.stages) {
    uint64_t read = 0, written = 0;
    std::string inputs, outputs;
    for (int f : s.inputs) {
      read += l.fifo(netlist.fifos[f].name, "read");
      inputs += (inputs.empty() ? "" : " + ") + netlist.fifos[f].name + ".read";
    }
    for (int f : s.outputs) {
      written += l.fifo(netlist.fifos[f].name, "written");
      outputs += (outputs.empty() ? "" : " + ") + netlist.fifos[f].name + ".written";
    }
    l.equal(s.name, "tokens_in", l.stage(s.name, "tokens_in"), inputs, read);
    if (!s.outputs.empty())
      l.equal(s.name, "tokens_out", l.stage(s.name, "tokens_out"), outputs, written);
  }

  // Each stage's own rules, from its spec.
  ConservationLedger::Frame totals;
  for (const NetlistTables::Stage& s : netlist.stages)
    totals.units = std::max<uint64_t>(totals.units, s.unit + 1);
  uint64_t assembled[3] = {0, 0, 0};  // by PrimitiveKind
  for (const DrawState& d : frame.draws) {
    totals.slots += d.buffers.slot_count;
    assembled[static_cast<int>(primitive_kind_of(d.primitive))] +=
        primitive_count(d.primitive, d.buffers.slot_count);
  }
  totals.draws = frame.draws.size();
  totals.triangles = assembled[static_cast<int>(PrimitiveKind::triangle)];
  totals.lines = assembled[static_cast<int>(PrimitiveKind::line)];
  totals.points = assembled[static_cast<int>(PrimitiveKind::point)];
  // The frame clear, the draw list's clears, and the end of frame.
  totals.clears = frame.clears.size() + 1;
  totals.control = totals.clears + 1;
  for (size_t n = 0; n <= frame.clears.size(); ++n) {
    totals.color_clears += frame.clear(n).color;
    totals.depth_clears += frame.clear(n).depth;
  }
  for (const NetlistTables::Stage& s : netlist.stages) {
    const StageSpec* spec = StageRegistry::find(s.kind);
    if (spec == nullptr) {
      l.fail(s.name, "no registered stage of kind " + s.kind);
      continue;
    }
    if (spec->conservation == nullptr) continue;
    StageLedger stage(l, netlist, s, totals);
    spec->conservation(stage);
  }

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

std::vector<std::string> pipeline_count_errors(const PipelineCounts& c) {
  std::vector<std::string> errors;
  const uint64_t in = c.triangles_in, invalid = c.triangles_invalid,
                 away = c.triangles_clipped_away, clipped = c.triangles_clipped,
                 after = c.triangles_after_clip, degenerate = c.triangles_degenerate,
                 culled = c.triangles_culled, rasterized = c.triangles_rasterized,
                 offscreen = c.triangles_offscreen, unfilled = c.triangles_unfilled,
                 generated = c.fragments_generated, passed = c.fragments_passed_depth,
                 written = c.fragments_written;
  const auto fail = [&](const std::string& what) { errors.push_back(what); };
  const auto n = [](uint64_t v) { return std::to_string(v); };
  // Survivors of the clipper of one kind: in - invalid - clipped away.
  const auto survivors = [&](const std::string& kind, uint64_t in_k, uint64_t invalid_k,
                             uint64_t away_k) -> uint64_t {
    if (invalid_k + away_k > in_k) {
      fail(kind + "_invalid + " + kind + "_clipped_away = " + n(invalid_k + away_k) + " exceeds " +
           kind + "_in = " + n(in_k));
      return 0;
    }
    return in_k - invalid_k - away_k;
  };

  // Triangles. The survivors leave filled (one triangles_after_clip each or
  // more, then degenerate, culled or rasterized in setup) or in polygon mode
  // (degenerate, culled or unfilled in the clipper, not after_clip): the
  // difference below counts the latter.
  const uint64_t survived = survivors("triangles", in, invalid, away);
  const uint64_t ended = degenerate + culled + rasterized + unfilled;
  if (ended < after) {
    fail("triangles_degenerate + triangles_culled + triangles_rasterized + triangles_unfilled = " +
         n(ended) + " is below triangles_after_clip = " + n(after));
  } else {
    const uint64_t polygon_mode = ended - after;
    if (polygon_mode < unfilled || polygon_mode > survived) {
      fail("polygon-mode triangles (degenerate + culled + rasterized + unfilled - after_clip) = " +
           n(polygon_mode) + " is not between triangles_unfilled = " + n(unfilled) + " and the " +
           n(survived) + " triangles the clipper kept");
    } else if (after < survived - polygon_mode) {
      fail("triangles_after_clip = " + n(after) + " is below the " + n(survived - polygon_mode) +
           " filled triangles the clipper kept");
    }
  }
  if (clipped > survived) {
    fail("triangles_clipped = " + n(clipped) + " exceeds the " + n(survived) +
         " triangles the clipper kept");
  }
  if (offscreen > rasterized) {
    fail("triangles_offscreen = " + n(offscreen) +
         " exceeds triangles_rasterized = " + n(rasterized));
  }

  // Lines and points: the survivors are rasterized (or degenerate), and so
  // are polygon mode's lines and points, which exist only with unfilled
  // triangles.
  const uint64_t lines = survivors("lines", c.lines_in, c.lines_invalid, c.lines_clipped_away);
  const uint64_t lines_clipped = c.lines_clipped;
  const uint64_t lines_set_up = c.lines_rasterized + c.lines_degenerate;
  if (lines_clipped > lines) {
    fail("lines_clipped = " + n(lines_clipped) + " exceeds the " + n(lines) +
         " lines the clipper kept");
  }
  if (lines_set_up < lines || (unfilled == 0 && lines_set_up != lines)) {
    fail("lines_rasterized + lines_degenerate = " + n(lines_set_up) + ", but the clipper kept " +
         n(lines) + " lines and " + n(unfilled) + " unfilled triangles");
  }
  const uint64_t points = survivors("points", c.points_in, c.points_invalid, c.points_clipped_away);
  const uint64_t points_set_up = c.points_rasterized;
  if (points_set_up < points || (unfilled == 0 && points_set_up != points)) {
    fail("points_rasterized = " + n(points_set_up) + ", but the clipper kept " + n(points) +
         " points and " + n(unfilled) + " unfilled triangles");
  }

  if (passed > generated) {
    fail("fragments_passed_depth = " + n(passed) +
         " exceeds fragments_generated = " + n(generated));
  }
  if (written > passed) {
    fail("fragments_written = " + n(written) + " exceeds fragments_passed_depth = " + n(passed));
  }
  return errors;
}

}  // namespace gpusim
