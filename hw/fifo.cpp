#include "hw/fifo.h"

namespace gpusim {

FifoChannel::FifoChannel(const char* name, size_t depth)
    : sc_core::sc_prim_channel(name),
      m_statistics(depth),
      m_stats(std::make_unique<StatGroup>(basename())) {
  if (depth == 0) throw std::invalid_argument(std::string("Fifo ") + name + ": depth 0");
  StatGroup& g = *m_stats;
  const auto cycles = [this](sc_core::sc_time FifoStats::*time) {
    return [this, time] { return stats().*time / m_cycle; };
  };
  const auto count = [this](auto FifoStats::*field) {
    return [this, field] { return static_cast<uint64_t>(stats().*field); };
  };
  g.gauge("depth", "items", "slots", [depth] { return depth; });
  g.gauge("written", "items", "items written", count(&FifoStats::written));
  g.gauge("read", "items", "items read", count(&FifoStats::read));
  g.gauge("max_occupancy", "items", "most items held at once", count(&FifoStats::max_occupancy));
  g.formula("mean_occupancy", "items", "items held, averaged over the frame",
            [this] { return stats().mean_occupancy; });
  g.formula("full_cycles", "cycles", "cycles holding depth items", cycles(&FifoStats::full));
  g.formula("empty_cycles", "cycles", "cycles holding no item", cycles(&FifoStats::empty));
  g.formula("writer_blocked_cycles", "cycles", "cycles its writer waited for a free slot (stall)",
            cycles(&FifoStats::writer_blocked));
  g.formula("reader_blocked_cycles", "cycles",
            "cycles its reader waited for a readable item (starve)",
            cycles(&FifoStats::reader_blocked));
  g.gauge("injected_stalls", "events", "reads and writes delayed by random stall injection",
          count(&FifoStats::injected_stalls));
  g.formula("injected_stall_cycles", "cycles", "delay added by random stall injection",
            cycles(&FifoStats::injected_stall));
  g.formula("observed_cycles", "cycles", "the window every figure above covers",
            cycles(&FifoStats::observed));
}

}  // namespace gpusim
