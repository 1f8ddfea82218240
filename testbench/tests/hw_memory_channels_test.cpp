// Memory channels (hw/memory.h, "Channels"): the interleaving of addresses,
// a request split at interleave boundaries, channels working in parallel,
// each with its own round-robin pointer, and the per-channel statistics.
// Clock 1 ns, latency 20 cycles, 32 bytes per cycle per channel, interleave
// 256 bytes: a piece of len bytes on an idle channel completes after
// ceil(len / 32) + 20 cycles. One sc_start per TEST (ctest: one process each).
#include <gtest/gtest.h>

#include <functional>
#include <vector>

#include "hw/memory.h"
#include "testbench/tests/memory_client.h"

namespace gpusim {
namespace {

using sc_core::sc_time;

constexpr uint64_t kSize = 1 << 16;
constexpr unsigned kLatency = 20, kWidth = 32, kInterleave = 256;

// Issues `n` 256-byte reads at `first`, `first` + stride, ... at time 0 and
// waits for the group: returns its completion, in cycles.
double read_group(Client& c, uint64_t first, uint64_t stride, unsigned n) {
  std::vector<uint8_t> buf(256);
  for (unsigned i = 0; i < n; ++i) c.port.read(first + i * stride, buf.data(), buf.size());
  const double done = in_cycles(c.port.wait_round().last());
  sc_core::wait(done * kCycle - sc_core::sc_time_stamp());
  return done;
}

TEST(MemoryChannels, AddressesInterleaveAcrossChannels) {
  Memory mem("mem", kSize, kLatency, kWidth, kCycle, 4, kInterleave);
  EXPECT_EQ(mem.num_channels(), 4u);
  EXPECT_EQ(mem.channel_of(0), 0u);
  EXPECT_EQ(mem.channel_of(255), 0u);
  EXPECT_EQ(mem.channel_of(256), 1u);
  EXPECT_EQ(mem.channel_of(3 * 256 + 17), 3u);
  EXPECT_EQ(mem.channel_of(4 * 256), 0u);
  Memory one("one", kSize, kLatency, kWidth, kCycle);
  EXPECT_EQ(one.num_channels(), 1u);
  EXPECT_EQ(one.channel_of(12345), 0u);
}

// Two clients, 8 reads of 256 B each (8 bus cycles a read), all arriving at
// 0. Client a's addresses are the even interleave blocks, b's the odd ones.
// One channel: a's burst is granted whole first, [0, 64), then b's, [64,
// 128): a completes at 64 + 20, b at 128 + 20.
TEST(MemoryChannels, OneChannelSerialisesTwoClients) {
  Memory mem("mem", kSize, kLatency, kWidth, kCycle, 1, kInterleave);
  double a_done = 0, b_done = 0;
  Client a("a", mem, [&](Client& c) { a_done = read_group(c, 0, 512, 8); });
  Client b("b", mem, [&](Client& c) { b_done = read_group(c, 256, 512, 8); });
  sc_core::sc_start();
  EXPECT_EQ(a_done, 64 + kLatency);
  EXPECT_EQ(b_done, 128 + kLatency);
  EXPECT_EQ(mem.busy_cycles(), 128u);
  EXPECT_EQ(in_cycles(mem.bus_free()), 128);
}

// The same traffic on two channels: even blocks are channel 0, odd ones
// channel 1, so each client has a bus of its own and both complete at 64 +
// 20: the bus time of the frame halves (128 -> 64 cycles).
TEST(MemoryChannels, TwoChannelsServeTwoClientsInParallel) {
  Memory mem("mem", kSize, kLatency, kWidth, kCycle, 2, kInterleave);
  double a_done = 0, b_done = 0;
  Client a("a", mem, [&](Client& c) { a_done = read_group(c, 0, 512, 8); });
  Client b("b", mem, [&](Client& c) { b_done = read_group(c, 256, 512, 8); });
  sc_core::sc_start();
  EXPECT_EQ(a_done, 64 + kLatency);
  EXPECT_EQ(b_done, 64 + kLatency);
  EXPECT_EQ(in_cycles(mem.bus_free()), 64);
  const nlohmann::json j = mem.stat_group().to_json();
  ASSERT_EQ(j["channels"].size(), 2u);
  for (unsigned ch = 0; ch < 2; ++ch) {
    const nlohmann::json& c = j["channels"][ch];
    EXPECT_EQ(c["channel"], ch);
    EXPECT_EQ(c["requests"], 8u);
    EXPECT_EQ(c["reads"], 8u);
    EXPECT_EQ(c["bytes_read"], 8u * 256);
    EXPECT_EQ(c["bytes_written"], 0u);
    EXPECT_EQ(c["busy_cycles"], 64u);
    // The k-th read of a burst waits 8k cycles: 8 * (0 + 1 + ... + 7).
    EXPECT_EQ(c["queued_cycles"], 8.0 * 28);
    EXPECT_EQ(c["queued_cycles_mean"], 8.0 * 28 / 8);
    EXPECT_EQ(c["queued_cycles_max"], 56.0);
    // The run ends at 84 (the clients wait for their completion).
    EXPECT_DOUBLE_EQ(c["utilization"].get<double>(), 64.0 / 84);
  }
  EXPECT_EQ(j["busy_cycles"], 128u);
  EXPECT_DOUBLE_EQ(j["utilization"].get<double>(), 128.0 / (2 * 84));
  EXPECT_EQ(j["interleave_bytes"], kInterleave);
}

// A read of 128 B at 192 crosses the boundary at 256: 64 B on channel 0 and
// 64 B on channel 1, 2 cycles each in parallel: 2 + 20 (one channel: 24).
// Then a 1000-byte read at 100 on 4 channels: pieces [100, 256) 156 B on
// channel 0 (5 cycles), [256, 512) ch 1, [512, 768) ch 2, [768, 1024) ch 3
// (8 cycles each) and [1024, 1100) 76 B on channel 0 again (3 cycles, behind
// the first piece: [5, 8), waiting 5): complete at max(5, 8, 8, 8, 8) + 20.
TEST(MemoryChannels, RequestIsSplitAtInterleaveBoundaries) {
  Memory mem("mem", kSize, kLatency, kWidth, kCycle, 4, kInterleave);
  double first = 0, second = 0;
  Client a("a", mem, [&](Client& c) {
    std::vector<uint8_t> buf(1000);
    c.port.read(192, buf.data(), 128);
    first = in_cycles(c.port.wait_round().last());
    sc_core::wait(first * kCycle);
    c.port.write(100 + 4096, buf.data(), 1000);
    second = in_cycles(c.port.wait_round().last() - sc_core::sc_time_stamp());
    sc_core::wait(second * kCycle);
  });
  sc_core::sc_start();
  EXPECT_EQ(first, 2 + kLatency);
  EXPECT_EQ(second, 8 + kLatency);
  const nlohmann::json j = mem.stat_group().to_json();
  const nlohmann::json& ch = j["channels"];
  // 4096 is a multiple of 4 blocks: the write's pieces fall as listed above.
  EXPECT_EQ(ch[0]["requests"], 1u + 2u);
  EXPECT_EQ(ch[0]["bytes_read"], 64u);
  EXPECT_EQ(ch[0]["bytes_written"], 156u + 76u);
  EXPECT_EQ(ch[0]["busy_cycles"], 2u + 5u + 3u);
  EXPECT_EQ(ch[0]["queued_cycles_max"], 5.0);
  EXPECT_EQ(ch[1]["bytes_read"], 64u);
  EXPECT_EQ(ch[1]["bytes_written"], 256u);
  EXPECT_EQ(ch[1]["busy_cycles"], 2u + 8u);
  for (unsigned c : {2u, 3u}) {
    EXPECT_EQ(ch[c]["requests"], 1u);
    EXPECT_EQ(ch[c]["bytes_written"], 256u);
    EXPECT_EQ(ch[c]["busy_cycles"], 8u);
    EXPECT_EQ(ch[c]["queued_cycles"], 0.0);
  }
  // The client counts its two issues; its bus cycles and waits add up over
  // the pieces.
  const MemoryClientStats s = mem.client_stats(0);
  EXPECT_EQ(s.requests, 2u);
  EXPECT_EQ(s.bytes_read, 128u);
  EXPECT_EQ(s.bytes_written, 1000u);
  EXPECT_EQ(s.busy_cycles, 2u + 2u + 5u + 8u + 8u + 8u + 3u);
  EXPECT_EQ(in_cycles(s.queued), 5);
  EXPECT_EQ(in_cycles(s.queued_max), 5);
}

// Each channel has its own round-robin pointer. At 0, a alone reads on
// channel 0 (its pointer moves past a, to b). At 10, a and b both read 64 B
// on channel 1, whose pointer has not moved: a first, [10, 12) -> 32, then
// b, [12, 14) -> 34. (With one pointer for all channels b would go first.)
TEST(MemoryChannels, EachChannelKeepsItsOwnRoundRobinPointer) {
  Memory mem("mem", kSize, kLatency, kWidth, kCycle, 2, kInterleave);
  double a_done = 0, b_done = 0;
  Client a("a", mem, [&](Client& c) {
    std::vector<uint8_t> buf(64);
    c.port.read(0, buf.data(), 64);
    c.port.wait_round();
    sc_core::wait(10 * kCycle);
    c.port.read(256, buf.data(), 64);
    a_done = in_cycles(c.port.wait_round().last());
  });
  Client b("b", mem, [&](Client& c) {
    std::vector<uint8_t> buf(64);
    sc_core::wait(10 * kCycle);
    c.port.read(768, buf.data(), 64);
    b_done = in_cycles(c.port.wait_round().last());
  });
  sc_core::sc_start();
  EXPECT_EQ(a_done, 10 + 2 + kLatency);
  EXPECT_EQ(b_done, 10 + 4 + kLatency);
}

}  // namespace
}  // namespace gpusim
