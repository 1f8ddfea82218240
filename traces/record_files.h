// Writing the binary record files of a trace (docs/traces.md; the records:
// traces/trace_records.h): a 16-byte header (magic, version, record size),
// then fixed-size little-endian records, streamed through a buffer so memory
// stays bounded however long the run.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "traces/buffered_file.h"
#include "traces/trace_records.h"

namespace gpusim {

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
