// Atomic output: temporaries, commit, rollback, directory creation.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include "hw/input_error.h"
#include "testbench/io/image_files.h"
#include "testbench/io/output_file.h"

namespace gpusim {
namespace {

namespace fs = std::filesystem;

class OutputFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("gpusim_io_output_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  std::set<std::string> listing() const {
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_)) names.insert(e.path().filename().string());
    return names;
  }

  static std::string read(const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }
  static void write(const std::string& p, const std::string& content) {
    std::ofstream(p, std::ios::binary) << content;
  }

  fs::path dir_;
};

TEST_F(OutputFileTest, TemporaryIsHiddenInTheSameDirectoryWithPid) {
  EXPECT_EQ(temporary_path_for("/a/b/frame.exr"),
            "/a/b/.frame.exr.tmp." + std::to_string(::getpid()));
  EXPECT_EQ(temporary_path_for("frame.png"), ".frame.png.tmp." + std::to_string(::getpid()));
}

TEST_F(OutputFileTest, CommitMovesAllFilesIntoPlace) {
  write(path("stats.json"), "old stats");
  OutputFiles files;
  const std::string t1 = files.add(path("a.txt"));
  const std::string t2 = files.add(path("stats.json"));
  EXPECT_EQ(t1, path(".a.txt.tmp." + std::to_string(::getpid())));
  write(t1, "alpha");
  write(t2, "new stats");
  // Nothing visible under the final names before commit.
  EXPECT_FALSE(fs::exists(path("a.txt")));
  EXPECT_EQ(read(path("stats.json")), "old stats");
  files.commit();
  EXPECT_EQ(read(path("a.txt")), "alpha");
  EXPECT_EQ(read(path("stats.json")), "new stats");
  EXPECT_EQ(listing(), (std::set<std::string>{"a.txt", "stats.json"}));
}

TEST_F(OutputFileTest, UncommittedSetLeavesExistingFilesIntactAndRemovesTemporaries) {
  write(path("frame.exr"), "previous exr");
  write(path("frame.png"), "previous png");
  Framebuffer fb(3, 2, ColorFormat::rgba8, DepthFormat::unorm24);
  const float grey[4] = {0.5f, 0.5f, 0.5f, 1.0f};
  fb.clear(grey, 0.25f);
  try {
    OutputFiles files;
    write_frame_exr(fb, files.add(path("frame.exr")));
    write_frame_png(fb, files.add(path("frame.png")));
    // Both temporaries are complete here...
    EXPECT_EQ(listing().size(), 4u);
    // ...but a later step of the command fails before commit.
    throw std::runtime_error("stats failed");
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "stats failed");
  }
  EXPECT_EQ(read(path("frame.exr")), "previous exr");
  EXPECT_EQ(read(path("frame.png")), "previous png");
  EXPECT_EQ(listing(), (std::set<std::string>{"frame.exr", "frame.png"}));
}

TEST_F(OutputFileTest, CommitWithAMissingTemporaryRenamesNothing) {
  write(path("one.txt"), "old one");
  OutputFiles files;
  write(files.add(path("one.txt")), "new one");
  files.add(path("two.txt"));  // never written
  try {
    files.commit();
    FAIL() << "commit must fail";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path("two.txt") + ": output was not written");
  }
  EXPECT_EQ(read(path("one.txt")), "old one");
  EXPECT_EQ(listing(), (std::set<std::string>{"one.txt"}));
}

TEST_F(OutputFileTest, CommitOntoADirectoryFailsBeforeRenaming) {
  fs::create_directories(path("taken"));
  OutputFiles files;
  write(files.add(path("first.txt")), "x");
  write(files.add(path("taken")), "y");
  EXPECT_THROW(files.commit(), InputError);
  EXPECT_FALSE(fs::exists(path("first.txt")));
  EXPECT_TRUE(fs::is_directory(path("taken")));
  EXPECT_EQ(listing(), (std::set<std::string>{"taken"}));
}

TEST_F(OutputFileTest, DiscardRemovesTemporaries) {
  OutputFiles files;
  write(files.add(path("x.txt")), "x");
  EXPECT_EQ(listing().size(), 1u);
  files.discard();
  EXPECT_TRUE(listing().empty());
}

TEST_F(OutputFileTest, AddingTheSamePathTwiceIsAnError) {
  OutputFiles files;
  files.add(path("x.txt"));
  EXPECT_THROW(files.add(path("x.txt")), InputError);
}

TEST_F(OutputFileTest, AddInMissingDirectoryNamesTheDestination) {
  OutputFiles files;
  const std::string p = path("missing/x.exr");
  try {
    files.add(p);
    FAIL() << "add must fail";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), p + ": directory " + path("missing") + " does not exist");
  }
}

TEST_F(OutputFileTest, WriteTextFileAtomicallyReplacesContent) {
  write(path("stats.json"), "{\"old\": true}");
  write_text_file_atomically(path("stats.json"), "{\"frames\": 3}\n");
  EXPECT_EQ(read(path("stats.json")), "{\"frames\": 3}\n");
  write_text_file_atomically(path("empty.json"), "");
  EXPECT_TRUE(fs::exists(path("empty.json")));
  EXPECT_EQ(fs::file_size(path("empty.json")), 0u);
  EXPECT_EQ(listing(), (std::set<std::string>{"empty.json", "stats.json"}));
}

TEST_F(OutputFileTest, WriteTextFileIntoMissingDirectoryThrows) {
  const std::string p = path("nope/stats.json");
  try {
    write_text_file_atomically(p, "{}");
    FAIL() << "write must fail";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(p + ": ", 0), 0u) << e.what();
  }
  EXPECT_TRUE(listing().empty());
}

TEST_F(OutputFileTest, CreateOutputDirectoryCreatesParents) {
  const std::string d = path("a/b/c");
  create_output_directory(d);
  EXPECT_TRUE(fs::is_directory(d));
  create_output_directory(d);  // existing: fine
  EXPECT_TRUE(fs::is_directory(d));
}

TEST_F(OutputFileTest, CreateOutputDirectoryUnderAFileThrowsNamingIt) {
  write(path("file"), "x");
  for (const std::string& d : {path("file"), path("file/sub")}) {
    try {
      create_output_directory(d);
      FAIL() << "must fail for " << d;
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(d + ": cannot create output directory: ", 0), 0u) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos);
    }
  }
}

}  // namespace
}  // namespace gpusim
