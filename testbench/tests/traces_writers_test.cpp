// The recorder's parts on their own (docs/traces.md): which primitives a
// vertex batch carries for each primitive type, the filter syntax, the VCD
// writer's window and time scale, and exact microseconds in the timeline.
// Expected values are worked out by hand from the assembly rules (list:
// triangle k uses slots 3k..3k+2; strip: k..k+2; fan: 0, k+1, k+2).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "hw/input_error.h"
#include "testbench/tests/file_bytes.h"
#include "traces/timeline_writer.h"
#include "traces/trace_filter.h"
#include "traces/trace_items.h"
#include "traces/vcd_writer.h"

namespace gpusim {
namespace {

namespace fs = std::filesystem;

// A frame of one draw of `slots` slots whose first primitive id is 100.
FrameState one_draw(PrimitiveType type, uint32_t slots) {
  FrameState f;
  DrawState d;
  d.primitive = type;
  d.buffers.slot_count = slots;
  d.first_primitive_id = 100;
  f.draws.push_back(d);
  return f;
}

std::pair<int64_t, int64_t> prims(const FrameState& f, uint32_t first_slot, uint32_t count) {
  BatchHeader b;
  b.first_slot = first_slot;
  b.slot_count = count;
  const ItemInfo i = ItemDescriber(f, 16).describe(b);
  EXPECT_EQ(i.count, count);
  return {i.prim_first, i.prim_last};
}

using Range = std::pair<int64_t, int64_t>;

TEST(TraceItems, BatchesCarryThePrimitivesUsingTheirSlots) {
  // 70 slots as a list: 23 triangles (slots 0..68), slot 69 unused.
  const FrameState list = one_draw(PrimitiveType::triangles, 70);
  EXPECT_EQ(prims(list, 0, 32), Range(100, 110));   // slots 0..31: triangles 0..10 (30..32)
  EXPECT_EQ(prims(list, 32, 32), Range(110, 121));  // slots 32..63: triangles 10..21
  EXPECT_EQ(prims(list, 64, 6), Range(121, 122));   // slots 64..69: 21 (63..65), 22 (66..68)
  // A strip of 40 slots: 38 triangles; slots 32..39 are used by 30..37.
  const FrameState strip = one_draw(PrimitiveType::triangle_strip, 40);
  EXPECT_EQ(prims(strip, 0, 32), Range(100, 131));
  EXPECT_EQ(prims(strip, 32, 8), Range(130, 137));
  // A fan of 40 slots: every triangle uses slot 0; slots 32..39 by 30..37.
  const FrameState fan = one_draw(PrimitiveType::triangle_fan, 40);
  EXPECT_EQ(prims(fan, 0, 32), Range(100, 137));
  EXPECT_EQ(prims(fan, 32, 8), Range(130, 137));
  // Too few slots for a triangle: none.
  EXPECT_EQ(prims(one_draw(PrimitiveType::triangles, 2), 0, 2), Range(-1, -1));
  // A draw command carries all of them.
  const ItemInfo draw = ItemDescriber(list, 16).describe(Command{PacketKind::work, 0});
  EXPECT_EQ(Range(draw.prim_first, draw.prim_last), Range(100, 122));
  EXPECT_EQ(draw.count, 23u);
  const ItemInfo clear = ItemDescriber(list, 16).describe(Command{PacketKind::clear, 0});
  EXPECT_EQ(clear.kind, 1);
  EXPECT_EQ(clear.prim_first, -1);
  EXPECT_EQ(clear.draw, ItemInfo::kNoDraw);
}

TEST(TraceItems, StampBatchesAreInTheirFirstStampsTile) {
  const FrameState f = one_draw(PrimitiveType::triangles, 3);
  auto tri = std::make_shared<RasterPrimitive>();
  tri->primitive_id = 7;
  StampBatch b;
  b.primitive = tri;
  b.stamps.push_back(Stamp{36, 20, 0xF, {}});
  b.stamps.push_back(Stamp{40, 20, 0xF, {}});
  const ItemInfo i = ItemDescriber(f, 16).describe(b);
  EXPECT_EQ(i.tile_x, 2);
  EXPECT_EQ(i.tile_y, 1);
  EXPECT_EQ(i.count, 2u);
  EXPECT_EQ(i.prim_first, 7);
}

TEST(TraceFilter, ParsesAndRejects) {
  const TraceFilter w = TraceFilter::parse("", ":5000", "3:3");
  EXPECT_TRUE(w.item_in_window(4999, 6000));
  EXPECT_FALSE(w.item_in_window(5000, 6000));
  EXPECT_TRUE(w.item_in_window(0, 1));
  EXPECT_TRUE(w.prims_match(0, 3));
  EXPECT_FALSE(w.prims_match(4, 9));
  EXPECT_FALSE(w.prims_match(-1, -1));
  const TraceFilter open = TraceFilter::parse("", "1000:", "");
  EXPECT_FALSE(open.item_in_window(0, 1000));  // [0, 1000) ends where the window starts
  EXPECT_TRUE(open.item_in_window(999, 1001));
  EXPECT_TRUE(open.item_in_window(1000, 1000));  // an instant inside
  EXPECT_TRUE(open.prims_match(-1, -1));
  for (const char* bad : {"5", "a:b", "5:5", "9:1", "-1:4", "1:2:3"}) {
    EXPECT_THROW(TraceFilter::parse("", bad, ""), InputError) << bad;
  }
  for (const char* bad : {"5", "2:1", "a:3", ":3", "3:"}) {
    EXPECT_THROW(TraceFilter::parse("", "", bad), InputError) << bad;
  }
  EXPECT_THROW(TraceFilter::parse("rop,,clipper", "", ""), InputError);

  NetlistTables t;
  t.stages = {{"clipper", "clipper", -1, {0}, {}, "primitive", {}, ""},
              {"rop_0", "rop", 0, {1}, {}, "stamp batch", {}, "write"},
              {"rop_1", "rop", 1, {2}, {}, "stamp batch", {}, "write"}};
  EXPECT_EQ(TraceFilter::parse("rop", "", "").stages_kept(t),
            (std::vector<bool>{false, true, true}));
  EXPECT_EQ(TraceFilter::parse("clipper,rop_1", "", "").stages_kept(t),
            (std::vector<bool>{true, false, true}));
  EXPECT_THROW(TraceFilter::parse("rop_2", "", "").stages_kept(t), InputError);

  // A renamed stage's former name selects it, with one warning.
  t.stages.push_back({"primitive_setup", "primitive_setup", -1, {3}, {}, "primitive", {}, ""});
  testing::internal::CaptureStderr();
  EXPECT_EQ(TraceFilter::parse("triangle_setup,rop_1", "", "").stages_kept(t),
            (std::vector<bool>{false, false, true, true}));
  const std::string warned = testing::internal::GetCapturedStderr();
  EXPECT_NE(warned.find("--trace-stages: 'triangle_setup' is deprecated, read as "
                        "'primitive_setup'"),
            std::string::npos)
      << warned;
}

TEST(VcdWriter, WritesTheWindowWithItsStartValues) {
  const fs::path path = fs::path(::testing::TempDir()) / ("vcd_" + std::to_string(getpid()));
  {
    VcdWriter w(path.string(), 1000, 10, 30);
    const size_t a = w.add("gpu.s", "busy", 1, 0);
    const size_t b = w.add("gpu.fifos", "f", 3, 0);
    w.begin();
    w.set(a, 1);  // cycle 0
    w.end_cycle(0);
    w.set(b, 5);  // cycle 12: the values at 10 are a = 1, b = 0
    w.set(a, 0);
    w.set(a, 1);  // back within the cycle: no change
    w.end_cycle(12);
    w.set(b, 2);  // cycle 35, outside
    w.end_cycle(35);
    w.finish(40);
    EXPECT_EQ(w.changes(), 3u);  // two in $dumpvars, one at 12
  }
  EXPECT_EQ(file_bytes(path),
            "$version gpusim $end\n$comment simulated time; one clock cycle is 1000 ps, 1 time "
            "unit $end\n$timescale 1 ns $end\n$scope module gpu $end\n$scope module s $end\n"
            "$var wire 1 ! busy $end\n$upscope $end\n$scope module fifos $end\n"
            "$var wire 3 \" f [2:0] $end\n$upscope $end\n$upscope $end\n$enddefinitions $end\n"
            "#10\n$dumpvars\n1!\nb0 \"\n$end\n#12\nb101 \"\n#30\n");
  fs::remove(path);
}

TEST(VcdWriter, TimescaleIsTheCoarsestUnitDividingThePeriod) {
  const auto ts = [](uint64_t ps) {
    const VcdWriter::Timescale t = VcdWriter::timescale_for(ps);
    return t.text + " x" + std::to_string(t.per_cycle);
  };
  EXPECT_EQ(ts(1000), "1 ns x1");     // 1000 MHz
  EXPECT_EQ(ts(10000), "10 ns x1");   // 100 MHz
  EXPECT_EQ(ts(100), "100 ps x1");    // 10 GHz
  EXPECT_EQ(ts(1000000), "1 us x1");  // 1 MHz
  EXPECT_EQ(ts(2500), "100 ps x25");  // 400 MHz
  EXPECT_EQ(ts(3333), "1 ps x3333");  // 300 MHz (SystemC's 1 ps resolution)
  EXPECT_EQ(ts(20000), "10 ns x2");   // 50 MHz
  EXPECT_EQ(ts(7000000), "1 us x7");
}

TEST(VcdWriter, TimesAreCyclesTimesThePeriod) {
  const fs::path path = fs::path(::testing::TempDir()) / ("vcd300_" + std::to_string(getpid()));
  {
    VcdWriter w(path.string(), 3333, 0, 100);
    const size_t a = w.add("gpu.front_end.s", "s_busy", 1, 0);
    w.begin();
    w.end_cycle(0);
    w.set(a, 1);
    w.end_cycle(7);
    w.finish(9);
  }
  EXPECT_EQ(
      file_bytes(path),
      "$version gpusim $end\n$comment simulated time; one clock cycle is 3333 ps, 3333 time "
      "units $end\n$timescale 1 ps $end\n$scope module gpu $end\n$scope module front_end $end\n"
      "$scope module s $end\n$var wire 1 ! s_busy $end\n$upscope $end\n$upscope $end\n"
      "$upscope $end\n$enddefinitions $end\n#0\n$dumpvars\n0!\n$end\n#23331\n1!\n#29997\n");
  fs::remove(path);
}

TEST(TimelineWriter, MicrosecondsAreNanosecondsRoundedOnce) {
  EXPECT_EQ(TimelineWriter::microseconds(12345, 1000), "12.345");
  EXPECT_EQ(TimelineWriter::microseconds(2000, 1000), "2.000");
  EXPECT_EQ(TimelineWriter::microseconds(0, 1000), "0.000");
  EXPECT_EQ(TimelineWriter::microseconds(1, 2500), "0.003");  // 2.5 ns: halves up
  EXPECT_EQ(TimelineWriter::microseconds(3, 2500), "0.008");  // 7.5 ns
  // 300 MHz (3333 ps): 96455 cycles = 321.484515 us -> 321.485.
  EXPECT_EQ(TimelineWriter::microseconds(96455, 3333), "321.485");
  EXPECT_EQ(TimelineWriter::nanoseconds(96455, 3333), 321485u);
}

TEST(TimelineWriter, DurationIsTheDifferenceOfTheRoundedEnds) {
  const fs::path path = fs::path(::testing::TempDir()) / ("tl_" + std::to_string(getpid()));
  {
    TimelineWriter w(path.string(), 3333, "{}");
    // Cycles 1..2: 3.333 ns to 6.666 ns -> ts 0.003, end 0.007, dur 0.004
    // (rounding 3.333 ns on its own would give 0.003 and an end at 0.006).
    w.complete(0, 0, "a", "work", 1, 2, "");
    w.complete(0, 0, "b", "work", 2, 5, "");
    w.counter(0, 0, "fifo f", 5, 3);
    w.finish();
  }
  EXPECT_EQ(file_bytes(path),
            "{\"displayTimeUnit\": \"ns\",\n\"otherData\": {},\n\"traceEvents\": [\n"
            "{\"ph\": \"X\", \"name\": \"a\", \"cat\": \"work\", \"ts\": 0.003, \"dur\": 0.004, "
            "\"pid\": 0, \"tid\": 0, \"args\": {\"cycle_in\": 1, \"cycle_out\": 2}},\n"
            "{\"ph\": \"X\", \"name\": \"b\", \"cat\": \"work\", \"ts\": 0.007, \"dur\": 0.010, "
            "\"pid\": 0, \"tid\": 0, \"args\": {\"cycle_in\": 2, \"cycle_out\": 5}},\n"
            "{\"ph\": \"C\", \"name\": \"fifo f\", \"ts\": 0.017, \"pid\": 0, \"tid\": 0, "
            "\"args\": {\"occupancy\": 3}}\n]}\n");
  fs::remove(path);
}

}  // namespace
}  // namespace gpusim
