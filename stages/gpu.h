// The GPU: every stage instantiated and joined by bounded FIFOs, N raster
// units each with its own rasterizer, depth test, interpolator and ROP, and
// one memory shared by every client.
//
//   commands -> CommandProcessor -> VertexFetch -> VertexShader -> Clipper
//            -> TriangleSetup -> TileDistributor -+-> unit 0: TileRasterizer -> DepthTest
//                                                 |            -> Interpolator -> Rop
//                                                 +-> unit 1 ...
//   VertexFetch, every DepthTest and Rop -> Memory (TLM-2.0)
//
// Robustness (docs/robustness.md): a watchdog thread stops a run in which no
// item moves for watchdog_cycles and reports every stage's state and every
// FIFO's occupancy; conservation_errors() checks, from the stages' counters,
// that every item that entered a stage left it or was counted as dropped.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <systemc>
#include <vector>

#include "hw/draw_state.h"
#include "hw/fifo.h"
#include "hw/gpu_config.h"
#include "hw/memory.h"
#include "hw/packets.h"
#include "hw/trace_probe.h"
#include "hw/vertex_packets.h"
#include "stages/clipper.h"
#include "stages/command_processor.h"
#include "stages/depth_test.h"
#include "stages/interpolator.h"
#include "stages/rop.h"
#include "stages/tile_distributor.h"
#include "stages/tile_rasterizer.h"
#include "stages/triangle_setup.h"
#include "stages/vertex_fetch.h"
#include "stages/vertex_shader.h"

namespace gpusim {

class Gpu : public sc_core::sc_module {
 public:
  // Test-only fault injection (docs/robustness.md, "Watchdog"), by FIFO name
  // ("commands", "clipper_to_setup", "rasterizer_to_depth_0", ...); empty: none.
  struct Faults {
    // The FIFO's reader is bound to an empty FIFO nobody writes: the FIFO
    // never delivers, and the pipeline deadlocks.
    std::string disconnected_fifo;
    // Every read and write of the FIFO first stalls up to 2^32 cycles: its
    // neighbours stay busy without moving an item, and the watchdog fires.
    std::string stalled_fifo;
  };

  // frame and config must outlive the GPU; memory_bytes sizes the memory.
  // An unknown FIFO name in `faults` throws std::invalid_argument.
  Gpu(sc_core::sc_module_name name, const GpuConfig& config, const FrameState& frame,
      uint64_t memory_bytes, const Faults& faults = Faults{});

  // The host writes commands here.
  Fifo<Command>& command_queue() { return m_commands; }
  Memory& memory() { return m_memory; }

  // Every unit has flushed its tiles after end_of_frame.
  bool frame_done() const;
  // Notified whenever a unit finishes its frame.
  const sc_core::sc_event_or_list& unit_done_events() const { return m_done_events; }
  // Testbench instrumentation: primitive id of the last colour write per pixel.
  void set_last_writer(std::vector<int64_t>* per_pixel);

  // Random stalls at every FIFO boundary (Fifo::inject_random_stalls), for
  // latency-insensitivity tests: results must not change.
  void inject_random_stalls(uint64_t seed, double probability, unsigned max_cycles);

  // --- Tracing (docs/traces.md) --------------------------------------------
  // The stages and FIFOs as the trace files number them, from the same views
  // the watchdog and stats use (test-fault stand-ins left out).
  TraceTables trace_tables() const;
  // Attaches a recorder before sc_start(): each FIFO gets probes.fifo_probe()
  // for its index in trace_tables(), every depth test and ROP the fragment
  // probe. `probes` must outlive the simulation.
  void attach_trace(TraceProbes& probes);

  // Assembled triangles the clipper has taken in so far (for progress lines).
  uint64_t triangles_assembled() const;

  // Everything stats.json reports about the run: per stage busy / stalled /
  // starved cycles, per FIFO occupancy, per unit work, memory traffic,
  // achieved against peak rates. `cycles` is the frame's length.
  nlohmann::json stats_json(uint64_t cycles) const;
  // Pipeline counters comparable with the golden model's statistics.
  nlohmann::json pipeline_counts() const;

  // --- Watchdog --------------------------------------------------------
  // A thread wakes every max(1, watchdog_cycles / 4) cycles and compares the
  // progress count (items written and read at every FIFO, memory requests)
  // with its last wake; memory transfers still in flight count as progress.
  // Without progress it looks at the stages (blocked-time integrals of their
  // FIFOs over the period):
  //  - some stage busy (not blocked on a FIFO) for watchdog_cycles without
  //    moving an item: it records a report (state_report) and calls
  //    sc_stop(): a stage stuck, or one item costing more than
  //    watchdog_cycles;
  //  - every stage blocked on a FIFO (readers on empty ones, writers on full
  //    ones): nothing can ever change, so it stops counting and waits for an
  //    item to move; the kernel runs out of events and sc_start() returns
  //    before the frame is done, which run_gpu reports as a deadlock.
  // It returns as soon as the frame is done, so it never lengthens a run, and
  // it only reads state, so it never changes one: no per-cycle work.
  // set_watchdog(false) before sc_start() turns it off.
  void set_watchdog(bool on) { m_watchdog_on = on; }
  bool watchdog_fired() const { return !m_watchdog_report.empty(); }
  // The report of a fired watchdog: a headline, then one line per stage and
  // per FIFO.
  const std::string& watchdog_report() const { return m_watchdog_report; }
  // Items moved so far: written and read at every FIFO, memory requests.
  uint64_t progress_count() const;
  // Notified whenever an item is written to or read from any FIFO.
  const sc_core::sc_event_or_list& activity_events() const { return m_activity_events; }

  // Every FIFO's blocked-time integrals at one instant; two samples tell
  // which stages were blocked in between.
  struct Sample {
    std::vector<sc_core::sc_time> reader_blocked, writer_blocked;
    sc_core::sc_time at;
  };
  Sample sample() const;
  // Per stage: blocked reading an empty input, blocked writing a full output,
  // or busy (neither, at some point between the samples; a reader waiting for
  // an item still in flight is busy too). Assumes no item moved in between.
  enum class StageState { busy, waiting_on_input, waiting_on_output };
  std::vector<StageState> stage_states(const Sample& before, const Sample& after) const;
  // A headline classifying the hang, then every stage's state and every
  // FIFO's occupancy, one per line.
  std::string state_report(const Sample& before, const Sample& after) const;
  // Occupancy lines only (after an exception, when time cannot advance).
  std::string fifo_report() const;

  // --- Conservation ----------------------------------------------------
  // Every way the counters say an item was lost, one line each; empty when
  // they balance. `cycles` is the frame's length, as for stats_json().
  std::vector<std::string> conservation_errors(uint64_t cycles) const;

 private:
  // A FIFO seen through its type-independent parts.
  struct FifoView {
    std::string name;
    std::function<FifoStats()> stats;
    std::function<size_t()> occupancy;  // items held, readable or not
    size_t depth = 0;
    std::function<void(TraceProbes&, size_t)> attach;  // sets the FIFO's probe
  };
  // A stage and the FIFOs it reads and writes (indices into m_fifo_views).
  struct StageView {
    std::string name;
    const StatGroup* stats = nullptr;
    std::vector<size_t> inputs, outputs;
  };
  template <typename T>
  size_t add_fifo_view(Fifo<T>& fifo, const std::string& name);
  // The FIFO a stage reads: `fifo`, or an empty stand-in when the fault
  // disconnects it.
  template <typename T>
  Fifo<T>& reader_side(Fifo<T>& fifo);
  void build_views();
  void apply_stall_fault();
  void watchdog();

  struct Unit {
    std::unique_ptr<Fifo<SetupPacket>> jobs;
    std::unique_ptr<TileRasterizer> rasterizer;
    std::unique_ptr<Fifo<StampBatch>> stamps;
    std::unique_ptr<DepthTest> depth;
    std::unique_ptr<Fifo<StampBatch>> visible;
    std::unique_ptr<Interpolator> interpolator;
    std::unique_ptr<Fifo<ShadedStampBatch>> shaded;
    std::unique_ptr<Rop> rop;
  };

  const GpuConfig& m_config;
  const FrameState& m_frame;
  Memory m_memory;
  Fifo<Command> m_commands;
  CommandProcessor m_command_processor;
  Fifo<Command> m_command_to_fetch;
  VertexFetch m_fetch;
  Fifo<VertexBatch> m_fetch_to_shader;
  VertexShader m_shader;
  Fifo<ShadedBatch> m_shader_to_clipper;
  Clipper m_clipper;
  Fifo<ClippedPrimitive> m_clipper_to_setup;
  TriangleSetup m_setup;
  Fifo<SetupPacket> m_setup_to_distributor;
  TileDistributor m_distributor;
  std::vector<Unit> m_units;
  sc_core::sc_event_or_list m_done_events;

  Faults m_faults;
  std::vector<std::shared_ptr<void>> m_stand_ins;  // disconnected readers' FIFOs
  std::map<std::string, size_t> m_stand_in_view;   // FIFO name -> view of its stand-in
  std::vector<FifoView> m_fifo_views;
  std::vector<StageView> m_stage_views;
  sc_core::sc_event_or_list m_activity_events;
  bool m_watchdog_on = true;
  std::string m_watchdog_report;
};

// The conservation rules (docs/robustness.md, "Conservation") over a
// Gpu::stats_json() dump of a one-frame run of `frame`: one line per
// violated rule, naming the stage or FIFO and both sides' figures. A counter
// missing from the dump is a violation too. A free function so tests can
// check it on doctored counters.
std::vector<std::string> conservation_errors(const nlohmann::json& stats, const FrameState& frame);

}  // namespace gpusim
