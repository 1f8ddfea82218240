// The binary record files of a trace (docs/traces.md): transactions.bin, one
// record per item per stage, and fragments.bin, one record per fragment at a
// depth test or ROP. A 16-byte header (magic, version, record size), then
// fixed-size little-endian records, streamed through a buffer so memory stays
// bounded however long the run.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "traces/buffered_file.h"

namespace gpusim {

struct TransactionRecord {
  static constexpr size_t kSize = 48;
  uint64_t cycle_in = 0, cycle_out = 0;
  int64_t prim_first = -1, prim_last = -1;
  uint32_t draw = 0xFFFFFFFFu;
  uint16_t stage = 0;
  uint8_t kind = 0;       // 0 work, 1 clear, 2 end of frame
  uint8_t prim_kind = 0;  // 0 none, 1 point, 2 line, 3 triangle (traces/trace_items.h)
  int16_t tile_x = -1, tile_y = -1;
  uint32_t count = 1;
};

struct FragmentRecord {
  static constexpr size_t kSize = 48;
  uint64_t cycle = 0;
  int64_t prim = 0;
  uint16_t x = 0, y = 0;
  uint8_t stage = 0;  // 0 depth test, 1 ROP
  uint8_t unit = 0;
  uint8_t outcome = 0;
  float depth = 0.0f, old_depth = 0.0f;
  std::array<float, 4> value{};
};

// A buffered binary file of fixed-size records behind a header. Throws
// InputError "<path>: <problem>" when it cannot be opened or written.
class RecordFile {
 public:
  RecordFile(const std::string& path, const char (&magic)[9], uint32_t version,
             uint32_t record_size);
  void write(const TransactionRecord& r);
  void write(const FragmentRecord& r);
  // Flushes and closes; records() stays readable.
  void close() { m_file.close(); }
  uint64_t records() const { return m_records; }

 private:
  BufferedFile m_file;
  uint64_t m_records = 0;
};

}  // namespace gpusim
