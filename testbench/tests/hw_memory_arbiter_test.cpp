// The memory's arbiter (hw/memory.h): grants in the documented order, never
// in the order the kernel happens to run the requesting processes. Clock
// 1 ns, latency 20 cycles, 32 bytes per cycle, so a request granted at S of
// len bytes completes at S + ceil(len / 32) + 20; every expected time below
// is derived by hand from that and the grant order.
#define SC_INCLUDE_DYNAMIC_PROCESSES
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "hw/memory.h"
#include "hw/simulation_context.h"

namespace gpusim {
namespace {

using sc_core::sc_time;

const sc_time kCycle(1, sc_core::SC_NS);
constexpr uint64_t kSize = 4096;
double in_cycles(sc_time t) {
  return t / kCycle;
}

// One request of a script, and where its completion is recorded.
struct Request {
  uint64_t len;
  uint64_t offset;  // cycles after the round's time
  bool write = false;
};
// A client's requests at one time (cycles), issued together in one delta.
struct Round {
  uint64_t at;
  std::vector<Request> requests;
};
using Script = std::vector<Round>;

// Per client, per round, per request: completion in cycles.
using Completions = std::vector<std::vector<std::vector<double>>>;

struct Outcome {
  Completions done;
  std::vector<unsigned> issue_order;  // client of each round as the kernel ran them
  std::vector<MemoryClientStats> stats;
};

// Builds a memory with one client per script (numbered in script order:
// the hardware's wiring), spawns one thread per client in `creation_order`,
// and runs. Each thread issues a round's requests straight through
// Memory::issue with a sink per request (so every request's completion is
// seen, not only a group's last), waits one delta and records them.
Outcome run_model(const std::vector<Script>& scripts, const std::vector<unsigned>& creation_order) {
  fresh_simulation_context();
  auto memory = std::make_unique<Memory>("memory", kSize, 20, 32, kCycle);
  Outcome out;
  out.done.resize(scripts.size());
  for (unsigned c = 0; c < scripts.size(); ++c) {
    EXPECT_EQ(memory->add_client("client_" + std::to_string(c)), c);
    out.done[c].resize(scripts[c].size());
  }
  std::vector<uint8_t> buffer(kSize);
  for (const unsigned c : creation_order) {
    sc_core::sc_spawn(
        [&, c] {
          Memory& m = *memory;
          for (size_t r = 0; r < scripts[c].size(); ++r) {
            const Round& round = scripts[c][r];
            const sc_time at = kCycle * static_cast<double>(round.at);
            if (at > sc_core::sc_time_stamp()) sc_core::wait(at - sc_core::sc_time_stamp());
            std::vector<MemoryArbiter::Sink> sinks(round.requests.size());
            for (size_t i = 0; i < round.requests.size(); ++i) {
              const Request& q = round.requests[i];
              ASSERT_TRUE(m.issue(c, q.write, 64 * c, buffer.data(), q.len,
                                  kCycle * static_cast<double>(q.offset), sinks[i]));
            }
            out.issue_order.push_back(c);
            sc_core::wait(sc_core::SC_ZERO_TIME);
            for (const MemoryArbiter::Sink& s : sinks) {
              EXPECT_FALSE(s.pending);
              out.done[c][r].push_back(in_cycles(s.done.last()));
            }
          }
        },
        ("client_" + std::to_string(c)).c_str());
  }
  sc_core::sc_start();
  for (unsigned c = 0; c < scripts.size(); ++c) out.stats.push_back(memory->client_stats(c));
  return out;
}

// Three clients issue in the same delta at t = 0; the pointer starts at
// client 0. Arrivals: 0 for a (read 64 B, then write 32 B), b (read 96 B)
// and c (read 32 B); 8 for c's second read (32 B); 1 for b's write (64 B).
// Grant order: arrival 0 from the pointer: a, a, b, c (pointer -> past c:
// 0); arrival 1: b (pointer -> c); arrival 8: c.
//   a read 64   S 0  D 2   -> 22
//   a write 32  S 2  D 3   -> 23
//   b read 96   S 3  D 6   -> 26
//   c read 32   S 6  D 7   -> 27
//   b write 64  S 7  D 9   -> 29 (arrived 1: queued 6)
//   c read 32   S 9  D 10  -> 30 (arrived 8: queued 1)
// Call-order reservation gave a different answer for each order in which
// the kernel ran the three threads.
const std::vector<Script> kThreeClients = {
    {{0, {{64, 0}, {32, 0, true}}}},
    {{0, {{96, 0}, {64, 1, true}}}},
    {{0, {{32, 0}, {32, 8}}}},
};

TEST(MemoryArbiter, GrantsDoNotDependOnProcessOrder) {
  const Outcome forward = run_model(kThreeClients, {0, 1, 2});
  const Outcome backward = run_model(kThreeClients, {2, 1, 0});
  const Outcome middle = run_model(kThreeClients, {1, 2, 0});
  // The kernel did run the clients in different orders (else this test
  // would prove nothing)...
  EXPECT_NE(forward.issue_order, backward.issue_order);
  // ...and the grants are the same, and the ones derived by hand.
  const Completions expected = {{{22, 23}}, {{26, 29}}, {{27, 30}}};
  EXPECT_EQ(forward.done, expected);
  EXPECT_EQ(backward.done, expected);
  EXPECT_EQ(middle.done, expected);
  // Queued S - A: a 0 + 2, b 3 + 6, c 6 + 1.
  for (const Outcome* o : {&forward, &backward, &middle}) {
    EXPECT_EQ(in_cycles(o->stats[0].queued), 2);
    EXPECT_EQ(in_cycles(o->stats[1].queued), 9);
    EXPECT_EQ(in_cycles(o->stats[2].queued), 7);
    EXPECT_EQ(o->stats[1].busy_cycles, 3u + 2u);
  }
}

// Round-robin: the pointer moves past the last client granted, so a client
// left out of a round does not lose its turn. 32-byte reads (1 bus cycle),
// one per client per round, all arriving at the round's time T on an idle
// bus: the k-th granted completes at T + k + 20.
//   T=0    a          pointer 0: a                -> pointer 1
//   T=100  a, b, c    from b: b, c, a             -> pointer 1 (past a)
//   T=200  a, c       from b: c, then a           -> pointer 1
//   T=300  b, c       from b: b, c                -> pointer 0
//   T=400  a, b, c    from a: a, b, c             -> pointer 0
TEST(MemoryArbiter, RoundRobinRotatesPastTheLastClientGranted) {
  const Request r{32, 0};
  const std::vector<Script> scripts = {
      {{0, {r}}, {100, {r}}, {200, {r}}, {400, {r}}},
      {{100, {r}}, {300, {r}}, {400, {r}}},
      {{100, {r}}, {200, {r}}, {300, {r}}, {400, {r}}},
  };
  const Completions expected = {
      {{21}, {123}, {222}, {421}},
      {{121}, {321}, {422}},
      {{122}, {221}, {322}, {423}},
  };
  EXPECT_EQ(run_model(scripts, {0, 1, 2}).done, expected);
  EXPECT_EQ(run_model(scripts, {2, 0, 1}).done, expected);
}

// Arrival time comes before priority, and there is no backfilling across
// rounds.
//   T=0: a (priority) issues 64 B arriving at 3; b issues 32 B arriving at 0.
//        b first: S 0 D 1 -> 21; then a: S 3 D 5 -> 25 (bus idle 1..3).
//   T=1: a issues 64 B arriving at 1 + 30 = 31: S 31 D 33 -> 53.
//   T=2: b issues 32 B arriving at 2: the bus is reserved up to 33 from the
//        earlier round, so S 33 D 34 -> 54 (queued 31), although the bus
//        idles from 5 to 31.
TEST(MemoryArbiter, EarlierArrivalFirstAndNoBackfilling) {
  const std::vector<Script> scripts = {
      {{0, {{64, 3}}}, {1, {{64, 30}}}},
      {{0, {{32, 0}}}, {2, {{32, 0}}}},
  };
  const Outcome o = run_model(scripts, {0, 1});
  const Completions expected = {{{25}, {53}}, {{21}, {54}}};
  EXPECT_EQ(o.done, expected);
  EXPECT_EQ(in_cycles(o.stats[1].queued), 31);
  EXPECT_EQ(in_cycles(o.stats[0].queued), 0);
  EXPECT_EQ(run_model(scripts, {1, 0}).done, expected);
}

// A client's requests at one arrival keep their issue order, seen through
// MemoryPort's separate read and write completions; posted writes are
// collected by a later wait_round(); a wait_round() with nothing pending
// does not wait.
struct PortClient : sc_core::sc_module {
  MemoryPort port{"mem"};
  std::vector<double> reads, writes;  // completion of each group, cycles
  std::vector<bool> waited;           // whether that wait_round() took a delta
  SC_HAS_PROCESS(PortClient);
  PortClient(sc_core::sc_module_name name, Memory& memory) : sc_core::sc_module(name) {
    port.bind(memory);
    SC_THREAD(run);
  }
  void group() {
    const sc_core::sc_time now = sc_core::sc_time_stamp();
    const uint64_t delta = sc_core::sc_delta_count();
    const MemoryCompletion c = port.wait_round();
    EXPECT_EQ(sc_core::sc_time_stamp(), now) << "a round takes no simulated time";
    waited.push_back(sc_core::sc_delta_count() != delta);
    reads.push_back(in_cycles(c.reads));
    writes.push_back(in_cycles(c.writes));
  }
  void run() {
    std::array<uint8_t, 64> buf{};
    // t=0: write 64 B then read 32 B: write S 0 D 2 -> 22, read S 2 D 3 -> 23.
    port.write(0, buf.data(), 64);
    port.read(64, buf.data(), 32);
    group();
    // t=0: read 32 B then write 64 B: read S 3 D 4 -> 24, write S 4 D 6 -> 26.
    port.read(64, buf.data(), 32);
    port.write(0, buf.data(), 64);
    group();
    // t=0: a posted write of 32 B (S 6 D 7 -> 27), not waited for; at t=10 a
    // read of 32 B: S 10 D 11 -> 31; the group returns the posted write too.
    port.write(0, buf.data(), 32);
    sc_core::wait(10 * kCycle);
    port.read(64, buf.data(), 32);
    group();
    // Nothing issued: no wait, zero times.
    group();
  }
};

TEST(MemoryArbiter, PortKeepsIssueOrderAndCollectsPostedWrites) {
  Memory memory("memory", kSize, 20, 32, kCycle);
  PortClient client("stage", memory);
  sc_core::sc_start();
  EXPECT_EQ(client.writes, (std::vector<double>{22, 26, 27, 0}));
  EXPECT_EQ(client.reads, (std::vector<double>{23, 24, 31, 0}));
  EXPECT_EQ(client.waited, (std::vector<bool>{true, true, true, false}));
  EXPECT_EQ(client.port.client_name(), "stage");
  EXPECT_EQ(memory.client_name(0), "stage");
  EXPECT_EQ(memory.busy_cycles(), 2u + 1 + 1 + 2 + 1 + 1);
}

}  // namespace
}  // namespace gpusim
