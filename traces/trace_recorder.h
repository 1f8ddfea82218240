// The trace recorder (docs/traces.md): attached to the GPU through its probes
// (hw/trace_probe.h), it follows every stage's state (busy, stalled,
// starved) and the item it works on from the FIFO events alone, and streams
// signals.vcd (with signals.gtkw, a GTKWave save file showing it), timeline.json,
// transactions.bin and fragments.bin; finish()
// writes manifest.json.
//
// Memory is bounded: per stage the open item, per FIFO its occupancy, and
// the records of the current cycle, which are sorted by stage and written
// when simulated time moves on (records go out in cycle_out order, ties in
// stage order, whatever order the kernel ran the processes in).
#pragma once

#include <cstdint>
#include <deque>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "hw/draw_state.h"
#include "hw/gpu_config.h"
#include "hw/memory.h"
#include "hw/trace_probe.h"
#include "traces/record_files.h"
#include "traces/timeline_writer.h"
#include "traces/trace_filter.h"
#include "traces/trace_items.h"
#include "traces/vcd_writer.h"

namespace gpusim {

class TraceRecorder : public TraceProbes, public FragmentProbe, public MemoryProbe {
 public:
  // Where each file goes (temporary names; the caller renames them). An
  // empty path: that format is not written (--trace-formats; vcd and gtkw go
  // together) and the recorder skips its work; manifest.json's "formats"
  // lists the ones written.
  struct Paths {
    std::string manifest, vcd, gtkw, timeline, transactions, fragments;
  };
  // `filter` must already have been checked against `tables`
  // (TraceFilter::stages_kept). config and frame must outlive the recorder.
  TraceRecorder(const NetlistTables& tables, const GpuConfig& config, const FrameState& frame,
                const TraceFilter& filter, const Paths& paths, const std::string& scene);
  ~TraceRecorder() override;

  FifoProbe<Command>* fifo_probe(size_t fifo, ProbeTag<Command>) override;
  FifoProbe<VertexBatch>* fifo_probe(size_t fifo, ProbeTag<VertexBatch>) override;
  FifoProbe<ShadedBatch>* fifo_probe(size_t fifo, ProbeTag<ShadedBatch>) override;
  FifoProbe<ClippedPrimitive>* fifo_probe(size_t fifo, ProbeTag<ClippedPrimitive>) override;
  FifoProbe<SetupPacket>* fifo_probe(size_t fifo, ProbeTag<SetupPacket>) override;
  FifoProbe<StampBatch>* fifo_probe(size_t fifo, ProbeTag<StampBatch>) override;
  FifoProbe<ShadedStampBatch>* fifo_probe(size_t fifo, ProbeTag<ShadedStampBatch>) override;
  FifoProbe<ControlToken>* fifo_probe(size_t fifo, ProbeTag<ControlToken>) override;
  FragmentProbe* fragment_probe() override { return m_fragments_traced ? this : nullptr; }
  // The memory channels' busy wires are VCD signals only.
  MemoryProbe* memory_probe() override { return m_write_vcd ? this : nullptr; }
  void transfer(unsigned channel, uint64_t start, uint64_t end) override;

  void depth_tested(unsigned unit, const DepthFragment& f) override;
  void rop_wrote(unsigned unit, const RopFragment& f) override;

  // The run ended at `end_time` (an sc_time value); `cycles` is the frame's
  // length. Closes items still open, completes every file and writes the
  // manifest.
  void finish(uint64_t cycles, uint64_t end_time);

  // From the probes, `now` an sc_time value.
  void read_called(size_t fifo, uint64_t now);
  void taken(size_t fifo, const ItemInfo& item, uint64_t now);
  void written(size_t fifo, const ItemInfo& item, uint64_t now);
  void blocked(size_t fifo, bool writer_side, bool begin, uint64_t now);
  void occupancy(size_t fifo, size_t items, uint64_t now);

 private:
  enum State : uint8_t { busy, stalled, starved };
  struct Stage {
    bool kept = false;
    bool counts_outputs = false;  // a tile rasterizer: count = stamps produced
    bool names_draws = false;     // items are named "draw d"
    int pid = 0, tid = 0;
    State state = starved;
    size_t signal = 0;  // the first of busy, stalled, starved in the VCD
    bool open = false;
    uint64_t cycle_in = 0;
    ItemInfo item;
    uint32_t out_stamps = 0;
    int16_t out_tile_x = -1, out_tile_y = -1;
    bool out_any = false, out_one_tile = true;
  };
  struct Fifo {
    bool kept = false;
    size_t signal = 0;
    int pid = 0, tid = 0;
    std::string counter_name;       // "fifo <name>"
    size_t value = 0, emitted = 0;  // occupancy now / as of the last cycle written
    bool dirty = false;
  };
  struct Finished {
    TransactionRecord record;
    ItemInfo item;
  };
  struct ProbeHolder;
  template <typename T>
  class Probe;
  template <typename T>
  FifoProbe<T>* make_probe(size_t fifo);

  void advance(uint64_t now) {
    const uint64_t cycle = now / m_cycle_value;
    if (cycle != m_now) {
      if (m_memory_next < cycle) memory_until(cycle);
      end_cycle(cycle);
    }
  }
  // Sets the channels' busy wires at each of their changes before cycle
  // `limit`, ending the cycles in between.
  void memory_until(uint64_t limit);
  // Writes what happened in m_now, then moves to `next`.
  void end_cycle(uint64_t next);
  void set_state(Stage& s, State state);
  void close_item(size_t stage);
  void write_item(const Finished& f);
  // Whether a fragment of `prim` at `stage` passes the filters; if so, sets
  // r.cycle and r.prim.
  bool fragment_kept(int stage, int64_t prim, FragmentRecord& r) const;
  // The VCD's scopes and signals, grouped by unit, in pipeline order.
  void declare_signals();
  // A GTKWave save file listing the signals as declared, grouped.
  void write_save_file(const std::string& path);
  void write_metadata();
  void write_manifest(uint64_t cycles);

  const NetlistTables m_tables;
  const GpuConfig& m_config;
  const FrameState& m_frame;
  const TraceFilter m_filter;
  const Paths m_paths;
  const std::string m_scene;
  const ItemDescriber m_describer;
  uint64_t m_cycle_value = 1;  // the clock period in sc_time units
  uint64_t m_cycle_ps = 1000;
  std::vector<bool> m_kept;
  std::vector<Stage> m_stages;
  std::vector<Fifo> m_fifos;
  std::vector<size_t> m_dirty_fifos;
  static constexpr int kMemoryGroup = -2;
  struct Shown {
    int unit;              // -1: the front end, kMemoryGroup: the memory channels
    size_t signal, count;  // consecutive VCD signals
  };
  std::vector<Shown> m_shown;  // in declaration order
  // Per memory channel: its busy wire and the bus transfers granted but not
  // yet written, merged into [start, end) cycle ranges in start order.
  struct Channel {
    size_t signal = 0;
    bool busy = false;
    std::deque<std::pair<uint64_t, uint64_t>> pending;
  };
  std::vector<Channel> m_channels;
  uint64_t m_memory_next = std::numeric_limits<uint64_t>::max();  // earliest change pending
  std::vector<int> m_depth_stage, m_rop_stage;                    // per unit: stage index
  bool m_fragments_traced = false;
  // The formats written (Paths not empty).
  bool m_write_vcd = true, m_write_timeline = true, m_write_transactions = true;
  bool m_counters_started = false;
  uint64_t m_now = 0;
  std::vector<Finished> m_finished;  // items finished in m_now
  std::vector<std::unique_ptr<ProbeHolder>> m_probes;
  std::string m_name, m_args;  // write_item's text, reused

  VcdWriter m_vcd;
  TimelineWriter m_timeline;
  RecordFile m_transactions;
  RecordFile m_fragment_file;
};

}  // namespace gpusim
