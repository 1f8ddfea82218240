// Trace hooks of a FIFO (hw/fifo.h): what a recorder (traces/) needs to
// reconstruct, cycle by cycle, every stage's state and every item's interval,
// without the stages knowing they are traced.
//
// The hooks cost one predictable branch per FIFO operation when no probe is
// set. A build configured with -DGPUSIM_TRACE_HOOKS=OFF compiles them out
// entirely (kTraceHooks is false and every call sits under `if constexpr`),
// so the benchmark (scripts/bench_trace) can measure what the branch costs.
#pragma once

#include <cstddef>
#include <cstdint>

#ifndef GPUSIM_TRACE_HOOKS
#define GPUSIM_TRACE_HOOKS 1
#endif

namespace gpusim {

inline constexpr bool kTraceHooks = GPUSIM_TRACE_HOOKS != 0;

// Times are sc_time values (units of the SystemC time resolution), so a
// probe converts them to cycles once, the way it needs. Calls arrive in the
// simulation's own order, which is deterministic: the same run gives the
// same sequence.
template <typename T>
class FifoProbe {
 public:
  virtual ~FifoProbe() = default;
  // The reader asked for an item (a blocking read() or a successful
  // nb_read()): the reader is done with its previous item.
  virtual void read_called(uint64_t now) = 0;
  // The reader holds `item`, just taken from the FIFO.
  virtual void taken(const T& item, uint64_t now) = 0;
  // A writer put `item` into the FIFO.
  virtual void written(const T& item, uint64_t now) = 0;
  // A reader (writer_side false) or writer began or ended waiting in a
  // blocking read() or write(): the time stats.json counts as starved or
  // stalled.
  virtual void blocked(bool writer_side, bool begin, uint64_t now) = 0;
  // Items held (readable or not) after a delta in which the FIFO changed.
  virtual void occupancy(size_t items, uint64_t now) = 0;
};

}  // namespace gpusim
