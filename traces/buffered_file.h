// An output file written through a large buffer: the trace writers stream
// millions of small records, so each write is a copy into memory and the
// file sees one fwrite per megabyte. Memory stays bounded however long the
// run. Errors throw InputError "<path>: cannot write: <reason>". An empty
// path opens no file and discards what is written (a trace format not
// chosen with --trace-formats).
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace gpusim {

class BufferedFile {
 public:
  explicit BufferedFile(const std::string& path);
  ~BufferedFile();
  BufferedFile(const BufferedFile&) = delete;
  BufferedFile& operator=(const BufferedFile&) = delete;

  void write(const char* data, size_t n) {
    if (m_used + n > m_buffer.size()) flush();
    if (n > m_buffer.size()) return write_through(data, n);
    std::copy(data, data + n, m_buffer.data() + m_used);
    m_used += n;
  }
  void write(const std::string& s) { write(s.data(), s.size()); }
  // `n` bytes of the buffer to fill in place (n at most the buffer's size).
  uint8_t* reserve(size_t n) {
    if (m_used + n > m_buffer.size()) flush();
    uint8_t* p = reinterpret_cast<uint8_t*>(m_buffer.data()) + m_used;
    m_used += n;
    return p;
  }
  // Flushes and closes; further writes are errors.
  void close();

 private:
  void flush();
  void write_through(const char* data, size_t n);

  std::string m_path;
  std::FILE* m_file = nullptr;
  std::vector<char> m_buffer;
  size_t m_used = 0;
};

}  // namespace gpusim
