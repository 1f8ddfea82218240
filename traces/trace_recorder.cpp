#include "traces/trace_recorder.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "hw/input_error.h"
#include "hw/stage_spec.h"

namespace gpusim {
namespace {

uint64_t picoseconds(const GpuConfig& config) {
  return static_cast<uint64_t>(std::llround(config.cycle().to_seconds() * 1e12));
}

// Bits needed to hold 0..depth.
unsigned width_for(size_t depth) {
  unsigned w = 1;
  while ((depth >> w) != 0) ++w;
  return w;
}

const char* category(uint8_t kind) {
  return kind == 0 ? "work" : kind == 1 ? "clear" : "end_of_frame";
}

}  // namespace

struct TraceRecorder::ProbeHolder {
  virtual ~ProbeHolder() = default;
};

// Forwards one FIFO's events, the packet described, to the recorder.
template <typename T>
class TraceRecorder::Probe final : public FifoProbe<T>, public ProbeHolder {
 public:
  Probe(TraceRecorder& r, size_t fifo, bool outputs_counted)
      : m_r(r), m_fifo(fifo), m_outputs_counted(outputs_counted) {}
  void read_called(uint64_t now) override { m_r.read_called(m_fifo, now); }
  void taken(const T& item, uint64_t now) override {
    m_r.taken(m_fifo, m_r.m_describer.describe(item), now);
  }
  void written(const T& item, uint64_t now) override {
    // Only a tile rasterizer's outputs say something about its item.
    if (m_outputs_counted) m_r.written(m_fifo, m_r.m_describer.describe(item), now);
  }
  void blocked(bool writer_side, bool begin, uint64_t now) override {
    m_r.blocked(m_fifo, writer_side, begin, now);
  }
  void occupancy(size_t items, uint64_t now) override { m_r.occupancy(m_fifo, items, now); }

 private:
  TraceRecorder& m_r;
  size_t m_fifo;
  bool m_outputs_counted;
};

TraceRecorder::TraceRecorder(const NetlistTables& tables, const GpuConfig& config,
                             const FrameState& frame, const TraceFilter& filter, const Paths& paths,
                             const std::string& scene)
    : m_tables(tables),
      m_config(config),
      m_frame(frame),
      m_filter(filter),
      m_paths(paths),
      m_scene(scene),
      m_describer(frame, config.tile_size),
      m_cycle_value(std::max<uint64_t>(1, config.cycle().value())),
      m_cycle_ps(picoseconds(config)),
      m_kept(filter.stages_kept(tables)),
      m_write_vcd(!paths.vcd.empty()),
      m_write_timeline(!paths.timeline.empty()),
      m_write_transactions(!paths.transactions.empty()),
      m_vcd(paths.vcd, m_cycle_ps, filter.window_start(), filter.window_end()),
      m_timeline(paths.timeline, m_cycle_ps,
                 nlohmann::json({{"format", "gpusim-trace"},
                                 {"version", 1},
                                 {"scene", scene},
                                 {"clock_mhz", config.clock_mhz},
                                 {"cycle_ps", m_cycle_ps}})
                     .dump()),
      m_transactions(paths.transactions, "GPUSIMTX", 1, TransactionRecord::kSize),
      m_fragment_file(paths.fragments, "GPUSIMFR", 1, FragmentRecord::kSize) {
  m_stages.resize(tables.stages.size());
  m_depth_stage.assign(config.units, -1);
  m_rop_stage.assign(config.units, -1);
  for (size_t i = 0; i < tables.stages.size(); ++i) {
    const NetlistTables::Stage& t = tables.stages[i];
    Stage& s = m_stages[i];
    s.kept = m_kept[i];
    // What a record of the stage is (its spec's StageTrace): a tile job
    // counts the stamps it produced, a draw names its draw.
    s.counts_outputs = t.item == "tile job";
    s.names_draws = t.item == "draw";
    s.pid = t.unit < 0 ? 0 : 1 + t.unit;
    s.tid = static_cast<int>(i);
    if (t.unit >= 0 && t.fragments == to_string(FragmentSite::test))
      m_depth_stage[t.unit] = static_cast<int>(i);
    if (t.unit >= 0 && t.fragments == to_string(FragmentSite::write))
      m_rop_stage[t.unit] = static_cast<int>(i);
    if (s.kept && !paths.fragments.empty() && !t.fragments.empty()) {
      m_fragments_traced = true;
    }
  }
  m_fifos.resize(tables.fifos.size());
  for (size_t i = 0; i < tables.fifos.size(); ++i) {
    const NetlistTables::Fifo& t = tables.fifos[i];
    Fifo& f = m_fifos[i];
    // A FIFO's signal belongs to the stages it joins: kept with either.
    f.kept = (t.reader >= 0 && m_kept[t.reader]) || (t.writer >= 0 && m_kept[t.writer]);
    f.pid = t.unit < 0 ? 0 : 1 + t.unit;
    f.tid = t.reader;
    f.counter_name = "fifo " + t.name;
  }
  declare_signals();
  m_vcd.begin();
  if (m_write_vcd) write_save_file(paths.gtkw);
  if (m_write_timeline) write_metadata();
}

void TraceRecorder::declare_signals() {
  // Pipeline order: each FIFO just before its reader (after its writer when
  // it has none), each stage after its inputs; stage and FIFO indices
  // already run front end first, then unit by unit.
  struct Slot {
    size_t key;
    bool stage;
    size_t index;
  };
  std::vector<Slot> order;
  for (size_t i = 0; i < m_stages.size(); ++i) {
    if (m_stages[i].kept) order.push_back({2 * i + 1, true, i});
  }
  for (size_t i = 0; i < m_fifos.size(); ++i) {
    const NetlistTables::Fifo& t = m_tables.fifos[i];
    if (!m_fifos[i].kept) continue;
    const size_t key = t.reader >= 0 ? 2 * static_cast<size_t>(t.reader)
                                     : 2 * static_cast<size_t>(std::max(t.writer, 0)) + 1;
    order.push_back({key, false, i});
  }
  std::stable_sort(order.begin(), order.end(),
                   [](const Slot& a, const Slot& b) { return a.key < b.key; });
  const auto group = [](int unit) {
    return unit < 0 ? std::string("gpu.front_end") : "gpu.unit_" + std::to_string(unit);
  };
  for (const Slot& slot : order) {
    if (slot.stage) {
      const NetlistTables::Stage& t = m_tables.stages[slot.index];
      const std::string scope = group(t.unit) + "." + t.name;
      // Every stage is starved until it takes its first item.
      Stage& s = m_stages[slot.index];
      s.signal = m_vcd.add(scope, t.name + "_busy", 1, 0);
      m_vcd.add(scope, t.name + "_stalled", 1, 0);
      m_vcd.add(scope, t.name + "_starved", 1, 1);
      m_shown.push_back({t.unit, s.signal, 3});
    } else {
      const NetlistTables::Fifo& t = m_tables.fifos[slot.index];
      Fifo& f = m_fifos[slot.index];
      f.signal = m_vcd.add(group(t.unit), t.name, width_for(t.depth), 0);
      m_shown.push_back({t.unit, f.signal, 1});
    }
  }
  // The memory channels last, whatever the stage filter: one busy wire each.
  m_channels.resize(m_config.memory.channels);
  for (size_t c = 0; c < m_channels.size(); ++c) {
    m_channels[c].signal = m_vcd.add("gpu.memory", "channel_" + std::to_string(c) + "_busy", 1, 0);
  }
  if (!m_channels.empty())
    m_shown.push_back({kMemoryGroup, m_channels[0].signal, m_channels.size()});
}

void TraceRecorder::write_save_file(const std::string& path) {
  // GTKWave's save file format: "[key] value" settings, then the displayed
  // traces in order, each after an "@flags" line (hexadecimal TR_* bits:
  // 0x8 binary, 0x4 decimal, 0x20 right-justified, 0x200 a blank/comment
  // line, 0x800000 / 0x1000000 the start / end of a group named by the "-"
  // line that follows).
  std::string g =
      "[*] gpusim trace (docs/traces.md): stage states and FIFO occupancies in pipeline order\n"
      "[dumpfile] \"signals.vcd\"\n[savefile] \"signals.gtkw\"\n[timestart] 0\n"
      "[size] 1400 900\n[pos] -1 -1\n[treeopen] gpu.\n[sst_width] 260\n"
      "[signals_width] 320\n[sst_expanded] 1\n[sst_vpaned_height] 250\n";
  for (size_t k = 0; k < m_shown.size(); ++k) {
    const int unit = m_shown[k].unit;
    const std::string label = unit == kMemoryGroup ? "memory"
                              : unit < 0           ? "front end"
                                                   : "unit " + std::to_string(unit);
    if (k == 0 || m_shown[k - 1].unit != unit) g += "@800200\n-" + label + "\n";
    for (size_t i = 0; i < m_shown[k].count; ++i) {
      const size_t signal = m_shown[k].signal + i;
      g += (m_vcd.width(signal) == 1 ? "@28\n" : "@24\n") + m_vcd.path(signal) + "\n";
    }
    if (k + 1 == m_shown.size() || m_shown[k + 1].unit != unit) g += "@1000200\n-" + label + "\n";
  }
  BufferedFile file(path);
  file.write(g);
  file.close();
}

TraceRecorder::~TraceRecorder() = default;

void TraceRecorder::write_metadata() {
  m_timeline.process_name(0, "front end");
  for (unsigned u = 0; u < m_config.units; ++u) {
    m_timeline.process_name(static_cast<int>(1 + u), "unit " + std::to_string(u));
  }
  for (size_t i = 0; i < m_stages.size(); ++i) {
    if (!m_stages[i].kept) continue;
    const NetlistTables::Stage& t = m_tables.stages[i];
    m_timeline.thread_name(m_stages[i].pid, m_stages[i].tid, t.unit < 0 ? t.name : t.kind,
                           static_cast<int>(i));
  }
}

template <typename T>
FifoProbe<T>* TraceRecorder::make_probe(size_t fifo) {
  const NetlistTables::Fifo& t = m_tables.fifos.at(fifo);
  const bool reader = t.reader >= 0 && m_kept[t.reader];
  const bool writer = t.writer >= 0 && m_kept[t.writer];
  if (!reader && !writer) return nullptr;
  auto probe = std::make_unique<Probe<T>>(*this, fifo, writer && m_stages[t.writer].counts_outputs);
  FifoProbe<T>* p = probe.get();
  m_probes.push_back(std::move(probe));
  return p;
}

FifoProbe<Command>* TraceRecorder::fifo_probe(size_t fifo, ProbeTag<Command>) {
  return make_probe<Command>(fifo);
}
FifoProbe<VertexBatch>* TraceRecorder::fifo_probe(size_t fifo, ProbeTag<VertexBatch>) {
  return make_probe<VertexBatch>(fifo);
}
FifoProbe<ShadedBatch>* TraceRecorder::fifo_probe(size_t fifo, ProbeTag<ShadedBatch>) {
  return make_probe<ShadedBatch>(fifo);
}
FifoProbe<ClippedPrimitive>* TraceRecorder::fifo_probe(size_t fifo, ProbeTag<ClippedPrimitive>) {
  return make_probe<ClippedPrimitive>(fifo);
}
FifoProbe<SetupPacket>* TraceRecorder::fifo_probe(size_t fifo, ProbeTag<SetupPacket>) {
  return make_probe<SetupPacket>(fifo);
}
FifoProbe<StampBatch>* TraceRecorder::fifo_probe(size_t fifo, ProbeTag<StampBatch>) {
  return make_probe<StampBatch>(fifo);
}
FifoProbe<ShadedStampBatch>* TraceRecorder::fifo_probe(size_t fifo, ProbeTag<ShadedStampBatch>) {
  return make_probe<ShadedStampBatch>(fifo);
}
FifoProbe<ControlToken>* TraceRecorder::fifo_probe(size_t fifo, ProbeTag<ControlToken>) {
  return make_probe<ControlToken>(fifo);
}

// --- Events -------------------------------------------------------------------

void TraceRecorder::set_state(Stage& s, State state) {
  if (s.state == state) return;
  s.state = state;
  if (!m_write_vcd) return;
  m_vcd.set(s.signal + busy, state == busy);
  m_vcd.set(s.signal + stalled, state == stalled);
  m_vcd.set(s.signal + starved, state == starved);
}

void TraceRecorder::read_called(size_t fifo, uint64_t now) {
  advance(now);
  const int reader = m_tables.fifos[fifo].reader;
  if (reader >= 0 && m_stages[reader].kept) close_item(static_cast<size_t>(reader));
}

void TraceRecorder::taken(size_t fifo, const ItemInfo& item, uint64_t now) {
  advance(now);
  const int reader = m_tables.fifos[fifo].reader;
  if (reader < 0 || !m_stages[reader].kept) return;
  Stage& s = m_stages[reader];
  s.open = true;
  s.cycle_in = m_now;
  s.item = item;
  s.out_stamps = 0;
  s.out_any = false;
  s.out_one_tile = true;
}

void TraceRecorder::written(size_t fifo, const ItemInfo& item, uint64_t now) {
  advance(now);
  const int writer = m_tables.fifos[fifo].writer;
  if (writer < 0 || item.kind != 0) return;
  Stage& s = m_stages[writer];
  if (!s.kept || !s.open) return;
  s.out_stamps += item.count;
  if (!s.out_any) {
    s.out_tile_x = item.tile_x;
    s.out_tile_y = item.tile_y;
    s.out_any = true;
  } else if (item.tile_x != s.out_tile_x || item.tile_y != s.out_tile_y) {
    s.out_one_tile = false;
  }
}

void TraceRecorder::blocked(size_t fifo, bool writer_side, bool begin, uint64_t now) {
  advance(now);
  const int stage = writer_side ? m_tables.fifos[fifo].writer : m_tables.fifos[fifo].reader;
  if (stage < 0 || !m_stages[stage].kept) return;
  set_state(m_stages[stage], begin ? (writer_side ? stalled : starved) : busy);
}

void TraceRecorder::occupancy(size_t fifo, size_t items, uint64_t now) {
  advance(now);
  Fifo& f = m_fifos[fifo];
  if (!f.kept || f.value == items) return;
  f.value = items;
  if (m_write_vcd) m_vcd.set(f.signal, items);
  if (!f.dirty) {
    f.dirty = true;
    m_dirty_fifos.push_back(fifo);
  }
}

void TraceRecorder::close_item(size_t stage) {
  Stage& s = m_stages[stage];
  if (!s.open) return;
  s.open = false;
  Finished f;
  f.item = s.item;
  if (s.counts_outputs && s.item.kind == 0) {
    // A tile job: the stamps it produced, in one tile or several.
    f.item.count = s.out_stamps;
    if (s.out_any && s.out_one_tile) {
      f.item.tile_x = s.out_tile_x;
      f.item.tile_y = s.out_tile_y;
    }
  }
  if (!m_filter.item_in_window(s.cycle_in, m_now)) return;
  if (f.item.kind == 0 && !m_filter.prims_match(f.item.prim_first, f.item.prim_last)) return;
  TransactionRecord& r = f.record;
  r.cycle_in = s.cycle_in;
  r.cycle_out = m_now;
  r.prim_first = f.item.prim_first;
  r.prim_last = f.item.prim_last;
  r.draw = f.item.draw;
  r.stage = static_cast<uint16_t>(stage);
  r.kind = f.item.kind;
  r.prim_kind = f.item.prim_kind;
  r.tile_x = f.item.tile_x;
  r.tile_y = f.item.tile_y;
  r.count = f.item.count;
  m_finished.push_back(f);
}

void TraceRecorder::transfer(unsigned channel, uint64_t start, uint64_t end) {
  // Whole cycles, as every wire: a transfer shorter than a cycle that
  // starts and ends within one is not seen.
  const uint64_t first = start / m_cycle_value, last = end / m_cycle_value;
  if (last <= first) return;
  auto& pending = m_channels[channel].pending;
  if (!pending.empty() && first <= pending.back().second) {
    pending.back().second = std::max(pending.back().second, last);
    return;
  }
  pending.emplace_back(first, last);
  if (pending.size() == 1 && !m_channels[channel].busy)
    m_memory_next = std::min(m_memory_next, first);
}

void TraceRecorder::memory_until(uint64_t limit) {
  for (;;) {
    uint64_t next = std::numeric_limits<uint64_t>::max();
    for (const Channel& c : m_channels) {
      if (!c.pending.empty())
        next = std::min(next, c.busy ? c.pending.front().second : c.pending.front().first);
    }
    m_memory_next = next;
    if (next >= limit) return;
    // Grants start at or after the time they are made, so never before m_now.
    if (next > m_now) end_cycle(next);
    for (Channel& c : m_channels) {
      while (!c.pending.empty()) {
        if (!c.busy && c.pending.front().first <= next) {
          c.busy = true;
        } else if (c.busy && c.pending.front().second <= next) {
          c.busy = false;
          c.pending.pop_front();
        } else {
          break;
        }
      }
      m_vcd.set(c.signal, c.busy);
    }
  }
}

void TraceRecorder::end_cycle(uint64_t next) {
  if (m_write_vcd) m_vcd.end_cycle(m_now);
  // FIFO counters: like the VCD, the values at the window's start first.
  if (!m_dirty_fifos.empty()) {
    std::sort(m_dirty_fifos.begin(), m_dirty_fifos.end());
    if (m_write_timeline && m_filter.cycle_in_window(m_now)) {
      if (!m_counters_started) {
        m_counters_started = true;
        const uint64_t start = m_filter.window_start();
        for (size_t i = 0; i < m_fifos.size(); ++i) {
          const Fifo& f = m_fifos[i];
          if (!f.kept) continue;
          m_timeline.counter(f.pid, f.tid, f.counter_name, start,
                             m_now == start ? f.value : f.emitted);
        }
      }
      for (size_t i : m_dirty_fifos) {
        const Fifo& f = m_fifos[i];
        if (f.value != f.emitted && m_now != m_filter.window_start()) {
          m_timeline.counter(f.pid, f.tid, f.counter_name, m_now, f.value);
        }
      }
    }
    for (size_t i : m_dirty_fifos) {
      m_fifos[i].emitted = m_fifos[i].value;
      m_fifos[i].dirty = false;
    }
    m_dirty_fifos.clear();
  }
  // Items finished in this cycle, in stage order.
  std::stable_sort(m_finished.begin(), m_finished.end(), [](const Finished& a, const Finished& b) {
    return a.record.stage < b.record.stage;
  });
  for (const Finished& f : m_finished) write_item(f);
  m_finished.clear();
  m_now = next;
}

namespace {

void append(std::string& s, int64_t v) {
  char buf[24];
  s.append(buf, static_cast<size_t>(std::to_chars(buf, buf + sizeof buf, v).ptr - buf));
}

}  // namespace

void TraceRecorder::write_item(const Finished& f) {
  const TransactionRecord& r = f.record;
  if (m_write_transactions) m_transactions.write(r);
  if (!m_write_timeline) return;
  const Stage& s = m_stages[r.stage];
  const ItemInfo& i = f.item;
  // m_name and m_args keep their storage from item to item.
  std::string& name = m_name;
  name.clear();
  if (i.kind != 0) {
    name = category(i.kind);
  } else if (s.names_draws) {
    name += "draw ";
    append(name, i.draw);
  } else if (i.is_batch) {
    name += "batch draw ";
    append(name, i.draw);
    name += " slots ";
    append(name, i.first_slot);
    name += "..";
    append(name, static_cast<int64_t>(i.first_slot) + i.count - 1);
  } else {
    // "line 12": the primitive as this stage sees it.
    name += i.prim_kind == 1   ? "point "
            : i.prim_kind == 2 ? "line "
            : i.prim_kind == 3 ? "triangle "
                               : "prim ";
    append(name, i.prim_first);
  }
  if (i.tile_x >= 0) {
    name += " tile (";
    append(name, i.tile_x);
    name += ",";
    append(name, i.tile_y);
    name += ")";
  }
  std::string& args = m_args;
  args = "\"draw\": ";
  if (i.draw == ItemInfo::kNoDraw) {
    args += "null";
  } else {
    append(args, i.draw);
  }
  args += ", \"prim_first\": ";
  append(args, i.prim_first);
  args += ", \"prim_last\": ";
  append(args, i.prim_last);
  if (i.tile_x >= 0) {
    args += ", \"tile\": [";
    append(args, i.tile_x);
    args += ", ";
    append(args, i.tile_y);
    args += "]";
  }
  args += ", \"count\": ";
  append(args, i.count);
  m_timeline.complete(s.pid, s.tid, name, category(i.kind), r.cycle_in, r.cycle_out, args);
}

// --- Fragments ------------------------------------------------------------------

bool TraceRecorder::fragment_kept(int stage, int64_t prim, FragmentRecord& r) const {
  const Stage& s = m_stages[stage];
  if (!s.kept || !m_filter.cycle_in_window(s.cycle_in) || !m_filter.prims_match(prim, prim)) {
    return false;
  }
  // The cycle the stage took the fragment's batch: the fragment is visited
  // then, before the stage waits its busy time.
  r.cycle = s.cycle_in;
  r.prim = prim;
  return true;
}

void TraceRecorder::depth_tested(unsigned unit, const DepthFragment& f) {
  FragmentRecord r;
  if (!fragment_kept(m_depth_stage[unit], f.prim, r)) return;
  const float nan = std::nanf("");
  r.x = static_cast<uint16_t>(f.x);
  r.y = static_cast<uint16_t>(f.y);
  r.stage = 0;
  r.unit = static_cast<uint8_t>(unit);
  r.outcome = f.outcome;
  r.depth = f.depth;
  r.old_depth = f.old_depth;
  r.value = {f.stored, nan, nan, nan};
  m_fragment_file.write(r);
}

void TraceRecorder::rop_wrote(unsigned unit, const RopFragment& f) {
  FragmentRecord r;
  if (!fragment_kept(m_rop_stage[unit], f.prim, r)) return;
  r.x = static_cast<uint16_t>(f.x);
  r.y = static_cast<uint16_t>(f.y);
  r.stage = 1;
  r.unit = static_cast<uint8_t>(unit);
  r.outcome = f.outcome;
  r.depth = r.old_depth = std::nanf("");
  r.value = {f.value[0], f.value[1], f.value[2], f.value[3]};
  m_fragment_file.write(r);
}

// --- The end ----------------------------------------------------------------------

void TraceRecorder::finish(uint64_t cycles, uint64_t end_time) {
  advance(end_time);
  if (m_memory_next <= m_now) memory_until(m_now + 1);
  for (size_t i = 0; i < m_stages.size(); ++i) {
    if (m_stages[i].kept) close_item(i);
  }
  const uint64_t end = m_now;
  end_cycle(end);
  m_vcd.finish(end);
  m_timeline.finish();
  m_transactions.close();
  m_fragment_file.close();
  write_manifest(cycles);
}

void TraceRecorder::write_manifest(uint64_t cycles) {
  // Keys in the documented order, for people reading the file.
  using json = nlohmann::ordered_json;
  const FramebufferDesc& fb = m_frame.framebuffer;
  const int tile = static_cast<int>(m_config.tile_size);
  const json netlist = to_json(m_tables);
  json draws = json::array();
  json formats = json::array();
  if (m_write_vcd) formats.push_back("vcd");
  if (m_write_timeline) formats.push_back("timeline");
  if (m_write_transactions) formats.push_back("transactions");
  if (!m_paths.fragments.empty()) formats.push_back("fragments");
  for (const DrawState& d : m_frame.draws) {
    draws.push_back({{"first_primitive_id", d.first_primitive_id},
                     {"primitives", primitive_count(d.primitive, d.buffers.slot_count)},
                     {"primitive", std::string(to_string(d.primitive))},
                     {"polygon_mode", std::string(to_string(d.state.polygon_mode))}});
  }
  const json manifest = {
      {"format", "gpusim-trace"},
      {"version", 2},
      {"scene", m_scene},
      {"formats", formats},
      {"config", json::parse(to_json(m_config).dump())},
      {"clock_mhz", m_config.clock_mhz},
      {"cycle_ps", m_cycle_ps},
      {"cycles", cycles},
      {"framebuffer",
       {{"width", fb.width},
        {"height", fb.height},
        {"tile_size", tile},
        {"tiles_x", (fb.width + tile - 1) / tile},
        {"tiles_y", (fb.height + tile - 1) / tile}}},
      {"units", m_config.units},
      {"filters", json::parse(m_filter.to_json(m_tables, m_kept).dump())},
      {"stages", netlist["stages"]},
      {"fifos", netlist["fifos"]},
      {"draws", draws},
      {"records",
       {{"transactions", m_transactions.records()},
        {"fragments", m_fragment_file.records()},
        {"timeline_events", m_write_timeline ? m_timeline.events() : 0},
        {"vcd_changes", m_write_vcd ? m_vcd.changes() : 0}}},
  };
  std::ofstream out(m_paths.manifest, std::ios::binary);
  out << manifest.dump(2) << "\n";
  out.close();
  if (!out) throw InputError(m_paths.manifest + ": cannot write");
}

}  // namespace gpusim
