#include "testbench/sim/conservation.h"

#include <functional>
#include <map>

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

// What a stage kind's rules see: the ledger, the stage's name, the frame's
// totals and the netlist around the stage.
struct Context {
  Ledger& l;
  const std::string& name;
  const NetlistTables& netlist;
  const NetlistTables::Stage& stage;
  uint64_t draws = 0;      // in the frame
  uint64_t slots = 0;      // vertex slots of the frame's draws
  uint64_t triangles = 0;  // assembled from them, by kind
  uint64_t lines = 0;
  uint64_t points = 0;
  uint64_t control = 0;  // control tokens every stage forwards (clears + frames)
  uint64_t units = 0;
  // The frame's clears (the frame clear and the draw list's), and of them
  // those of the colour and of the depth buffer (spec section 15).
  uint64_t clears = 0;
  uint64_t color_clears = 0;
  uint64_t depth_clears = 0;

  uint64_t get(const std::string& counter) const { return l.stage(name, counter); }
  // The nearest stage of `kind` before this one along the first inputs:
  // the producer whose counters this stage's must match, whatever stages
  // were put between them (stages/topology.h, Interposers). "host" when
  // there is none.
  std::string upstream(const std::string& kind) const {
    const NetlistTables::Stage* s = &stage;
    while (!s->inputs.empty()) {
      const int w = netlist.fifos[s->inputs[0]].writer;
      if (w < 0) break;
      s = &netlist.stages[w];
      if (s->kind == kind) return s->name;
    }
    return "host";
  }
};

using Rule = std::function<void(Context&)>;

// Each stage kind's own rules.
const std::map<std::string, Rule>& rules() {
  static const std::map<std::string, Rule> table = {
      {"command_processor",
       [](Context& c) {
         // Commands in = commands out.
         c.l.equal(c.name, "draws", c.get("draws"), "draws in the frame", c.draws);
         c.l.equal(c.name, "frames", c.get("frames"), "frames run", 1);
         c.l.equal(c.name, "clears", c.get("clears"), "clears in the frame", c.clears);
         c.l.equal(c.name, "tokens_in", c.get("tokens_in"), "draws + clears + frames",
                   c.get("draws") + c.get("clears") + c.get("frames"));
         c.l.equal(c.name, "tokens_out", c.get("tokens_out"), "tokens_in", c.get("tokens_in"));
       }},
      {"vertex_fetch",
       [](Context& c) {
         // Draws become batches of slots; every slot is invalid, a cache hit
         // or fetched.
         c.l.equal(c.name, "draws", c.get("draws"), "draws in the frame", c.draws);
         c.l.equal(c.name, "tokens_in", c.get("tokens_in"), "draws + control tokens",
                   c.draws + c.control);
         c.l.equal(c.name, "tokens_out", c.get("tokens_out"), "batches + control tokens",
                   c.get("batches") + c.control);
         c.l.equal(c.name, "slots", c.get("slots"), "slots of the frame's draws", c.slots);
         c.l.equal(c.name, "slots", c.get("slots"), "invalid_slots + cache_hits + vertices_fetched",
                   c.get("invalid_slots") + c.get("cache_hits") + c.get("vertices_fetched"));
       }},
      {"vertex_shader",
       [](Context& c) {
         // Every fetched vertex is shaded.
         const std::string vf = c.upstream("vertex_fetch");
         c.l.equal(c.name, "tokens_out", c.get("tokens_out"), "tokens_in", c.get("tokens_in"));
         c.l.equal(c.name, "vertices_shaded", c.get("vertices_shaded"), vf + ".vertices_fetched",
                   c.l.stage(vf, "vertices_fetched"));
       }},
      {"clipper",
       [](Context& c) {
         // Per kind, primitives in = invalid + clipped away + survivors.
         // A filled triangle leaves as one triangle or more; a polygon-mode
         // one (line or point) is degenerate, culled or unfilled here, and
         // an unfilled one leaves as lines or points; an assembled line or
         // point leaves as itself.
         const auto survivors = [&c](const std::string& kind, uint64_t assembled) {
           const uint64_t in = c.get(kind + "_in");
           const uint64_t dropped = c.get(kind + "_invalid") + c.get(kind + "_clipped_away");
           c.l.equal(c.name, kind + "_in", in, kind + " assembled from the frame's draws",
                     assembled);
           c.l.at_most(c.name, kind + "_invalid + " + kind + "_clipped_away", dropped, kind + "_in",
                       in);
           return in >= dropped ? in - dropped : 0;
         };
         const uint64_t triangles = survivors("triangles", c.triangles);
         const uint64_t lines = survivors("lines", c.lines);
         const uint64_t points = survivors("points", c.points);
         const uint64_t after = c.get("triangles_after_clip");
         const uint64_t unfilled = c.get("triangles_unfilled");
         const uint64_t polygon_mode =
             c.get("triangles_degenerate") + c.get("triangles_culled") + unfilled;
         c.l.at_most(c.name, "polygon-mode triangles (degenerate + culled + unfilled)",
                     polygon_mode, "triangle survivors", triangles);
         const uint64_t filled = triangles >= polygon_mode ? triangles - polygon_mode : 0;
         c.l.at_most(c.name, "filled survivors", filled, "triangles_after_clip", after);
         c.l.at_most(c.name, "triangles_clipped", c.get("triangles_clipped"), "triangle survivors",
                     triangles);
         c.l.at_most(c.name, "lines_clipped", c.get("lines_clipped"), "line survivors", lines);
         const uint64_t lines_out = c.get("lines_out"), points_out = c.get("points_out");
         c.l.equal(c.name, "lines_out", lines_out, "line survivors + unfilled_lines",
                   lines + c.get("unfilled_lines"));
         c.l.equal(c.name, "points_out", points_out, "point survivors + unfilled_points",
                   points + c.get("unfilled_points"));
         if (unfilled == 0) {
           c.l.equal(c.name, "unfilled_lines + unfilled_points",
                     c.get("unfilled_lines") + c.get("unfilled_points"),
                     "lines and points of triangles_unfilled", 0);
         }
         c.l.equal(c.name, "cache_reads", c.get("cache_reads"), "vertex_fetch.cache_hits",
                   c.l.stage("vertex_fetch", "cache_hits"));
         c.l.equal(c.name, "tokens_in", c.get("tokens_in"), "vertex_fetch batches + control tokens",
                   c.l.stage("vertex_fetch", "batches") + c.control);
         c.l.equal(c.name, "tokens_out", c.get("tokens_out"),
                   "triangles_after_clip + lines_out + points_out + control tokens",
                   after + lines_out + points_out + c.control);
       }},
      {"triangle_setup",
       [](Context& c) {
         // Primitives in = the clipper's outputs. Triangles in = degenerate
         // + culled + rasterized (setup's own counters: polygon mode's are
         // the clipper's); lines in = degenerate + rasterized; points in =
         // rasterized. The rasterized ones leave unless their box holds no
         // pixel. Line and point counters are read when the clipper wrote
         // lines or points.
         const std::string cl = c.upstream("clipper");
         const uint64_t after = c.l.stage(cl, "triangles_after_clip");
         const uint64_t lines = c.l.stage(cl, "lines_out");
         const uint64_t points = c.l.stage(cl, "points_out");
         const uint64_t rasterized = c.get("triangles_rasterized");
         const uint64_t offscreen = c.get("triangles_offscreen");
         c.l.equal(c.name, "tokens_in", c.get("tokens_in"),
                   cl + ".triangles_after_clip + lines_out + points_out + control tokens",
                   after + lines + points + c.control);
         c.l.equal(c.name, cl + ".triangles_after_clip", after,
                   "triangles_degenerate + triangles_culled + triangles_rasterized",
                   c.get("triangles_degenerate") + c.get("triangles_culled") + rasterized);
         c.l.at_most(c.name, "triangles_offscreen", offscreen, "triangles_rasterized", rasterized);
         uint64_t sent = rasterized >= offscreen ? rasterized - offscreen : 0;
         if (lines > 0) {
           const uint64_t lr = c.get("lines_rasterized"), lo = c.get("lines_offscreen");
           c.l.equal(c.name, cl + ".lines_out", lines, "lines_degenerate + lines_rasterized",
                     c.get("lines_degenerate") + lr);
           c.l.at_most(c.name, "lines_offscreen", lo, "lines_rasterized", lr);
           sent += lr >= lo ? lr - lo : 0;
         }
         if (points > 0) {
           const uint64_t pr = c.get("points_rasterized"), po = c.get("points_offscreen");
           c.l.equal(c.name, cl + ".points_out", points, "points_rasterized", pr);
           c.l.at_most(c.name, "points_offscreen", po, "points_rasterized", pr);
           sent += pr >= po ? pr - po : 0;
         }
         c.l.equal(c.name, "tokens_out", c.get("tokens_out"),
                   "primitives rasterized - offscreen + control tokens", sent + c.control);
       }},
      {"tile_distributor",
       [](Context& c) {
         // Each triangle goes to one unit or more; control tokens to every
         // unit, so each output carries its unit's triangles and them all.
         const uint64_t in = c.get("tokens_in");
         const uint64_t work_in = in >= c.control ? in - c.control : 0;
         const uint64_t sent = c.get("triangles_sent");
         c.l.equal(c.name, "tokens_out", c.get("tokens_out"),
                   "triangles_sent + control tokens x units", sent + c.control * c.units);
         c.l.at_most(c.name, "triangles read", work_in, "triangles_sent", sent);
         c.l.at_most(c.name, "triangles_sent", sent, "triangles read x units", work_in * c.units);
         uint64_t sum = 0;
         for (int f : c.stage.outputs) {
           const NetlistTables::Fifo& out = c.netlist.fifos[f];
           const std::string u = std::to_string(out.unit);
           const uint64_t sent_u = c.get("triangles_sent_unit" + u);
           sum += sent_u;
           c.l.equal(c.name, out.name + ".written", c.l.fifo(out.name, "written"),
                     "triangles_sent_unit" + u + " + control tokens", sent_u + c.control);
           // Every primitive sent to a unit (triangles_sent counts every
           // kind) is received by its rasterizer, which counts them by kind.
           const std::string tr = c.netlist.stages[out.reader].name;
           c.l.equal(tr, "triangles + lines + points",
                     c.l.stage(tr, "triangles") + c.l.stage(tr, "lines") + c.l.stage(tr, "points"),
                     c.name + ".triangles_sent_unit" + u, sent_u);
         }
         c.l.equal(c.name, "sum of triangles_sent_unit*", sum, "triangles_sent", sent);
       }},
      {"tile_rasterizer",
       [](Context& c) {
         // The line walker's stamps (line_stamps) are emitted as it builds them.
         c.l.at_most(c.name, "stamps_emitted", c.get("stamps_emitted"),
                     "stamps_evaluated + stamps_accepted + line_stamps",
                     c.get("stamps_evaluated") + c.get("stamps_accepted") + c.get("line_stamps"));
         c.l.at_most(c.name, "control tokens", c.control, "tokens_out", c.get("tokens_out"));
       }},
      {"depth_test",
       [](Context& c) {
         // Stamps and pixels in are the rasterizer's; the ones that fail are
         // dropped, so at most as many pass.
         const std::string tr = c.upstream("tile_rasterizer");
         c.l.equal(c.name, "stamps", c.get("stamps"), tr + ".stamps_emitted",
                   c.l.stage(tr, "stamps_emitted"));
         c.l.equal(c.name, "fragments_in", c.get("fragments_in"), tr + ".fragments",
                   c.l.stage(tr, "fragments"));
         c.l.at_most(c.name, "fragments_passed", c.get("fragments_passed"), "fragments_in",
                     c.get("fragments_in"));
         c.l.at_most(c.name, "stamps_passed", c.get("stamps_passed"), "stamps", c.get("stamps"));
         // Every unit executes every depth clear on its own tiles.
         c.l.equal(c.name, "depth_clears", c.get("depth_clears"), "depth clears in the frame",
                   c.depth_clears);
         c.l.at_most(c.name, "tokens_out", c.get("tokens_out"), "tokens_in", c.get("tokens_in"));
         c.l.at_most(c.name, "control tokens", c.control, "tokens_out", c.get("tokens_out"));
       }},
      {"interpolator",
       [](Context& c) {
         // Shades exactly the pixels that passed.
         const std::string dt = c.upstream("depth_test");
         c.l.equal(c.name, "tokens_out", c.get("tokens_out"), "tokens_in", c.get("tokens_in"));
         c.l.equal(c.name, "stamps", c.get("stamps"), dt + ".stamps_passed",
                   c.l.stage(dt, "stamps_passed"));
         c.l.equal(c.name, "fragments", c.get("fragments"), dt + ".fragments_passed",
                   c.l.stage(dt, "fragments_passed"));
       }},
      {"rop",
       [](Context& c) {
         // Retires every token, or with a resolve after it passes the control
         // tokens on; writes at most the pixels it received.
         const std::string ip = c.upstream("interpolator");
         if (c.stage.outputs.empty()) {
           c.l.equal(c.name, "tokens_out", c.get("tokens_out"), "tokens_in", c.get("tokens_in"));
         } else {
           c.l.equal(c.name, "tokens_out", c.get("tokens_out"), "control tokens", c.control);
         }
         c.l.equal(c.name, "stamps", c.get("stamps"), ip + ".stamps", c.l.stage(ip, "stamps"));
         c.l.equal(c.name, "fragments_in", c.get("fragments_in"), ip + ".fragments",
                   c.l.stage(ip, "fragments"));
         c.l.at_most(c.name, "fragments_written", c.get("fragments_written"), "fragments_in",
                     c.get("fragments_in"));
         c.l.equal(c.name, "frames", c.get("frames"), "frames run", 1);
         c.l.equal(c.name, "color_clears", c.get("color_clears"), "colour clears in the frame",
                   c.color_clears);
         c.l.at_most(c.name, "samples_written", c.get("samples_written"), "fragments_written x 16",
                     16 * c.get("fragments_written"));
         c.l.at_most(c.name, "fragments_written", c.get("fragments_written"), "samples_written",
                     c.get("samples_written"));
       }},
      {"resolve",
       [](Context& c) {
         // One token per unit per control token; forwards nothing.
         c.l.equal(c.name, "tokens_in", c.get("tokens_in"), "control tokens x units",
                   c.control * c.units);
         c.l.equal(c.name, "frames", c.get("frames"), "frames run", 1);
       }},
  };
  return table;
}

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

  // Each kind's own rules.
  uint64_t units = 0;
  for (const NetlistTables::Stage& s : netlist.stages)
    units = std::max<uint64_t>(units, s.unit + 1);
  uint64_t slots = 0, assembled[3] = {0, 0, 0};  // by PrimitiveClass
  for (const DrawState& d : frame.draws) {
    slots += d.buffers.slot_count;
    assembled[static_cast<int>(primitive_class(d.primitive))] +=
        primitive_count(d.primitive, d.buffers.slot_count);
  }
  const uint64_t control =
      l.stage("command_processor", "clears") + l.stage("command_processor", "frames");
  uint64_t color_clears = 0, depth_clears = 0;
  for (size_t n = 0; n <= frame.clears.size(); ++n) {
    color_clears += frame.clear(n).color;
    depth_clears += frame.clear(n).depth;
  }
  for (const NetlistTables::Stage& s : netlist.stages) {
    const auto rule = rules().find(s.kind);
    if (rule == rules().end()) continue;
    Context c{l, s.name, netlist, s};
    c.draws = frame.draws.size();
    c.slots = slots;
    c.triangles = assembled[static_cast<int>(PrimitiveClass::triangle)];
    c.lines = assembled[static_cast<int>(PrimitiveClass::line)];
    c.points = assembled[static_cast<int>(PrimitiveClass::point)];
    c.control = control;
    c.units = units;
    c.clears = frame.clears.size() + 1;
    c.color_clears = color_clears;
    c.depth_clears = depth_clears;
    rule->second(c);
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
