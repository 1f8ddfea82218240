// What a trace recorder (traces/) attaches to the GPU: a probe per FIFO
// (hw/fifo_probe.h), a fragment probe called by every depth test and ROP, and
// the tables naming stages and FIFOs that the trace files index
// (docs/traces.md). Interfaces only, so stages/ knows nothing of the files.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "hw/fifo_probe.h"
#include "hw/netlist_tables.h"
#include "hw/packets.h"
#include "hw/vertex_packets.h"

namespace gpusim {

class MemoryProbe;  // hw/memory.h

// One fragment at a depth test. Values are decoded from the buffer format.
struct DepthFragment {
  int x = 0, y = 0;  // GL window coordinates
  int64_t prim = 0;
  uint8_t outcome = 0;     // DepthOutcome
  float depth = 0.0f;      // after polygon offset, as compared; NaN when not computed
  float old_depth = 0.0f;  // the stored value compared with; NaN when not read
  float stored = 0.0f;     // the value written to the buffer; NaN when none
};
enum DepthOutcome : uint8_t {
  depth_failed = 0,
  depth_passed = 1,
  depth_untested = 2,  // passed without a test: the stored value cannot change the outcome
};

// One fragment at a ROP; `value` is the stored colour, decoded (NaN when the
// colour mask stored nothing).
struct RopFragment {
  int x = 0, y = 0;
  int64_t prim = 0;
  uint8_t outcome = 0;  // RopOutcome
  float value[4] = {0.0f, 0.0f, 0.0f, 0.0f};
};
enum RopOutcome : uint8_t {
  rop_written = 1,
  rop_masked = 3,  // colour mask all false: nothing written
};

// Called per fragment while a stage works on a stamp batch, in the stage's
// own pixel order. Only called when set, so a stage without a probe pays one
// branch per batch or per fragment.
class FragmentProbe {
 public:
  virtual ~FragmentProbe() = default;
  virtual void depth_tested(unsigned unit, const DepthFragment& f) = 0;
  virtual void rop_wrote(unsigned unit, const RopFragment& f) = 0;
};

// Calls f(x, y) for every covered pixel of `stamps`, in stamp order, then
// bit order: the order in which the depth test and ROP visit them.
template <typename F>
void for_each_covered_pixel(const std::vector<Stamp>& stamps, unsigned stamp_w, int stamp_shift,
                            F&& f) {
  for (const Stamp& s : stamps) {
    for (uint64_t bits = s.mask; bits != 0; bits &= bits - 1) {
      const int idx = __builtin_ctzll(bits);
      f(s.x + (idx & static_cast<int>(stamp_w - 1)), s.y + (idx >> stamp_shift));
    }
  }
}

// Overloads chosen by the FIFO's packet type.
template <typename T>
struct ProbeTag {};

// A recorder as the GPU sees it (Gpu::attach_trace): one probe per FIFO,
// by index into NetlistTables::fifos (nullptr: that FIFO is not traced), and
// one fragment probe (nullptr: none).
class TraceProbes {
 public:
  virtual ~TraceProbes() = default;
  virtual FifoProbe<Command>* fifo_probe(size_t fifo, ProbeTag<Command>) = 0;
  virtual FifoProbe<VertexBatch>* fifo_probe(size_t fifo, ProbeTag<VertexBatch>) = 0;
  virtual FifoProbe<ShadedBatch>* fifo_probe(size_t fifo, ProbeTag<ShadedBatch>) = 0;
  virtual FifoProbe<ClippedPrimitive>* fifo_probe(size_t fifo, ProbeTag<ClippedPrimitive>) = 0;
  virtual FifoProbe<SetupPacket>* fifo_probe(size_t fifo, ProbeTag<SetupPacket>) = 0;
  virtual FifoProbe<StampBatch>* fifo_probe(size_t fifo, ProbeTag<StampBatch>) = 0;
  virtual FifoProbe<ShadedStampBatch>* fifo_probe(size_t fifo, ProbeTag<ShadedStampBatch>) = 0;
  virtual FifoProbe<ControlToken>* fifo_probe(size_t fifo, ProbeTag<ControlToken>) = 0;
  virtual FragmentProbe* fragment_probe() = 0;
  // The memory's bus transfers (nullptr: not traced).
  virtual MemoryProbe* memory_probe() { return nullptr; }
};

}  // namespace gpusim
