#include "traces/record_files.h"

#include <cstring>

namespace gpusim {
RecordFile::RecordFile(const std::string& path, const char (&magic)[9], uint32_t version,
                       uint32_t record_size)
    : m_file(path) {
  uint8_t* h = m_file.reserve(16);
  std::memcpy(h, magic, 8);
  record_codec::Encoder e{h + 8};
  e(version);
  e(record_size);
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
