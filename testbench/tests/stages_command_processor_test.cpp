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

  Fifo<Command> in("in", 16), out("out", 16);
  CommandProcessor cp("command_processor", config, frame);
  cp.in(in);
  cp.out(out);
  feed(in, kScript);
  Sink<Command> sink(out, config.cycle());
  sc_core::sc_start();

  // Forwarded as they came: the same kinds, draw ids and order.
  ASSERT_EQ(sink.items.size(), kScript.size());
  for (size_t n = 0; n < kScript.size(); ++n) {
    EXPECT_EQ(sink.items[n], kScript[n]) << "command " << n;
  }
  // Every command is read as soon as the one before has spent its ii (all
  // are waiting at 0): command n is read at n * ii, written at (n + 1) * ii
  // and readable, so read by the sink, latency cycles later.
  std::vector<uint64_t> want;
  for (uint64_t n = 0; n < kScript.size(); ++n) want.push_back((n + 1) * ii + latency);
  EXPECT_EQ(sink.cycles, want);

  const StatGroup& s = cp.stats();
  EXPECT_EQ(counter(s, "draws"), 5u);
  EXPECT_EQ(counter(s, "clears"), 2u);
  EXPECT_EQ(counter(s, "frames"), 1u);
  EXPECT_EQ(counter(s, "tokens_in"), 8u);
  EXPECT_EQ(counter(s, "tokens_out"), 8u);
  EXPECT_EQ(counter(s, "busy_cycles"), 8u * ii);
}

// A full output FIFO holds the command processor: with one slot and a sink
// that starts reading at cycle 40, the first command waits in the slot
// (readable at 1 + 2 = 3, read at 40); the second, written at 2, finds the
// slot full until 40 and enters the FIFO then, its latency starting there:
// readable at 42. Only then is the third read (at 40: the stage was blocked
// in its write), written at 41, blocked until the slot frees at 42 and
// readable at 44; and so on, every two cycles.
TEST(CommandProcessorStage, WaitsForItsOutputFifo) {
  GpuConfig config = GpuConfig::baseline();  // ii 1, latency 2
  FrameState frame;
  frame.draws.resize(3);
  Fifo<Command> in("in", 16), out("out", 1);
  CommandProcessor cp("command_processor", config, frame);
  cp.in(in);
  cp.out(out);
  feed(in, {token(PacketKind::clear), draw(0), draw(1), draw(2), token(PacketKind::end_of_frame)});
  Sink<Command> sink(out, config.cycle(), 40);
  sc_core::sc_start();

  EXPECT_EQ(sink.cycles, (std::vector<uint64_t>{40, 42, 44, 46, 48}));
  // Busy only for its ii per command: the wait for the slot is a stall.
  EXPECT_EQ(counter(cp.stats(), "busy_cycles"), 5u);
  EXPECT_EQ(counter(cp.stats(), "tokens_out"), 5u);
}

// A draw id without a draw register is a driver bug the stage stops at.
TEST(CommandProcessorStage, RejectsADrawBeyondTheFrame) {
  const GpuConfig config = GpuConfig::baseline();
  FrameState frame;
  frame.draws.resize(2);
  Fifo<Command> in("in", 4), out("out", 4);
  CommandProcessor cp("command_processor", config, frame);
  cp.in(in);
  cp.out(out);
  feed(in, {draw(0), draw(1), draw(2)});
  Sink<Command> sink(out, config.cycle());
  try {
    sc_core::sc_start();
    ADD_FAILURE() << "no error for draw 2";
  } catch (const sc_core::sc_report& r) {
    EXPECT_NE(std::string(r.what()).find("draw 2 does not exist (2 draws)"), std::string::npos)
        << r.what();
  }
}

}  // namespace
}  // namespace gpusim
