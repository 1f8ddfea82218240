// The testbench's hang detector and the reports it (and run_gpu's deadlock
// check) print, all over the GPU's netlist (stages/topology.h): nothing here
// names a stage or a FIFO.
//
// The watchdog is a thread that wakes every max(1, watchdog_cycles / 4)
// cycles and compares the progress count (items written and read at every
// FIFO, memory requests) with its last wake; memory transfers still in
// flight count as progress. Without progress it looks at the stages
// (blocked-time integrals of their FIFOs over the period):
//  - some stage busy (not blocked on a FIFO) for watchdog_cycles without
//    moving an item: it records a report and calls sc_stop(): a stage stuck,
//    or one item costing more than watchdog_cycles;
//  - every stage blocked on a FIFO (readers on empty ones, writers on full
//    ones): nothing can ever change, so it stops counting and waits for an
//    item to move; the kernel runs out of events and sc_start() returns
//    before the frame is done, which run_gpu reports as a deadlock.
// It returns as soon as the frame is done, so it never lengthens a run, and
// it only reads state, so it never changes one: no per-cycle work, and the
// GPU's cycle counts are the same with it or without it (tested).
#pragma once

#include <cstdint>
#include <string>
#include <systemc>
#include <vector>

#include "stages/gpu.h"

namespace gpusim {

// Items moved so far: written and read at every FIFO, memory requests.
uint64_t progress_count(const Gpu& gpu);
// Memory transfers still in flight: the bus reserved beyond now, or the last
// transfer's latency not over. A tile cache's write-back of a whole frame is
// issued at once and takes the bus for long after, with no item moving.
bool transfers_in_flight(const Gpu& gpu, sc_core::sc_time memory_latency);
// Notified whenever an item is written to or read from any FIFO, while
// someone waits on them through wait_for_activity.
sc_core::sc_event_or_list activity_events(const Topology& topology);
// Waits on `events` (activity_events, perhaps with more) with every FIFO
// watched: a FIFO notifies its events only while watched (hw/fifo.h).
void wait_for_activity(const Topology& topology, const sc_core::sc_event_or_list& events);

// Every FIFO's blocked-time integrals at one instant; two samples tell
// which stages were blocked in between.
struct NetlistSample {
  std::vector<sc_core::sc_time> reader_blocked, writer_blocked;
  sc_core::sc_time at;
};
NetlistSample sample(const Topology& topology);

// Per stage: blocked reading an empty input, blocked writing a full output,
// or busy (neither, at some point between the samples; a reader waiting for
// an item still in flight is busy too). Assumes no item moved in between.
enum class StageState { busy, waiting_on_input, waiting_on_output };
std::vector<StageState> stage_states(const Topology& topology, const NetlistSample& before,
                                     const NetlistSample& after);
// A headline classifying the hang, then every stage's state and every
// FIFO's occupancy, one per line.
std::string state_report(const Topology& topology, const NetlistSample& before,
                         const NetlistSample& after);
// Occupancy lines only (after an exception, when time cannot advance).
std::string fifo_report(const Topology& topology);

class Watchdog : public sc_core::sc_module {
 public:
  // `gpu` must outlive the watchdog; elaborate it after the GPU.
  Watchdog(sc_core::sc_module_name name, const Gpu& gpu, const GpuConfig& config);

  bool fired() const { return !m_report.empty(); }
  // A headline, then one line per stage and per FIFO.
  const std::string& report() const { return m_report; }

 private:
  void run();
  // One frame, from its first instant (cycles in the report count from it).
  void watch_frame();

  const Gpu& m_gpu;
  const GpuConfig& m_config;
  std::string m_report;
};

}  // namespace gpusim
