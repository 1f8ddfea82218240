#include "traces/trace_follow.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

#include "hw/input_error.h"
#include "hw/stage_spec.h"

namespace gpusim {
namespace {

std::string format_float(float v) {
  if (std::isnan(v)) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6f", static_cast<double>(v));
  return buf;
}

// "line", "point", "triangle": what a record's primitives are at its stage;
// "primitive" when the trace does not say (written before the field).
std::string kind_word(uint8_t prim_kind) {
  switch (prim_kind) {
    case TransactionRecord::prim_point:
      return "point";
    case TransactionRecord::prim_line:
      return "line";
    case TransactionRecord::prim_triangle:
      return "triangle";
  }
  return "primitive";
}

// What a work item is at its stage (docs/traces.md, "Model"), by what the
// manifest says a record of the stage is.
std::string item_text(const TraceStage& s, const TransactionRecord& r) {
  const std::string word = kind_word(r.prim_kind);
  const std::string prims =
      r.prim_first == r.prim_last
          ? word + " " + std::to_string(r.prim_first)
          : word + "s " + std::to_string(r.prim_first) + ".." + std::to_string(r.prim_last);
  const std::string n = std::to_string(r.count);
  const std::string stamps = n + (r.count == 1 ? " stamp" : " stamps");
  if (s.item == "draw") return "draw " + std::to_string(r.draw) + ": " + prims;
  if (s.item == "batch") return "batch of " + n + " slots: " + prims;
  if (s.item == "tile job") return "tile job: " + stamps + " out";
  if (s.item == "stamp batch") return "stamp batch: " + stamps;
  return word;  // one primitive after clipping
}

// The stage of `unit` that makes the fragment records of `site`, or null.
const TraceStage* site_stage(const TraceManifest& m, unsigned unit, FragmentSite site) {
  for (const TraceStage& s : m.stages) {
    if (s.unit == static_cast<int>(unit) && s.fragments == to_string(site)) return &s;
  }
  return nullptr;
}

std::string outcome_text(const FragmentRecord& f) {
  if (f.stage == FragmentRecord::at_test) {
    switch (f.outcome) {
      case FragmentRecord::failed:
        return "failed";
      case FragmentRecord::passed:
        return "passed";
      case FragmentRecord::passed_test_off:
        return "passed (test off)";
    }
  } else {
    switch (f.outcome) {
      case FragmentRecord::written:
        return "written";
      case FragmentRecord::not_written:
        return "not written (mask)";
    }
  }
  return "outcome " + std::to_string(f.outcome);
}

std::string value_text(const FragmentRecord& f) {
  if (f.stage == FragmentRecord::at_test) {
    return std::isnan(f.value[0]) ? "depth not stored" : "depth " + format_float(f.value[0]);
  }
  char buf[96];
  std::snprintf(buf, sizeof buf, "rgba (%.4f, %.4f, %.4f, %.4f)", static_cast<double>(f.value[0]),
                static_cast<double>(f.value[1]), static_cast<double>(f.value[2]),
                static_cast<double>(f.value[3]));
  return buf;
}

// Why the last stage a primitive reached is the last, for an unfiltered
// trace: the stage's own reason for `word` (what the draw assembles:
// "line", "point", "triangle", or "primitive" in a trace without the field,
// read as a triangle), "" when it ended where it should.
std::string stop_reason(const TraceStage& stage, const std::string& word) {
  const auto it = stage.drops.find(word == "primitive" ? "triangle" : word);
  if (it != stage.drops.end()) return it->second;
  return "it left the pipeline after " + stage.kind;
}

}  // namespace

std::vector<TraceFollow::Step> TraceFollow::prim_steps(int64_t prim) const {
  std::vector<Step> steps;
  const TraceManifest& m = m_reader.manifest();
  m_reader.for_each_transaction([&](const TransactionRecord& r) {
    if (r.kind == TransactionRecord::work && r.carries(prim))
      steps.push_back({&m.stages[r.stage], r});
  });
  std::stable_sort(steps.begin(), steps.end(), [&m](const Step& a, const Step& b) {
    const int ra = m.pipeline_rank(a.stage->kind), rb = m.pipeline_rank(b.stage->kind);
    if (ra != rb) return ra < rb;
    if (a.record.cycle_in != b.record.cycle_in) return a.record.cycle_in < b.record.cycle_in;
    return a.stage->unit < b.stage->unit;
  });
  return steps;
}

std::vector<FragmentRecord> TraceFollow::pixel_fragments(int x, int y) const {
  std::vector<FragmentRecord> out;
  m_reader.for_each_fragment([&](const FragmentRecord& f) {
    if (f.x == x && f.y == y) out.push_back(f);
  });
  std::stable_sort(out.begin(), out.end(), [](const FragmentRecord& a, const FragmentRecord& b) {
    if (a.cycle != b.cycle) return a.cycle < b.cycle;
    return a.stage < b.stage;
  });
  return out;
}

std::string TraceFollow::prim_absence(int64_t prim) const {
  const TraceManifest& m = m_reader.manifest();
  const TraceFilters& f = m.filters;
  if (f.prims && (prim < f.prims->first || prim > f.prims->second)) {
    return m.prim_word(prim) + " " + std::to_string(prim) +
           " was filtered out of the trace: it was recorded with --trace-prims " +
           std::to_string(f.prims->first) + ":" + std::to_string(f.prims->second);
  }
  std::string why =
      m.prim_word(prim) + " " + std::to_string(prim) + " never appears in transactions.bin";
  if (f.window || f.stages) {
    why += ": it may have passed outside what was recorded (" + f.describe() + ")";
  }
  return why;
}

std::string TraceFollow::prim_text(int64_t prim) const {
  if (prim < 0)
    throw InputError("--prim " + std::to_string(prim) + ": expected a primitive id >= 0");
  const TraceManifest& m = m_reader.manifest();
  // An id beyond the scene's primitives is bad input (exit 2), not an answer.
  const uint64_t total = m.primitives();
  if (static_cast<uint64_t>(prim) >= total) {
    throw InputError("--prim " + std::to_string(prim) + ": primitive " + std::to_string(prim) +
                     " does not exist: the scene has " + std::to_string(total) + " primitive" +
                     (total == 1 ? "" : "s") +
                     (total ? " (ids 0.." + std::to_string(total - 1) + ")" : ""));
  }
  const std::vector<Step> steps = prim_steps(prim);
  if (steps.empty()) return prim_absence(prim) + "\n";

  std::set<std::string> stages;
  for (const Step& s : steps) stages.insert(s.stage->name);
  // "line 12 (draw 1, line_strip)", "triangle 5 (draw 0, triangles, polygon_mode line)":
  // what the draw assembles, from the manifest.
  const std::string word = m.prim_word(prim);
  std::string draw = "draw " + std::to_string(steps.front().record.draw);
  const int64_t di = m.draw_of(prim);
  if (di >= 0) {
    const TraceManifest::Draw& d = m.draws[static_cast<size_t>(di)];
    if (!d.primitive.empty()) draw += ", " + d.primitive;
    if (!d.polygon_mode.empty() && d.polygon_mode != "fill" && word == "triangle") {
      draw += ", polygon_mode " + d.polygon_mode;
    }
  }
  char buf[256];
  std::string out;
  std::snprintf(buf, sizeof buf, "%s %lld (%s) in %s: %zu item%s at %zu stage%s\n", word.c_str(),
                static_cast<long long>(prim), draw.c_str(), m_reader.dir().c_str(), steps.size(),
                steps.size() == 1 ? "" : "s", stages.size(), stages.size() == 1 ? "" : "s");
  out += buf;
  std::snprintf(buf, sizeof buf, "  %-20s %4s %9s %10s %10s %7s %6s  %s\n", "stage", "unit", "tile",
                "cycle_in", "cycle_out", "cycles", "count", "item");
  out += buf;
  for (const Step& s : steps) {
    const TransactionRecord& r = s.record;
    const std::string unit = s.stage->unit < 0 ? "-" : std::to_string(s.stage->unit);
    const std::string tile =
        r.tile_x < 0 ? "-" : "(" + std::to_string(r.tile_x) + "," + std::to_string(r.tile_y) + ")";
    std::snprintf(buf, sizeof buf, "  %-20s %4s %9s %10llu %10llu %7llu %6u  %s\n",
                  s.stage->name.c_str(), unit.c_str(), tile.c_str(),
                  static_cast<unsigned long long>(r.cycle_in),
                  static_cast<unsigned long long>(r.cycle_out),
                  static_cast<unsigned long long>(r.cycle_out - r.cycle_in), r.count,
                  item_text(*s.stage, r).c_str());
    out += buf;
  }
  const TraceFilters& f = m.filters;
  if (f.window || f.stages) {
    out += "  (only what was recorded: " + f.describe() + ")\n";
  } else {
    const std::string reason = stop_reason(*steps.back().stage, word);
    if (!reason.empty()) out += "  ends at " + steps.back().stage->kind + ": " + reason + "\n";
  }
  return out;
}

std::string TraceFollow::pixel_text(int x, int y, const FrameLookup& frame) const {
  const TraceManifest& m = m_reader.manifest();
  if (x < 0 || y < 0 || x >= m.width || y >= m.height) {
    throw InputError("--pixel " + std::to_string(x) + "," + std::to_string(y) + ": outside the " +
                     std::to_string(m.width) + "x" + std::to_string(m.height) + " framebuffer of " +
                     m_reader.path("manifest.json"));
  }
  const int tx = m.tile_size ? x / m.tile_size : 0, ty = m.tile_size ? y / m.tile_size : 0;
  const unsigned unit = m.units ? static_cast<unsigned>(tx + ty) % m.units : 0;  // tile_owner
  const std::vector<FragmentRecord> frags = pixel_fragments(x, y);
  char buf[256];
  std::string out;
  size_t depth = 0;
  for (const FragmentRecord& f : frags) depth += f.stage == FragmentRecord::at_test;
  std::snprintf(buf, sizeof buf,
                "pixel (%d,%d) in %s: tile (%d,%d) of unit %u; %zu fragment record%s (%zu at the "
                "depth test, %zu at the ROP)\n",
                x, y, m_reader.dir().c_str(), tx, ty, unit, frags.size(),
                frags.size() == 1 ? "" : "s", depth, frags.size() - depth);
  out += buf;
  if (!frags.empty()) {
    std::snprintf(buf, sizeof buf, "  %10s %-10s %9s %4s %10s %10s %-18s %s\n", "cycle", "stage",
                  "primitive", "unit", "depth", "old depth", "outcome", "value");
    out += buf;
  }
  // The stages of the pixel's unit at each fragment site, from the manifest.
  const TraceStage* at_test = site_stage(m, unit, FragmentSite::test);
  const TraceStage* at_write = site_stage(m, unit, FragmentSite::write);
  const std::string test_kind = at_test ? at_test->kind : "test";
  const std::string write_kind = at_write ? at_write->kind : "write";
  for (const FragmentRecord& f : frags) {
    std::snprintf(buf, sizeof buf, "  %10llu %-10s %9lld %4u %10s %10s %-18s %s\n",
                  static_cast<unsigned long long>(f.cycle),
                  (f.stage == FragmentRecord::at_test ? test_kind : write_kind).c_str(),
                  static_cast<long long>(f.prim), f.unit, format_float(f.depth).c_str(),
                  format_float(f.old_depth).c_str(), outcome_text(f).c_str(),
                  value_text(f).c_str());
    out += buf;
  }

  // Why the list may be incomplete or empty.
  const TraceFilters& filters = m.filters;
  const std::string u = std::to_string(unit);
  const bool depth_kept = at_test == nullptr || filters.keeps_stage(at_test->name);
  const bool rop_kept = at_write == nullptr || filters.keeps_stage(at_write->name);
  if (!depth_kept || !rop_kept) {
    out += "  note: the pixel's unit " + u + " had " +
           (depth_kept ? "its ROP"
            : rop_kept ? "its depth test"
                       : "its depth test and ROP") +
           " filtered out (" + filters.describe() + ")\n";
  }
  if (filters.prims) {
    out += "  note: only fragments of primitives " + std::to_string(filters.prims->first) + ".." +
           std::to_string(filters.prims->second) + " were recorded (" + filters.describe() + ")\n";
  }
  if (filters.window) {
    out += "  note: only fragments inside the window were recorded (" + filters.describe() + ")\n";
  }
  if (frags.empty() && !filters.any()) {
    out += "  no fragment touched it: it holds the clear values\n";
  }

  // The frame's final value, to compare with the last ROP write.
  if (frame) {
    if (const std::optional<PixelValue> v = frame(x, y)) {
      std::snprintf(buf, sizeof buf, "  frame.exr: rgba (%.4f, %.4f, %.4f, %.4f), depth %s\n",
                    static_cast<double>(v->rgba[0]), static_cast<double>(v->rgba[1]),
                    static_cast<double>(v->rgba[2]), static_cast<double>(v->rgba[3]),
                    format_float(v->depth).c_str());
      out += buf;
    }
  }
  return out;
}

}  // namespace gpusim
