#include "hw/fifo_statistics.h"

namespace gpusim {

FifoStats FifoStatistics::snapshot(uint64_t written, uint64_t read,
                                   const sc_core::sc_time& observed) const {
  const uint64_t now = std::max({static_cast<uint64_t>(observed.value()), m_occupancy.since,
                                 m_blocked_writers.since, m_blocked_readers.since});
  const uint64_t dt = now - m_occupancy.since;
  const uint64_t window = now - m_start;
  FifoStats s;
  s.written = written;
  s.read = read;
  s.max_occupancy = m_max_occupancy;
  s.mean_occupancy =
      window == 0 ? 0.0
                  : static_cast<double>(m_occupancy.area_at(now)) / static_cast<double>(window);
  s.full = sc_core::sc_time::from_value(m_full + (m_occupancy.level == m_depth ? dt : 0));
  s.empty = sc_core::sc_time::from_value(m_empty + (m_occupancy.level == 0 ? dt : 0));
  s.writer_blocked = sc_core::sc_time::from_value(m_blocked_writers.area_at(now));
  s.reader_blocked = sc_core::sc_time::from_value(m_blocked_readers.area_at(now));
  s.injected_stalls = m_injected_stalls;
  s.injected_stall = m_injected_stall;
  s.observed = sc_core::sc_time::from_value(observed.value() - m_start);
  return s;
}

}  // namespace gpusim
