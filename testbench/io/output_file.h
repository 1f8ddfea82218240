// Atomic output: every file is written under a temporary name in its
// destination directory and renamed into place only when all of a command's
// outputs are complete, so an interrupted or failed run never leaves a
// half-written file or destroys the previous result. rename(2) within one
// directory replaces the target atomically.
#pragma once

#include <string>
#include <vector>

namespace gpusim {

// Create dir and its parents (nothing to do when it exists or is empty, which
// means the current directory). Throws InputError "<dir>: cannot create output
// directory: <reason>" when it cannot be created or exists as a non-directory.
void create_output_directory(const std::string& dir);

// An output directory that a session may end up writing nothing into (a
// replay that fails before its first frame): created as
// create_output_directory() does, and at destruction, unless keep() was
// called, the directories it created are removed again, deepest first and
// only while empty, so a failed session leaves no empty folder behind.
class OutputDirectory {
 public:
  explicit OutputDirectory(const std::string& dir);
  // Something was written into it: it stays.
  void keep() { m_made.clear(); }
  ~OutputDirectory();
  // One owner removes what it made.
  OutputDirectory(const OutputDirectory&) = delete;
  OutputDirectory& operator=(const OutputDirectory&) = delete;

 private:
  std::vector<std::string> m_made;  // deepest first
};

// The temporary name for final_path: "<dir>/.<name>.tmp.<pid>", in the same
// directory so that the final rename never crosses file systems.
std::string temporary_path_for(const std::string& final_path);

// A set of outputs committed together:
//
//   OutputFiles files;
//   write_frame_exr(fb, files.add(dir + "/frame.exr"));
//   write_frame_png(fb, files.add(dir + "/frame.png"));
//   write_text_file_atomically(files.add(dir + "/stats.json"), json);
//   files.commit();  // all three appear, or (on any exception above) none
//
// commit() first checks that every temporary exists and no destination is a
// directory, then renames; after those checks a rename inside one directory
// only fails on I/O errors, so "all or none" holds barring such failures.
// The destructor removes the temporaries of an uncommitted set.
class OutputFiles {
 public:
  OutputFiles() = default;
  ~OutputFiles();
  OutputFiles(const OutputFiles&) = delete;
  OutputFiles& operator=(const OutputFiles&) = delete;

  // Register final_path and return the temporary path to write instead.
  // Throws InputError when final_path's directory does not exist or the path
  // was already added to this set.
  std::string add(const std::string& final_path);

  // Rename every temporary into place; the set is empty afterwards and may be
  // reused. Throws InputError naming the file on failure (remaining
  // temporaries are removed).
  void commit();

  // Remove all temporaries without committing.
  void discard() noexcept;

 private:
  struct Entry {
    std::string final_path;
    std::string temp_path;
  };
  std::vector<Entry> entries_;
};

// Write content to path via a temporary and rename (for JSON and other text).
// Throws InputError "<path>: <problem>".
void write_text_file_atomically(const std::string& path, const std::string& content);

}  // namespace gpusim
