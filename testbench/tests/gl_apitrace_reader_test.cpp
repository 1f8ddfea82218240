// The apitrace trace reader against apitrace itself: real programs' traces
// (recorded by the gl_record_traces fixture: scripts/replay-check
// --record-only) read call by call and compared with `apitrace dump`'s text of
// the same file, every call's number, function, arguments and return value,
// numbers checked against the printed digits; files written here byte by byte
// from apitrace's docs/FORMAT.markdown, compared with what `apitrace dump`
// makes of them; truncated and corrupt files rejected with one line.
#include <gtest/gtest.h>
#include <snappy.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "hw/input_error.h"
#include "testbench/gl/apitrace_reader.h"

namespace gpusim::gl {
namespace {

namespace fs = std::filesystem;

const fs::path kTraces = fs::path(GPUSIM_BINARY_DIR) / "gl_traces";

// stdout of a shell command; fails the test on a non-zero exit.
std::string run(const std::string& command) {
  FILE* pipe = popen((command + " 2>/dev/null").c_str(), "r");
  if (!pipe) {
    ADD_FAILURE() << "cannot run: " << command;
    return "";
  }
  std::string out;
  std::array<char, 65536> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) out.append(buf.data(), n);
  const int status = pclose(pipe);
  if (status != 0)
    ADD_FAILURE() << command << " exited with " << WEXITSTATUS(status)
                  << " (scripts/setup installs apitrace)";
  return out;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// A call line of `apitrace dump`: its number first; "//" lines are properties.
bool is_call_line(const std::string& line) {
  return !line.empty() && line[0] >= '0' && line[0] <= '9';
}

std::vector<TraceCall> read_all(const std::string& path) {
  ApitraceReader reader(path);
  std::vector<TraceCall> calls;
  TraceCall call;
  while (reader.next(call)) calls.push_back(call);
  EXPECT_EQ(reader.bytes_read(), reader.file_size()) << path;
  return calls;
}

std::string text_of(const TraceCall& call) {
  std::ostringstream s;
  s << call;
  return s.str();
}

// ---------------------------------------------------------------------------
// Real programs

class RecordedTrace : public testing::TestWithParam<const char*> {
 protected:
  std::string path() const {
    return (kTraces / GetParam() / (std::string(GetParam()) + ".trace")).string();
  }
  void SetUp() override {
    ASSERT_TRUE(fs::exists(path())) << path()
                                    << " was not recorded: the gl_record_traces fixture "
                                       "(scripts/replay-check --record-only) failed";
  }
};

TEST_P(RecordedTrace, EveryCallAsApitraceDumpPrintsIt) {
  const std::vector<TraceCall> calls = read_all(path());
  std::vector<std::string> dump;
  for (const auto& line :
       lines_of(run("apitrace dump -v --color=never --multiline=false '" + path() + "'")))
    if (is_call_line(line)) dump.push_back(line);
  ASSERT_EQ(calls.size(), dump.size());
  EXPECT_GE(calls.size(), 300u) << "a recording of a few frames makes hundreds of calls";
  int failures = 0;
  for (size_t i = 0; i < calls.size() && failures < 10; ++i) {
    const std::string& line = dump[i];
    // Number and name straight from dump's text, apart from our printer.
    const size_t space = line.find(' '), paren = line.find('(');
    ASSERT_NE(paren, std::string::npos) << line;
    const bool same = std::to_string(calls[i].number) == line.substr(0, space) &&
                      calls[i].function == line.substr(space + 1, paren - space - 1) &&
                      text_of(calls[i]) == line;
    if (!same) {
      ++failures;
      ADD_FAILURE() << "call " << i << "\n ours: " << text_of(calls[i]) << "\n dump: " << line;
    }
  }
}

// Every argument dump prints as a plain number, compared with the value read:
// integers exactly, floats to the 7 (float) or 16 (double) significant digits
// dump prints.
TEST_P(RecordedTrace, NumbersEqualDumpsDigits) {
  const std::vector<TraceCall> calls = read_all(path());
  const std::string text = run("apitrace dump -v --color=never --multiline=false '" + path() + "'");
  const std::regex arg(R"(([A-Za-z_]\w*) = (-?(?:\d+\.?\d*(?:e[-+]\d+)?|nan|inf))(?=[,)]))");
  size_t index = 0, compared = 0;
  for (const auto& line : lines_of(text)) {
    if (!is_call_line(line)) continue;
    ASSERT_LT(index, calls.size());
    const TraceCall& call = calls[index++];
    // Only top-level arguments: the part before any '{' keeps members out.
    const std::string top = line.substr(0, line.find('{'));
    for (auto it = std::sregex_iterator(top.begin(), top.end(), arg); it != std::sregex_iterator();
         ++it) {
      const std::string name = (*it)[1], digits = (*it)[2];
      size_t k = 0;
      while (k < call.arg_names.size() && call.arg_names[k] != name) ++k;
      ASSERT_LT(k, call.args.size()) << line;
      const TraceValue& v = call.args[k];
      using K = TraceValue::Kind;
      if (v.kind == K::float32 || v.kind == K::float64) {
        const double printed = std::strtod(digits.c_str(), nullptr);
        const double rel = v.kind == K::float32 ? 5e-7 : 5e-16;
        if (std::isnan(printed)) {
          EXPECT_TRUE(std::isnan(v.real)) << line;
        } else {
          EXPECT_LE(std::fabs(v.real - printed), rel * std::fabs(printed) + 1e-45) << line;
        }
      } else if (v.kind == K::sint || v.kind == K::uint || v.kind == K::enumeration) {
        EXPECT_EQ(digits, v.kind == K::uint ? std::to_string(v.uint) : std::to_string(v.sint))
            << line;
      } else {
        ADD_FAILURE() << name << " printed as a number but read as kind "
                      << static_cast<int>(v.kind) << ": " << line;
      }
      ++compared;
    }
  }
  EXPECT_EQ(index, calls.size());
  EXPECT_GE(compared, 300u);
}

// dump (multi-line) leaves an empty line after each call apitrace counts as
// the end of a frame.
TEST_P(RecordedTrace, FrameEndsAsApitraceCountsThem) {
  const std::vector<TraceCall> calls = read_all(path());
  const std::vector<std::string> lines =
      lines_of(run("apitrace dump -v --color=never '" + path() + "'"));
  std::vector<uint32_t> dump_ends, our_ends;
  for (size_t i = 0; i + 1 < lines.size(); ++i)
    if (is_call_line(lines[i]) && lines[i + 1].empty())
      dump_ends.push_back(static_cast<uint32_t>(std::stoul(lines[i])));
  for (const auto& call : calls)
    if (ends_frame(call)) our_ends.push_back(call.number);
  EXPECT_EQ(our_ends, dump_ends);
  EXPECT_GE(our_ends.size(), 1u);
}

// scripts/replay-check's census (counted from `apitrace dump` text) is the
// reader's count of calls per function.
TEST_P(RecordedTrace, CensusOfReplayCheck) {
  std::ifstream in(kTraces / "results.json");
  ASSERT_TRUE(in) << "the gl_record_traces fixture wrote no results.json";
  const nlohmann::json results = nlohmann::json::parse(in);
  std::map<std::string, uint64_t> census, ours;
  for (const auto& program : results.at("programs"))
    if (program.at("program") == GetParam())
      census = program.at("functions").get<std::map<std::string, uint64_t>>();
  for (const auto& call : read_all(path())) ++ours[call.function];
  EXPECT_EQ(ours, census);
}

TEST_P(RecordedTrace, SameFileSameCalls) {
  const auto first = read_all(path());
  const auto second = read_all(path());
  EXPECT_TRUE(first == second);
}

INSTANTIATE_TEST_SUITE_P(Programs, RecordedTrace,
                         testing::Values("glxgears", "gears", "sierpinski3d"));

// ---------------------------------------------------------------------------
// Files written here

// The decompressed stream, spelled as FORMAT.markdown spells it.
struct Stream {
  std::string b;
  Stream& byte(int v) {
    b += static_cast<char>(v);
    return *this;
  }
  Stream& uint(uint64_t v) {
    do {
      const uint8_t low = v & 0x7F;
      v >>= 7;
      byte(v ? (low | 0x80) : low);
    } while (v);
    return *this;
  }
  Stream& str(const std::string& s) {
    uint(s.size());
    b += s;
    return *this;
  }
  Stream& f32(float f) {
    char raw[4];
    std::memcpy(raw, &f, 4);
    b.append(raw, 4);
    return *this;
  }
  Stream& f64(double d) {
    char raw[8];
    std::memcpy(raw, &d, 8);
    b.append(raw, 8);
    return *this;
  }
  Stream& header(int version = 6) {
    uint(version);
    if (version >= 6) uint(2).str("process.name").str("/usr/bin/synthetic").str("");
    return *this;
  }
};

// 'a' 't', then chunks: a little-endian uint32 length and snappy data. The
// stream is cut into chunks at `cuts`, so values straddle chunk boundaries.
std::string container(const std::string& stream, std::vector<size_t> cuts = {}) {
  std::string file = "at";
  cuts.push_back(stream.size());
  size_t from = 0;
  for (size_t to : cuts) {
    std::string compressed;
    snappy::Compress(stream.data() + from, to - from, &compressed);
    const uint32_t n = static_cast<uint32_t>(compressed.size());
    for (int i = 0; i < 4; ++i) file += static_cast<char>((n >> (8 * i)) & 0xFF);
    file += compressed;
    from = to;
  }
  return file;
}

class WrittenTrace : public testing::Test {
 protected:
  fs::path dir_;
  void SetUp() override {
    dir_ =
        fs::temp_directory_path() / ("gl_apitrace_reader_test_" + std::to_string(::getpid()) + "_" +
                                     testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& bytes) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
  }
  // The one-line message the reader throws, reading the whole file.
  std::string error_of(const std::string& path) {
    try {
      ApitraceReader reader(path);
      TraceCall call;
      while (reader.next(call)) {
      }
    } catch (const InputError& e) {
      return e.what();
    }
    return "(no error)";
  }
  void expect_error(const std::string& path, const std::string& text) {
    const std::string message = error_of(path);
    EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
    EXPECT_NE(message.find(text), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
};

// One trace with every value type, two threads whose calls finish out of
// order, a backtrace, a fake call, and a call the program never returned from.
std::string every_kind() {
  Stream s;
  s.header();
  // 0: glVertex3f on thread 0, its signature defined here.
  s.byte(0).uint(0).uint(0).str("glVertex3f").uint(3).str("x").str("y").str("z");
  s.byte(1).uint(0).byte(5).f32(1.5f).byte(1).uint(1).byte(5).f32(-2.25f).byte(0);
  s.byte(1).uint(0).byte(1).uint(2).byte(5).f32(1e-8f).byte(0);  // z at the leave
  // 1: glClear on thread 1, a bitmask with one bit no flag names; left later.
  s.byte(0).uint(1).uint(1).str("glClear").uint(1).str("mask");
  s.byte(1).uint(0).byte(10).uint(0).uint(2);
  s.str("GL_COLOR_BUFFER_BIT").uint(0x4000).str("GL_DEPTH_BUFFER_BIT").uint(0x100);
  s.uint(0x4101).byte(0);
  // 2: glVertex3f again (signature by id only), then its leave, before 1's.
  s.byte(0).uint(0).uint(0).byte(1).uint(0).byte(5).f32(0).byte(0);
  s.byte(1).uint(2).byte(0);
  s.byte(1).uint(1).byte(0);
  // 3: everything else; y is never recorded; a backtrace and the fake flag.
  s.byte(0).uint(0).uint(2).str("glEverything").uint(10);
  for (const char* n : {"e", "y", "st", "arr", "rep", "bl", "p", "d", "w", "one"}) s.str(n);
  s.byte(1).uint(0).byte(9).uint(0).uint(2).str("GL_TRIANGLES").byte(4).uint(4);
  s.str("GL_MINUS_ONE").byte(3).uint(1).byte(4).uint(4);  // GL_MINUS_ONE is -1
  s.byte(1).uint(2).byte(12).uint(0).str("S").uint(3).str("a").str("").str("b");
  s.byte(3).uint(7).byte(12).uint(1).str("Inner").uint(1).str("c").byte(2);
  s.byte(7).str("h\"i\n\x01");
  s.byte(1).uint(3).byte(11).uint(3).byte(0).byte(2).byte(1);
  s.byte(1).uint(4).byte(14).byte(7).str("GL_ONE").byte(4).uint(1);  // human, machine
  s.byte(1).uint(5).byte(8).str(std::string("\0\1\2", 3));
  s.byte(1).uint(6).byte(13).uint(0xDEADBEEF);
  s.byte(1).uint(7).byte(6).f64(0.1);
  s.byte(1).uint(8).byte(15).uint(2).uint(0x48).uint(0xE9);
  s.byte(1).uint(9).byte(11).uint(1).byte(9).uint(0).byte(4).uint(4);  // enum 0 by id
  s.byte(4)
      .uint(1)
      .uint(0)
      .byte(1)
      .str("libsynthetic.so")
      .byte(2)
      .str("main")
      .byte(4)
      .uint(42)
      .byte(0);
  s.byte(5).uint(1).byte(0);
  s.byte(1).uint(3).byte(2).byte(9).uint(0).byte(3).uint(1).byte(0);  // returns GL_MINUS_ONE
  // 4: eglSwapBuffers, entered, never left.
  s.byte(0).uint(0).uint(3).str("eglSwapBuffers").uint(2).str("dpy").str("surface");
  s.byte(1).uint(0).byte(13).uint(0x10).byte(1).uint(1).byte(13).uint(0x20).byte(0);
  return s.b;
}

TEST_F(WrittenTrace, EveryValueKindAsWritten) {
  const std::string bytes = every_kind();
  // Cuts inside a string, a float and a varint.
  const std::string path = write("every.trace", container(bytes, {37, 70, 200}));
  ApitraceReader reader(path);
  EXPECT_EQ(reader.version(), 6u);
  EXPECT_EQ(reader.semantic_version(), 2u);
  ASSERT_EQ(reader.properties().size(), 1u);
  EXPECT_EQ(reader.properties()[0].second, "/usr/bin/synthetic");
  std::vector<TraceCall> calls;
  TraceCall call;
  while (reader.next(call)) calls.push_back(call);
  ASSERT_EQ(calls.size(), 5u);
  using K = TraceValue::Kind;
  // In the order their leave events came: 0, 2, 1, 3, then 4 (never left).
  EXPECT_EQ(calls[0].number, 0u);
  EXPECT_EQ(calls[1].number, 2u);
  EXPECT_EQ(calls[2].number, 1u);
  EXPECT_EQ(calls[3].number, 3u);
  EXPECT_EQ(calls[4].number, 4u);
  EXPECT_EQ(calls[0].function, "glVertex3f");
  EXPECT_EQ(calls[0].args[0].kind, K::float32);
  EXPECT_EQ(calls[0].args[0].real, 1.5);
  EXPECT_EQ(calls[0].args[1].to_double(), -2.25);
  EXPECT_EQ(calls[0].args[2].real, static_cast<double>(1e-8f));
  EXPECT_FALSE(calls[0].has_ret);
  EXPECT_EQ(calls[2].thread, 1u);
  EXPECT_EQ(calls[2].args[0].kind, K::bitmask);
  EXPECT_EQ(calls[2].args[0].to_uint(), 0x4101u);
  EXPECT_EQ(calls[2].args[0].name, "GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | 0x1");
  EXPECT_EQ(calls[1].args[1].kind, K::null);  // y, z never recorded
  EXPECT_FALSE(calls[1].arg_recorded[1]);

  const TraceCall& e = calls[3];
  EXPECT_EQ(e.args[0].kind, K::enumeration);
  EXPECT_EQ(e.args[0].to_int(), 4);
  EXPECT_EQ(e.args[0].name, "GL_TRIANGLES");
  EXPECT_EQ(e.args[1].kind, K::null);
  EXPECT_FALSE(e.arg_recorded[1]);
  EXPECT_EQ(e.args[2].kind, K::structure);
  EXPECT_EQ(e.args[2].name, "S");
  ASSERT_EQ(e.args[2].elements.size(), 3u);
  EXPECT_EQ(e.args[2].elements[0].to_int(), -7);
  EXPECT_EQ(e.args[2].elements[1].elements[0].kind, K::boolean);
  EXPECT_EQ(e.args[2].elements[2].bytes, "h\"i\n\x01");
  EXPECT_EQ(e.args[3].elements.size(), 3u);
  EXPECT_EQ(e.args[3].elements[1].to_int(), 1);
  EXPECT_EQ(e.args[3].elements[2].to_int(), 0);
  ASSERT_EQ(e.args[4].kind, K::repr);
  EXPECT_EQ(e.args[4].elements[0].to_uint(), 1u);    // machine
  EXPECT_EQ(e.args[4].elements[1].bytes, "GL_ONE");  // human
  EXPECT_EQ(e.args[5].kind, K::blob);
  EXPECT_EQ(e.args[5].bytes, std::string("\0\1\2", 3));
  EXPECT_EQ(e.args[6].kind, K::pointer);
  EXPECT_EQ(e.args[6].uint, 0xDEADBEEFu);
  EXPECT_EQ(e.args[7].kind, K::float64);
  EXPECT_EQ(e.args[7].real, 0.1);
  EXPECT_EQ(e.args[8].bytes, "H\xC3\xA9");  // L"Hé" as UTF-8
  EXPECT_EQ(e.args[9].elements.at(0).name, "GL_TRIANGLES");
  EXPECT_TRUE(e.fake);
  EXPECT_TRUE(e.has_ret);
  EXPECT_EQ(e.ret.to_int(), -1);
  EXPECT_EQ(e.ret.name, "GL_MINUS_ONE");
  EXPECT_THROW(e.args[2].to_double(), InputError);
  EXPECT_THROW(e.args[5].to_int(), InputError);
  EXPECT_THROW(e.args[6].to_uint(), InputError);

  EXPECT_TRUE(calls[4].incomplete);
  EXPECT_TRUE(ends_frame(calls[4]));
  EXPECT_FALSE(ends_frame(calls[3]));
  EXPECT_EQ(calls[4].args[1].uint, 0x20u);
}

// apitrace reads the same hand-written file: its dump is our printing, line
// for line (the wide string apart: we read it as UTF-8, dump prints L"...").
TEST_F(WrittenTrace, ApitraceReadsItAsWeDo) {
  const std::string path = write("every.trace", container(every_kind(), {37, 70, 200}));
  std::vector<std::string> dump;
  for (const auto& line :
       lines_of(run("apitrace dump -v --color=never --multiline=false '" + path + "'")))
    if (is_call_line(line)) dump.push_back(line);
  const auto calls = read_all(path);
  ASSERT_EQ(dump.size(), calls.size());
  for (size_t i = 0; i < calls.size(); ++i) {
    std::string ours = text_of(calls[i]);
    if (calls[i].function == "glEverything") {
      std::ostringstream wide;
      wide << "w = " << calls[i].args[8];
      ASSERT_NE(ours.find(wide.str()), std::string::npos);
      ours.replace(ours.find(wide.str()), wide.str().size(), "w = L\"H\\551\"");
    }
    EXPECT_EQ(ours, dump[i]);
  }
}

TEST_F(WrittenTrace, OlderVersions) {
  // Version 3: no semantic version, no properties; the thread number is a
  // call detail; enums as in version 6.
  Stream v3;
  v3.uint(3).byte(0).uint(0).str("glBegin").uint(1).str("mode");
  v3.byte(1).uint(0).byte(9).uint(0).uint(1).str("GL_QUADS").byte(4).uint(7).byte(4).uint(7);
  v3.byte(3).uint(5).byte(0).byte(1).uint(0).byte(0);
  const auto calls3 = read_all(write("v3.trace", container(v3.b)));
  ASSERT_EQ(calls3.size(), 1u);
  EXPECT_EQ(calls3[0].thread, 5u);
  EXPECT_EQ(calls3[0].args[0].name, "GL_QUADS");
  // Version 2: an enum signature holds one name and its value, and the value
  // is not repeated after it.
  Stream v2;
  v2.uint(2).byte(0).uint(0).str("glBegin").uint(1).str("mode");
  v2.byte(1).uint(0).byte(9).uint(0).str("GL_QUADS").byte(4).uint(7).byte(0);
  v2.byte(1).uint(0).byte(0);
  const auto calls2 = read_all(write("v2.trace", container(v2.b)));
  ASSERT_EQ(calls2.size(), 1u);
  EXPECT_EQ(calls2[0].args[0].to_int(), 7);
  EXPECT_EQ(calls2[0].args[0].name, "GL_QUADS");
}

TEST_F(WrittenTrace, BadFilesOneLine) {
  expect_error((dir_ / "missing.trace").string(), "cannot read: No such file");
  expect_error(dir_.string(), "cannot read: not a regular file");
  expect_error(write("empty.trace", ""), "not an apitrace trace");
  expect_error(write("text.trace", "hello, world\n"), "not an apitrace trace");
  expect_error(write("gzip.trace", "\x1f\x8b\x08\x00"), "gzip-compressed");
  expect_error(write("v7.trace", container(Stream().uint(7).b)),
               "unsupported trace format version 7");
  expect_error(write("noheader.trace", "at"), "truncated trace: no header");

  std::string event = Stream().header().byte(7).b;
  expect_error(write("event.trace", container(event)), "corrupt trace at decompressed byte " +
                                                           std::to_string(event.size() - 1) +
                                                           ": unknown event 7");
  Stream type;
  type.header().byte(0).uint(0).uint(0).str("f").uint(1).str("a").byte(1).uint(0).byte(0x33);
  expect_error(write("type.trace", container(type.b)), "unknown value type 51");
  Stream detail;
  detail.header().byte(0).uint(0).uint(0).str("f").uint(0).byte(9);
  expect_error(write("detail.trace", container(detail.b)), "unknown call detail 9 in call 0 f");

  // A chunk whose bytes are not snappy data (a length varint far beyond the
  // chunk limit).
  std::string bad = "at";
  bad += std::string("\x05\x00\x00\x00", 4) + "\xff\xff\xff\xff\x7f";
  expect_error(write("snappy.trace", bad), "is not valid snappy data");
  std::string huge = "at";
  huge += std::string("\x00\x00\x00\x7f", 4);
  expect_error(write("huge.trace", huge), "corrupt trace: chunk of 2130706432 bytes");
}

TEST_F(WrittenTrace, TruncatedFilesOneLine) {
  const std::string whole = container(every_kind(), {37, 70, 200});
  // Every cut inside the container: the length fields, the chunks' data.
  size_t cuts = 0;
  for (size_t n = 3; n < whole.size(); n += 3) {
    const std::string message = error_of(write("cut.trace", whole.substr(0, n)));
    EXPECT_NE(message.find(": truncated trace"), std::string::npos) << n << ": " << message;
    ++cuts;
  }
  EXPECT_GT(cuts, 100u);
  // A stream cut inside an event, in a container that is itself whole.
  const std::string stream = every_kind();
  expect_error(write("event.trace", container(stream.substr(0, stream.size() - 3))),
               "truncated trace: the data ends inside an event");
}

TEST_F(WrittenTrace, TruncatedRecording) {
  const std::string recorded = (kTraces / "glxgears" / "glxgears.trace").string();
  ASSERT_TRUE(fs::exists(recorded)) << "the gl_record_traces fixture did not record glxgears";
  std::ifstream in(recorded, std::ios::binary);
  const std::string whole((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (size_t n : {size_t(4), whole.size() / 3, whole.size() / 2, whole.size() - 1}) {
    const std::string message = error_of(write("cut.trace", whole.substr(0, n)));
    EXPECT_NE(message.find(": truncated trace"), std::string::npos) << n << ": " << message;
  }
}

TEST(TraceValue, Conversions) {
  TraceValue v;
  v.kind = TraceValue::Kind::float32;
  v.real = -2.75;
  EXPECT_EQ(v.to_int(), -2);  // toward zero, as a C cast
  EXPECT_EQ(v.to_double(), -2.75);
  v.kind = TraceValue::Kind::boolean;
  v.sint = 1;
  EXPECT_EQ(v.to_uint(), 1u);
  v.kind = TraceValue::Kind::string;
  EXPECT_THROW(v.to_int(), InputError);
  v.kind = TraceValue::Kind::null;
  EXPECT_THROW(v.to_double(), InputError);
}

}  // namespace
}  // namespace gpusim::gl
