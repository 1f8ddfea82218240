#include "traces/buffered_file.h"

#include <cerrno>
#include <cstring>

#include "hw/input_error.h"

namespace gpusim {

BufferedFile::BufferedFile(const std::string& path) : m_path(path), m_buffer(1 << 20) {
  if (path.empty()) return;  // discards
  m_file = std::fopen(path.c_str(), "wb");
  if (!m_file) throw InputError(path + ": cannot write: " + std::strerror(errno));
}

BufferedFile::~BufferedFile() {
  if (m_file) std::fclose(m_file);
}

void BufferedFile::flush() {
  if (m_used == 0) return;
  write_through(m_buffer.data(), m_used);
  m_used = 0;
}

void BufferedFile::write_through(const char* data, size_t n) {
  if (m_path.empty()) return;
  if (!m_file || std::fwrite(data, 1, n, m_file) != n) {
    throw InputError(m_path + ": cannot write: " + std::strerror(errno));
  }
}

void BufferedFile::close() {
  if (!m_file) return;
  flush();
  const bool failed = std::fclose(m_file) != 0;
  m_file = nullptr;
  if (failed) throw InputError(m_path + ": cannot write: " + std::strerror(errno));
}

}  // namespace gpusim
