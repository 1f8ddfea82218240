#include "hw/fifo_stamped_sync.h"

namespace gpusim {

void StampLog::reset(size_t depth) {
  size_t n = 4;
  while (n < 2 * depth + 4) n *= 2;
  m_ring.assign(n, SuperdenseTime{});
  m_mask = n - 1;
  m_head = m_tail = 0;
}

void StampLog::grow() {
  std::vector<SuperdenseTime> bigger(2 * m_ring.size());
  for (uint64_t i = m_head; i != m_tail; ++i) bigger[i - m_head] = m_ring[i & m_mask];
  m_tail -= m_head;
  m_head = 0;
  m_ring.swap(bigger);
  m_mask = m_ring.size() - 1;
}

void FifoStampedSync::start(size_t depth, const SuperdenseTime* writer,
                            const SuperdenseTime* reader) {
  writer_clock = writer;
  reader_clock = reader;
  readable_from.assign(depth, SuperdenseTime{});
  free_from.assign(depth, SuperdenseTime{});
  write_log.reset(depth);
  read_log.reset(depth);
}

void FifoStampedSync::restart(size_t depth) {
  start(depth, writer_clock, reader_clock);
  writer_asleep = reader_asleep = false;
  stall_end = 0;
  stall_end_event.cancel();
}

void FifoStampedSync::settle(const SuperdenseTime& limit, FifoStatistics& stats, size_t& committed,
                             const char* fifo) {
  for (;;) {
    const SuperdenseTime* w = write_log.oldest_before(limit);
    const SuperdenseTime* r = read_log.oldest_before(limit);
    if (!w && !r) return;
    const SuperdenseTime at = !r || (w && *w < *r) ? *w : *r;
    if (at.t < stats.last_change()) report_behind_kernel(fifo, "a logged operation");
    const size_t written = write_log.take(at), read = read_log.take(at);
    committed = committed - read + written;
    stats.held(committed, at.t);
  }
}

}  // namespace gpusim
