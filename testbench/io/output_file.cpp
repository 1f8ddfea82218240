#include "testbench/io/output_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "hw/input_error.h"

namespace gpusim {

namespace fs = std::filesystem;

void create_output_directory(const std::string& dir) {
  if (dir.empty()) return;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir + ": cannot create output directory: " + ec.message());
  // create_directories reports success for some existing non-directories
  // (e.g. a symlink to a file), so check what is there now.
  if (!fs::is_directory(dir, ec)) {
    throw InputError(dir + ": cannot create output directory: exists and is not a directory");
  }
}

OutputDirectory::OutputDirectory(const std::string& dir) {
  std::error_code ec;
  for (fs::path p = dir; !p.empty() && !fs::exists(p, ec); p = p.parent_path()) {
    m_made.push_back(p.string());
    if (p == p.parent_path()) break;
  }
  create_output_directory(dir);
}

OutputDirectory::~OutputDirectory() {
  std::error_code ec;
  for (const std::string& d : m_made) {
    if (!fs::remove(d, ec)) break;  // not empty (or gone): leave it and its parents
  }
}

std::string temporary_path_for(const std::string& final_path) {
  const fs::path p(final_path);
  const std::string name = "." + p.filename().string() + ".tmp." + std::to_string(::getpid());
  return (p.parent_path() / name).string();
}

OutputFiles::~OutputFiles() {
  discard();
}

std::string OutputFiles::add(const std::string& final_path) {
  const fs::path p(final_path);
  if (p.filename().empty()) throw InputError(final_path + ": not a file name");
  // Checked here so the error names the real destination, not the temporary
  // that the writer would fail to open.
  const fs::path dir = p.parent_path();
  std::error_code ec;
  if (!dir.empty() && !fs::is_directory(dir, ec)) {
    throw InputError(final_path + ": directory " + dir.string() + " does not exist");
  }
  for (const Entry& e : entries_) {
    if (e.final_path == final_path) throw InputError(final_path + ": output written twice");
  }
  entries_.push_back({final_path, temporary_path_for(final_path)});
  return entries_.back().temp_path;
}

void OutputFiles::commit() {
  // Check everything that can be checked before the first rename, so that a
  // foreseeable failure leaves all destinations untouched.
  for (const Entry& e : entries_) {
    std::error_code ec;
    if (!fs::is_regular_file(e.temp_path, ec)) {
      const std::string problem = e.final_path + ": output was not written";
      discard();
      throw InputError(problem);
    }
    if (fs::is_directory(e.final_path, ec)) {
      const std::string problem = e.final_path + ": cannot replace a directory";
      discard();
      throw InputError(problem);
    }
  }
  for (size_t i = 0; i < entries_.size(); ++i) {
    std::error_code ec;
    fs::rename(entries_[i].temp_path, entries_[i].final_path, ec);
    if (ec) {
      const std::string problem =
          entries_[i].final_path + ": cannot move into place: " + ec.message();
      entries_.erase(entries_.begin(), entries_.begin() + static_cast<long>(i));
      discard();
      throw InputError(problem);
    }
  }
  entries_.clear();
}

void OutputFiles::discard() noexcept {
  for (const Entry& e : entries_) {
    std::error_code ec;
    fs::remove(e.temp_path, ec);  // best effort: nothing useful to do on failure
  }
  entries_.clear();
}

void write_text_file_atomically(const std::string& path, const std::string& content) {
  OutputFiles files;
  const std::string temp = files.add(path);
  // stdio rather than ofstream: fclose reports errors (e.g. a full disk) that
  // would otherwise only surface as a silently truncated file.
  std::FILE* f = std::fopen(temp.c_str(), "wb");
  if (f == nullptr) throw InputError(path + ": cannot write: " + std::strerror(errno));
  const size_t written = std::fwrite(content.data(), 1, content.size(), f);
  const int write_errno = errno;
  const bool closed = std::fclose(f) == 0;
  if (written != content.size()) {
    throw InputError(path + ": cannot write: " + std::strerror(write_errno));
  }
  if (!closed) throw InputError(path + ": cannot write: " + std::strerror(errno));
  files.commit();
}

}  // namespace gpusim
