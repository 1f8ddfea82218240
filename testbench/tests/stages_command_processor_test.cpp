// The command processor (stages/command_processor.h) alone: a host writes a
// frame's command stream into its input FIFO and a sink reads what it hands
// to vertex fetch (testbench/tests/stage_host.h). Checked: every command
// forwarded unchanged and in the driver's order, so the clears and the end of
// frame stay where they were between the draws; its cost, ii per command of
// every kind, each readable latency cycles after its ii; its counters; and
// the model error of a draw id beyond the frame's draw registers. One
// sc_start per TEST (ctest runs each in its own process).
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "hw/draw_state.h"
#include "hw/fifo.h"
#include "hw/gpu_config.h"
#include "hw/packets.h"
#include "stages/command_processor.h"
#include "testbench/tests/stage_host.h"

namespace gpusim {
namespace {

using namespace test;

Command draw(uint32_t id) {
  return Command{PacketKind::work, id};
}
Command token(PacketKind k) {
  return Command{k, 0};
}

// The command processor between its FIFOs, its output FIFO `depth` deep and
// read from cycle `from` on.
struct Bench {
  Fifo<Command> in, out;
  CommandProcessor cp;
  Sink<Command> sink;
  Bench(const GpuConfig& c, const FrameState& f, std::vector<Command> script, unsigned depth = 16,
        uint64_t from = 0)
      : in("in", 16), out("out", depth), cp("command_processor", c, f), sink(out, c.cycle(), from) {
    cp.in(in);
    cp.out(out);
    feed(in, std::move(script));
  }
};

// A frame of three draws: the frame clear first, a clear from the draw list
// between draws, a draw repeated, the end of frame last.
const std::vector<Command> kScript = {token(PacketKind::clear),
                                      draw(0),
                                      draw(1),
                                      token(PacketKind::clear),
                                      draw(2),
                                      draw(0),
                                      draw(2),
                                      token(PacketKind::end_of_frame)};

TEST(CommandProcessorStage, ForwardsEveryCommandInOrderAtItsCost) {
  GpuConfig config = GpuConfig::baseline();
  const unsigned ii = 3, latency = 4;  // not the defaults (1, 2): both show
  config.stages["command_processor"] = {ii, latency};
  FrameState frame;
  frame.draws.resize(3);
  frame.clears.resize(1);
  Bench b(config, frame, kScript);
  sc_core::sc_start();

  // Forwarded as they came: the same kinds, draw ids and order.
  EXPECT_EQ(b.sink.items, kScript);
  // Every command is read as soon as the one before has spent its ii (all
  // are waiting at 0): command n is read at n * ii, written at (n + 1) * ii
  // and readable, so read by the sink, latency cycles later.
  std::vector<uint64_t> want;
  for (uint64_t n = 0; n < kScript.size(); ++n) want.push_back((n + 1) * ii + latency);
  EXPECT_EQ(b.sink.cycles, want);
  expect_counters(b.cp.stats(), {{"draws", 5},
                                 {"clears", 2},
                                 {"frames", 1},
                                 {"tokens_in", 8},
                                 {"tokens_out", 8},
                                 {"busy_cycles", 8 * ii}});
}

// A full output FIFO holds the command processor: with one slot and a sink
// that starts reading at cycle 40, the first command waits in the slot
// (readable at 1 + 2 = 3, read at 40); the second, written at 2, finds the
// slot full until 40 and enters the FIFO then, its latency starting there:
// readable at 42. Only then is the third read (at 40: the stage was blocked
// in its write), written at 41, blocked until the slot frees at 42 and
// readable at 44; and so on, every two cycles.
TEST(CommandProcessorStage, WaitsForItsOutputFifo) {
  const GpuConfig config = GpuConfig::baseline();  // ii 1, latency 2
  FrameState frame;
  frame.draws.resize(3);
  Bench b(config, frame,
          {token(PacketKind::clear), draw(0), draw(1), draw(2), token(PacketKind::end_of_frame)}, 1,
          40);
  sc_core::sc_start();

  EXPECT_EQ(b.sink.cycles, (std::vector<uint64_t>{40, 42, 44, 46, 48}));
  // Busy only for its ii per command: the wait for the slot is a stall.
  expect_counters(b.cp.stats(), {{"busy_cycles", 5}, {"tokens_out", 5}});
}

// A draw id without a draw register is a driver bug the stage stops at.
TEST(CommandProcessorStage, RejectsADrawBeyondTheFrame) {
  const GpuConfig config = GpuConfig::baseline();  // the stage keeps a reference
  FrameState frame;
  frame.draws.resize(2);
  Bench b(config, frame, {draw(0), draw(1), draw(2)});
  std::string error = "none";
  try {
    sc_core::sc_start();
  } catch (const sc_core::sc_report& r) {
    error = r.what();
  }
  EXPECT_NE(error.find("draw 2 does not exist (2 draws)"), std::string::npos) << error;
}

}  // namespace
}  // namespace gpusim
