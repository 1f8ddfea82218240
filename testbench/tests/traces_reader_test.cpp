// The trace reader on files written byte by byte here, following
// docs/traces.md's tables rather than the recorder's code: every field at its
// documented offset, and bad or truncated files rejected with one line naming
// the file, by the library and by the command line (exit status 2).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "hw/input_error.h"
#include "testbench/tests/traces_support.h"
#include "traces/trace_follow.h"
#include "traces/trace_reader.h"
#include "traces/vcd_reader.h"

namespace gpusim {
namespace {

namespace fs = std::filesystem;
using trace_test::CommandResult;
using trace_test::gpusim;

// Little-endian fields appended to a byte string.
struct Bytes {
  std::string b;
  template <typename T>
  Bytes& put(T v) {
    uint64_t u = 0;
    std::memcpy(&u, &v, sizeof v);
    for (size_t i = 0; i < sizeof v; ++i) b += static_cast<char>((u >> (8 * i)) & 0xFF);
    return *this;
  }
  Bytes& text(const char* s) {
    b += s;
    return *this;
  }
};

std::string header(const char* magic, uint32_t version = 1, uint32_t size = 48) {
  return Bytes().text(magic).put(version).put(size).b;
}

class TraceReaderTest : public trace_test::TraceTest {
 protected:
  // A one-unit trace of one triangle (primitive 0) with one transaction per
  // front-end stage it passed and two fragments, written from the contract.
  void SetUp() override {
    TraceTest::SetUp();
    trace_ = (dir_ / "t").string();
    fs::create_directories(trace_);
    nlohmann::json stages = nlohmann::json::array();
    const char* names[] = {"command_processor", "primitive_setup", "depth_test_0", "rop_0"};
    const char* kinds[] = {"command_processor", "primitive_setup", "depth_test", "rop"};
    // What the stages' specs say of their records (docs/traces.md).
    const char* items[] = {"draw", "primitive", "stamp batch", "stamp batch"};
    for (int i = 0; i < 4; ++i) {
      stages.push_back({{"index", i},
                        {"name", names[i]},
                        {"kind", kinds[i]},
                        {"unit", i >= 2 ? nlohmann::json(0) : nlohmann::json()},
                        {"inputs", {"in" + std::to_string(i)}},
                        {"outputs", nlohmann::json::array()},
                        {"item", items[i]}});
    }
    manifest_ = {
        {"format", "gpusim-trace"},
        {"version", 2},
        {"scene", "synthetic.json"},
        {"config", nlohmann::json::object()},
        {"clock_mhz", 1000},
        {"cycle_ps", 1000},
        {"cycles", 100},
        {"framebuffer",
         {{"width", 16}, {"height", 16}, {"tile_size", 16}, {"tiles_x", 1}, {"tiles_y", 1}}},
        {"units", 1},
        {"filters", {{"stages", nullptr}, {"window", nullptr}, {"prims", nullptr}}},
        {"stages", stages},
        {"fifos", nlohmann::json::array()},
        {"draws", {{{"first_primitive_id", 0}, {"primitives", 1}}}},
        {"records", {{"transactions", 2}, {"fragments", 2}}}};
    write_json("t/manifest.json", manifest_);
    // Records: the setup's triangle, then the processor's draw: cycle_in,
    // cycle_out, prim_first, prim_last, draw, stage, kind, prim_kind (0: as
    // written before the field, when the byte was reserved), tile_x, tile_y,
    // count. The manifest's draws lack "primitive" and "polygon_mode" alike.
    transactions_ = header("GPUSIMTX");
    transactions_ += Bytes()
                         .put<uint64_t>(74)
                         .put<uint64_t>(78)
                         .put<int64_t>(0)
                         .put<int64_t>(0)
                         .put<uint32_t>(0)
                         .put<uint16_t>(1)
                         .put<uint8_t>(0)
                         .put<uint8_t>(0)
                         .put<int16_t>(-1)
                         .put<int16_t>(-1)
                         .put<uint32_t>(1)
                         .b;
    transactions_ += Bytes()
                         .put<uint64_t>(1)
                         .put<uint64_t>(0x100000002ull)  // a value needing all 8 bytes
                         .put<int64_t>(0)
                         .put<int64_t>(0)
                         .put<uint32_t>(0)
                         .put<uint16_t>(0)
                         .put<uint8_t>(0)
                         .put<uint8_t>(0)
                         .put<int16_t>(3)
                         .put<int16_t>(-1)
                         .put<uint32_t>(7)
                         .b;
    // A depth-test fragment at (3, 4): passed, 0.25 against 1.0, stored
    // 0.25; its ROP write of (1, 0.5, 0, 1).
    const float nan = std::nanf("");
    fragments_ = header("GPUSIMFR");
    fragments_ += Bytes()
                      .put<uint64_t>(116)
                      .put<int64_t>(0)
                      .put<uint16_t>(3)
                      .put<uint16_t>(4)
                      .put<uint8_t>(0)
                      .put<uint8_t>(0)
                      .put<uint8_t>(1)
                      .put<uint8_t>(0)
                      .put(0.25f)
                      .put(1.0f)
                      .put(0.25f)
                      .put(nan)
                      .put(nan)
                      .put(nan)
                      .b;
    fragments_ += Bytes()
                      .put<uint64_t>(144)
                      .put<int64_t>(0)
                      .put<uint16_t>(3)
                      .put<uint16_t>(4)
                      .put<uint8_t>(1)
                      .put<uint8_t>(0)
                      .put<uint8_t>(1)
                      .put<uint8_t>(0)
                      .put(nan)
                      .put(nan)
                      .put(1.0f)
                      .put(0.5f)
                      .put(0.0f)
                      .put(1.0f)
                      .b;
    write_files();
  }

  void write_files() {
    std::ofstream(trace_ + "/transactions.bin", std::ios::binary) << transactions_;
    std::ofstream(trace_ + "/fragments.bin", std::ios::binary) << fragments_;
  }

  // The InputError message of opening the trace, "" when it opens.
  std::string open_error() {
    try {
      TraceReader r(trace_);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }

  // The command line rejects the trace: exit 2, one line starting with
  // "gpusim: <file>: " and holding `what`.
  void expect_cli_error(const std::string& file, const std::string& what) {
    const CommandResult r = gpusim("trace follow " + trace_ + " --prim 0");
    EXPECT_EQ(r.status, 2) << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
    EXPECT_EQ(r.out.rfind("gpusim: " + trace_ + "/" + file + ": ", 0), 0u) << r.out;
    EXPECT_NE(r.out.find(what), std::string::npos) << r.out;
  }

  std::string trace_;
  nlohmann::json manifest_;
  std::string transactions_, fragments_;
};

TEST_F(TraceReaderTest, ReadsEveryFieldAtItsDocumentedOffset) {
  const TraceReader reader(trace_);
  EXPECT_EQ(reader.manifest().cycles, 100u);
  EXPECT_EQ(reader.manifest().stages.size(), 4u);
  EXPECT_EQ(reader.manifest().stages[2].unit, 0);
  EXPECT_EQ(reader.manifest().stages[0].unit, -1);
  EXPECT_FALSE(reader.manifest().filters.any());
  EXPECT_EQ(reader.manifest().filters.describe(), "none");

  std::vector<TransactionRecord> t;
  reader.for_each_transaction([&](const TransactionRecord& r) { t.push_back(r); });
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[0].cycle_in, 74u);
  EXPECT_EQ(t[0].cycle_out, 78u);
  EXPECT_EQ(t[0].stage, 1u);
  EXPECT_EQ(t[0].tile_x, -1);
  EXPECT_EQ(t[1].cycle_out, 0x100000002ull);
  EXPECT_EQ(t[1].tile_x, 3);
  EXPECT_EQ(t[1].tile_y, -1);
  EXPECT_EQ(t[1].count, 7u);
  EXPECT_TRUE(t[1].carries(0));
  EXPECT_FALSE(t[1].carries(1));
  EXPECT_EQ(t[0].prim_kind, TransactionRecord::prim_none);
  EXPECT_EQ(reader.manifest().draws[0].primitive, "");
  EXPECT_EQ(reader.manifest().prim_word(0), "primitive");  // a trace from before lines

  std::vector<FragmentRecord> f;
  reader.for_each_fragment([&](const FragmentRecord& r) { f.push_back(r); });
  ASSERT_EQ(f.size(), 2u);
  EXPECT_EQ(f[0].cycle, 116u);
  EXPECT_EQ(f[0].x, 3);
  EXPECT_EQ(f[0].y, 4);
  EXPECT_EQ(f[0].stage, FragmentRecord::at_test);
  EXPECT_EQ(f[0].outcome, FragmentRecord::passed);
  EXPECT_EQ(f[0].depth, 0.25f);
  EXPECT_EQ(f[0].old_depth, 1.0f);
  EXPECT_EQ(f[0].value[0], 0.25f);
  EXPECT_TRUE(std::isnan(f[0].value[1]));
  EXPECT_EQ(f[1].stage, FragmentRecord::at_write);
  EXPECT_TRUE(std::isnan(f[1].depth));
  EXPECT_EQ(f[1].value[1], 0.5f);

  // follow orders by pipeline position, whatever the file order.
  const std::vector<TraceFollow::Step> steps = TraceFollow(reader).prim_steps(0);
  ASSERT_EQ(steps.size(), 2u);
  EXPECT_EQ(steps[0].stage->name, "command_processor");
  EXPECT_EQ(steps[1].stage->name, "primitive_setup");
  EXPECT_EQ(TraceFollow(reader).pixel_fragments(3, 4).size(), 2u);
  EXPECT_TRUE(TraceFollow(reader).pixel_fragments(4, 3).empty());
}

TEST_F(TraceReaderTest, NamesLinesAndPointsFromTheRecordsAndTheManifest) {
  // Two draws: a line strip of 3 lines (ids 0..2) and 2 points (ids 3..4);
  // the setup's record is line 0 (prim_kind 2), the processor's the draw.
  manifest_["draws"] = {{{"first_primitive_id", 0},
                         {"primitives", 3},
                         {"primitive", "line_strip"},
                         {"polygon_mode", "fill"}},
                        {{"first_primitive_id", 3},
                         {"primitives", 2},
                         {"primitive", "points"},
                         {"polygon_mode", "line"}}};
  write_json("t/manifest.json", manifest_);
  transactions_[16 + 39] = 2;
  transactions_[16 + 48 + 39] = 2;
  transactions_.replace(16 + 48 + 24, 8, Bytes().put<int64_t>(2).b);  // the draw: lines 0..2
  write_files();
  const TraceReader reader(trace_);
  const TraceManifest& m = reader.manifest();
  EXPECT_EQ(m.draws[0].primitive, "line_strip");
  EXPECT_EQ(m.draws[1].polygon_mode, "line");
  EXPECT_EQ(m.draw_of(2), 0);
  EXPECT_EQ(m.draw_of(3), 1);
  EXPECT_EQ(m.draw_of(5), -1);
  EXPECT_EQ(m.prim_word(0), "line");
  EXPECT_EQ(m.prim_word(4), "point");
  EXPECT_EQ(m.prim_word(5), "primitive");
  std::vector<TransactionRecord> t;
  reader.for_each_transaction([&](const TransactionRecord& r) { t.push_back(r); });
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[0].prim_kind, TransactionRecord::prim_line);

  const std::string text = TraceFollow(reader).prim_text(0);
  // Polygon mode is named for triangles only: a points draw ignores it.
  EXPECT_EQ(text.rfind("line 0 (draw 0, line_strip) in " + trace_ + ": 2 items at 2 stages\n", 0),
            0u)
      << text;
  EXPECT_NE(text.find("draw 0: lines 0..2\n"), std::string::npos) << text;
  EXPECT_NE(text.find("      1  line\n"), std::string::npos) << text;  // the setup's row
  EXPECT_EQ(text.find("triangle"), std::string::npos) << text;         // a line, set up as one
  // Point 4 has no record: the absence names it as a point.
  EXPECT_EQ(TraceFollow(reader).prim_text(4), "point 4 never appears in transactions.bin\n");

  // A primitive kind beyond 3 is a damaged file.
  transactions_[16 + 39] = 4;
  write_files();
  try {
    TraceReader(trace_).for_each_transaction([](const TransactionRecord&) {});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(
        e.what(),
        (trace_ + "/transactions.bin: record 0: primitive kind 4 is not 0, 1, 2 or 3").c_str());
  }
}

TEST_F(TraceReaderTest, RejectsBadMagic) {
  transactions_.replace(0, 8, "GPUSIMXX");
  write_files();
  EXPECT_EQ(open_error(),
            trace_ + "/transactions.bin: bad magic \"GPUSIMXX\", expected \"GPUSIMTX\"");
  expect_cli_error("transactions.bin", "bad magic");
}

TEST_F(TraceReaderTest, RejectsATruncatedRecord) {
  fragments_.resize(fragments_.size() - 5);
  write_files();
  EXPECT_EQ(open_error(), trace_ +
                              "/fragments.bin: truncated: 91 bytes after the header is not a whole "
                              "number of 48-byte records");
  expect_cli_error("fragments.bin", "truncated");
}

TEST_F(TraceReaderTest, RejectsMissingRecordsAndShortHeaders) {
  transactions_.resize(16 + 48);
  write_files();
  EXPECT_EQ(open_error(),
            trace_ + "/transactions.bin: holds 1 records, manifest.json says 2 (truncated)");
  expect_cli_error("transactions.bin", "(truncated)");

  transactions_.resize(10);
  write_files();
  EXPECT_EQ(open_error(), trace_ +
                              "/transactions.bin: truncated: 10 bytes, shorter than the "
                              "16-byte header");
}

TEST_F(TraceReaderTest, RejectsOtherVersionsAndRecordSizes) {
  fragments_.replace(0, 16, header("GPUSIMFR", 2));
  write_files();
  EXPECT_EQ(open_error(), trace_ + "/fragments.bin: version 2, this reader knows version 1");
  fragments_.replace(0, 16, header("GPUSIMFR", 1, 40));
  write_files();
  EXPECT_EQ(open_error(), trace_ + "/fragments.bin: record size 40, expected 48");
}

TEST_F(TraceReaderTest, RejectsABadManifest) {
  manifest_["stages"][1].erase("kind");
  write_json("t/manifest.json", manifest_);
  EXPECT_EQ(open_error(), trace_ + "/manifest.json: stages[1].kind: missing");
  expect_cli_error("manifest.json", "stages[1].kind: missing");
  std::ofstream(trace_ + "/manifest.json") << "{\"format\": ";
  EXPECT_EQ(open_error().rfind(trace_ + "/manifest.json: not valid JSON", 0), 0u);
}

TEST_F(TraceReaderTest, RejectsARecordNamingAnUnknownStage) {
  transactions_[16 + 36] = 9;  // stage 9 of 4
  write_files();
  const TraceReader reader(trace_);
  try {
    reader.for_each_transaction([](const TransactionRecord&) {});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), (trace_ + "/transactions.bin: record 0: stage 9 is not in "
                                     "manifest.json's 4 stages")
                               .c_str());
  }
}

// A VCD in the layout docs/traces.md describes, written by hand.
const char* const kVcd =
    "$date today $end\n$version test $end\n"
    "$comment one time unit is one clock cycle $end\n$timescale 1 ns $end\n"
    "$scope module gpu $end\n"
    "$scope module primitive_setup $end\n"
    "$var wire 1 ! busy $end\n$var wire 1 \" stalled $end\n$var wire 1 # starved $end\n"
    "$upscope $end\n"
    "$scope module fifos $end\n$var wire 5 $ clipper_to_setup [4:0] $end\n$upscope $end\n"
    "$upscope $end\n$enddefinitions $end\n"
    "#0\n$dumpvars\n0!\n0\"\n1#\nb0 $\n$end\n"
    "#10\n1!\n0#\nb11 $\n"
    "#15\nb10000 $\n"
    "#25\n0!\n1\"\nbx $\n"
    "#40\n";

TEST(VcdReader, ScopesVariablesChangesAndHistograms) {
  const std::string path = ::testing::TempDir() + "/gpusim_vcd_reader_" + std::to_string(getpid());
  std::ofstream(path) << kVcd;
  const VcdReader vcd(path);
  EXPECT_EQ(vcd.timescale(), "1 ns");
  ASSERT_EQ(vcd.signals().size(), 4u);
  EXPECT_EQ(vcd.signals()[0].scope, "gpu.primitive_setup");
  EXPECT_EQ(vcd.signals()[3].scope, "gpu.fifos");
  EXPECT_EQ(vcd.signals()[3].width, 5u);
  const auto busy = vcd.find("gpu.primitive_setup", "busy");
  const auto fifo = vcd.find("gpu.fifos", "clipper_to_setup");
  ASSERT_TRUE(busy && fifo);

  const auto changes = vcd.changes();
  const std::vector<std::pair<uint64_t, uint64_t>> busy_changes = {{0, 0}, {10, 1}, {25, 0}};
  EXPECT_EQ(changes[*busy], busy_changes);
  const std::vector<std::pair<uint64_t, uint64_t>> fifo_changes = {
      {0, 0}, {10, 3}, {15, 16}, {25, VcdReader::kUnknown}};
  EXPECT_EQ(changes[*fifo], fifo_changes);

  // [0, 40): busy 10..25; the FIFO 10 cycles at 0, 5 at 3, 10 at 16.
  const auto h = vcd.histograms(0, 40);
  EXPECT_EQ(h[*busy].at(1), 15u);
  EXPECT_EQ(h[*busy].at(0), 25u);
  EXPECT_EQ(h[*fifo].at(0), 10u);
  EXPECT_EQ(h[*fifo].at(3), 5u);
  EXPECT_EQ(h[*fifo].at(16), 10u);
  // A window cuts the intervals.
  const auto w = vcd.histograms(12, 20);
  EXPECT_EQ(w[*busy].at(1), 8u);
  EXPECT_EQ(w[*fifo].at(3), 3u);
  EXPECT_EQ(w[*fifo].at(16), 5u);

  // Not a VCD, or cut before $enddefinitions: one line naming the file.
  std::ofstream(path) << std::string(kVcd).substr(0, std::string(kVcd).find("$enddefinitions"));
  try {
    VcdReader bad(path);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path + ": line ", 0), 0u) << e.what();
    EXPECT_NE(std::string(e.what()).find("no $enddefinitions"), std::string::npos) << e.what();
  }
  std::ofstream(path) << std::string(kVcd) + "#50\nq!\n";
  try {
    VcdReader(path).changes();
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("line 35: unexpected \"q!\""), std::string::npos)
        << e.what();
  }
  std::remove(path.c_str());
}

TEST(VcdReader, ReadsSimulatedTimeAsCycles) {
  const std::string path = ::testing::TempDir() + "/gpusim_vcd_cycles_" + std::to_string(getpid());
  const std::string header =
      "$timescale 1 ps $end\n$scope module gpu $end\n$var wire 1 ! b $end\n$upscope $end\n"
      "$enddefinitions $end\n";
  std::ofstream(path) << header + "#0\n$dumpvars\n0!\n$end\n#6666\n1!\n#16665\n";
  const auto b_changes = [&](uint64_t cycle_ps) { return VcdReader(path, cycle_ps).changes()[0]; };
  const std::vector<std::pair<uint64_t, uint64_t>> ps = {{0, 0}, {6666, 1}};
  const std::vector<std::pair<uint64_t, uint64_t>> cycles = {{0, 0}, {2, 1}};
  EXPECT_EQ(b_changes(0), ps);
  EXPECT_EQ(b_changes(3333), cycles);  // 300 MHz
  EXPECT_EQ(VcdReader(path, 3333).histograms(0, 5)[0].at(1), 3u);
  // Off a cycle boundary, or a period the time unit does not divide.
  std::ofstream(path) << header + "#0\n0!\n#5000\n1!\n";
  try {
    VcdReader(path, 3333).changes();
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("#5000 is not on a clock cycle boundary"),
              std::string::npos)
        << e.what();
  }
  std::ofstream(path) << "$timescale 1 ns $end\n$enddefinitions $end\n";
  EXPECT_THROW(VcdReader(path, 3333), InputError);
  EXPECT_EQ(VcdReader(path, 2000).units_per_time(), 2u);
  // Traces written before: times are cycles, whatever the timescale says.
  std::ofstream(path) << "$comment one time unit is one clock cycle of 3333 ps $end\n"
                         "$timescale 1 ps $end\n$enddefinitions $end\n";
  EXPECT_EQ(VcdReader(path, 3333).units_per_time(), 1u);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace gpusim
