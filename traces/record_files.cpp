#include "traces/record_files.h"

#include <cstring>

namespace gpusim {
namespace {

// Little endian whatever the host, so the files read the same everywhere.
void put(uint8_t* p, uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}
void put_f32(uint8_t* p, float f) {
  uint32_t bits;
  std::memcpy(&bits, &f, 4);
  put(p, bits, 4);
}

}  // namespace

RecordFile::RecordFile(const std::string& path, const char (&magic)[9], uint32_t version,
                       uint32_t record_size)
    : m_file(path) {
  uint8_t* h = m_file.reserve(16);
  std::memcpy(h, magic, 8);
  put(h + 8, version, 4);
  put(h + 12, record_size, 4);
}

void RecordFile::write(const TransactionRecord& r) {
  uint8_t* p = m_file.reserve(TransactionRecord::kSize);
  put(p, r.cycle_in, 8);
  put(p + 8, r.cycle_out, 8);
  put(p + 16, static_cast<uint64_t>(r.prim_first), 8);
  put(p + 24, static_cast<uint64_t>(r.prim_last), 8);
  put(p + 32, r.draw, 4);
  put(p + 36, r.stage, 2);
  p[38] = r.kind;
  p[39] = r.prim_kind;
  put(p + 40, static_cast<uint16_t>(r.tile_x), 2);
  put(p + 42, static_cast<uint16_t>(r.tile_y), 2);
  put(p + 44, r.count, 4);
  ++m_records;
}

void RecordFile::write(const FragmentRecord& r) {
  uint8_t* p = m_file.reserve(FragmentRecord::kSize);
  put(p, r.cycle, 8);
  put(p + 8, static_cast<uint64_t>(r.prim), 8);
  put(p + 16, r.x, 2);
  put(p + 18, r.y, 2);
  p[20] = r.stage;
  p[21] = r.unit;
  p[22] = r.outcome;
  p[23] = 0;
  put_f32(p + 24, r.depth);
  put_f32(p + 28, r.old_depth);
  for (int k = 0; k < 4; ++k) put_f32(p + 32 + 4 * k, r.value[k]);
  ++m_records;
}

}  // namespace gpusim
