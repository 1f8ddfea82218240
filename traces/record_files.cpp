#include "traces/record_files.h"

#include <cstring>

namespace gpusim {
namespace {

// Little endian whatever the host, so the files read the same everywhere.
void put(uint8_t* p, uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
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
  encode(r, m_file.reserve(TransactionRecord::kSize));
  ++m_records;
}

void RecordFile::write(const FragmentRecord& r) {
  encode(r, m_file.reserve(FragmentRecord::kSize));
  ++m_records;
}

}  // namespace gpusim
