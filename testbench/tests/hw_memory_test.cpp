// Memory data, timing and statistics. Clock 1 ns, latency 20 cycles, 32 bytes
// per cycle: a request of len bytes on an idle bus completes after
// ceil(len / 32) + 20 cycles. One sc_start per TEST (ctest: one process each).
// The arbitration order itself: hw_memory_arbiter_test.cpp.
#include <gtest/gtest.h>
#include <tlm_utils/simple_initiator_socket.h>

#include <array>
#include <cstring>
#include <functional>
#include <numeric>
#include <vector>

#include "hw/memory.h"
#include "testbench/tests/memory_client.h"

namespace gpusim {
namespace {

using sc_core::sc_time;

constexpr uint64_t kSize = 4096;

// The delay from now until the port's group completes, in cycles (what the
// old call-order interface returned per request).
double group_delay(MemoryPort& port) {
  return in_cycles(port.wait_round().last() - sc_core::sc_time_stamp());
}

std::vector<uint8_t> pattern(size_t n, uint8_t seed) {
  std::vector<uint8_t> v(n);
  for (size_t i = 0; i < n; ++i) v[i] = static_cast<uint8_t>(seed + 7 * i);
  return v;
}

TEST(Memory, WrittenDataReadsBackWithSingleRequestTiming) {
  Memory mem("mem", kSize, 20, 32, kCycle);
  const auto data = pattern(64, 3);
  const auto backdoor = pattern(16, 100);
  mem.debug_write(1000, backdoor.data(), backdoor.size());
  std::vector<double> delays;
  std::vector<uint8_t> back(64), back_door(16), odd(33);
  Client a("a", mem, [&](Client& c) {
    const auto wait_for = [&] {
      delays.push_back(group_delay(c.port));
      sc_core::wait(delays.back() * kCycle);
    };
    c.port.write(128, data.data(), data.size());
    wait_for();
    c.port.read(128, back.data(), back.size());
    wait_for();
    c.port.read(1000, back_door.data(), back_door.size());  // 16 bytes: 1 cycle
    wait_for();
    c.port.read(2000, odd.data(), 33);  // 2 cycles
    delays.push_back(group_delay(c.port));
  });
  sc_core::sc_start();

  EXPECT_EQ(back, data);
  EXPECT_EQ(back_door, backdoor);
  EXPECT_EQ(std::memcmp(mem.data(128, 64), data.data(), 64), 0);
  // Writes and reads alike: bus cycles + 20.
  EXPECT_EQ(delays, (std::vector<double>{22, 22, 21, 22}));
  // The last request was issued at 22 + 22 + 21 = 65 and freed the bus at 67.
  EXPECT_EQ(in_cycles(mem.bus_free()), 67);
  EXPECT_EQ(mem.busy_cycles(), 7u);
}

// One client issues a group of requests, one round: granted by arrival,
// then in issue order.
//   64 B, arrives 0:             bus [0,2)   -> 2 + 20 = 22
//   64 B, arrives 0:             bus [2,4)   -> 24 (queued 2)
//   64 B, incoming offset 10:    bus [10,12) -> 32 (bus idle from 6 to 10)
//   64 B, incoming offset 1:     bus [4,6)   -> 26 (queued 3; granted third)
// Then, in a later round at the same time, 64 B arriving at 1 queues behind
// the slot reserved up to 12 (no backfilling): bus [12,14) -> 34, queued 11.
TEST(Memory, BackToBackRequestsQueueOnTheBus) {
  Memory mem("mem", kSize, 20, 32, kCycle);
  double first = 0, second = 0;
  Client a("a", mem, [&](Client& c) {
    std::array<uint8_t, 64> buf{};
    c.port.read(0, buf.data(), 64);
    c.port.read(64, buf.data(), 64);
    c.port.read(128, buf.data(), 64, 10 * kCycle);
    c.port.read(192, buf.data(), 64, kCycle);
    first = group_delay(c.port);
    c.port.read(0, buf.data(), 64, kCycle);
    second = group_delay(c.port);
  });
  sc_core::sc_start();
  EXPECT_EQ(first, 32);
  EXPECT_EQ(second, 34);
  EXPECT_EQ(in_cycles(mem.bus_free()), 14);
  EXPECT_EQ(mem.client_stats(0).busy_cycles, 10u);
  EXPECT_EQ(in_cycles(mem.client_stats(0).queued), 2 + 3 + 11);
  EXPECT_EQ(mem.stat_group().to_json()["clients"]["a"]["queued_cycles"], 16.0);
}

// Two clients at the same instant share the bus in round-robin order, the
// pointer starting at the first client bound (a). At t=0 both read 64 B: a
// gets 22, b 24, and the pointer moves past b (back to a). At t=30, b one
// delta after a, so in a later round: a reads 96 B -> bus [30,33) -> 23; b
// reads 32 B -> bus [33,34) -> 24.
TEST(Memory, ConcurrentClientsShareTheBandwidth) {
  Memory mem("mem", kSize, 20, 32, kCycle);
  double a0 = 0, b0 = 0, a1 = 0, b1 = 0;
  std::array<uint8_t, 96> buf_a{}, buf_b{};
  Client a("a", mem, [&](Client& c) {
    c.port.read(0, buf_a.data(), 64);
    a0 = group_delay(c.port);
    sc_core::wait(30 * kCycle);
    c.port.read(0, buf_a.data(), 96);
    a1 = group_delay(c.port);
  });
  Client b("b", mem, [&](Client& c) {
    c.port.read(512, buf_b.data(), 64);
    b0 = group_delay(c.port);
    sc_core::wait(30 * kCycle);
    sc_core::wait(sc_core::SC_ZERO_TIME);
    c.port.read(512, buf_b.data(), 32);
    b1 = group_delay(c.port);
  });
  sc_core::sc_start();
  EXPECT_EQ(a0, 22);
  EXPECT_EQ(b0, 24);
  EXPECT_EQ(a1, 23);
  EXPECT_EQ(b1, 24);
  EXPECT_EQ(mem.busy_cycles(), 2u + 2u + 3u + 1u);
}

// Mean and maximum wait per request (issue #16 item 8: the summed
// queued_cycles alone read as absurd). A 32-byte request takes one bus cycle.
// a and b each issue four 32 B reads at t=0, one round: a's burst goes first
// (the pointer starts at a), so a's requests start at 0, 1, 2, 3 and b's at
// 4, 5, 6, 7. a waits 0+1+2+3 = 6 (mean 1.5, max 3), b 4+5+6+7 = 22 (mean
// 5.5, max 7). A client without requests reports mean and max 0.
TEST(Memory, QueueingMeanAndMaximumPerRequest) {
  Memory mem("mem", kSize, 20, 32, kCycle);
  std::array<uint8_t, 32> buf_a{}, buf_b{};
  const auto four_reads = [](std::array<uint8_t, 32>& buf, uint64_t base) {
    return [&buf, base](Client& c) {
      for (uint64_t i = 0; i < 4; ++i) c.port.read(base + 32 * i, buf.data(), 32);
      group_delay(c.port);
    };
  };
  Client a("a", mem, four_reads(buf_a, 0));
  Client b("b", mem, four_reads(buf_b, 512));
  Client idle("idle", mem, [](Client&) {});
  sc_core::sc_start();
  const nlohmann::json clients = mem.stat_group().to_json()["clients"];
  EXPECT_EQ(clients["a"]["requests"], 4u);
  EXPECT_EQ(clients["a"]["queued_cycles"], 6.0);
  EXPECT_EQ(clients["a"]["queued_cycles_mean"], 1.5);
  EXPECT_EQ(clients["a"]["queued_cycles_max"], 3.0);
  EXPECT_EQ(clients["b"]["queued_cycles"], 22.0);
  EXPECT_EQ(clients["b"]["queued_cycles_mean"], 5.5);
  EXPECT_EQ(clients["b"]["queued_cycles_max"], 7.0);
  EXPECT_EQ(clients["idle"]["queued_cycles_mean"], 0.0);
  EXPECT_EQ(clients["idle"]["queued_cycles_max"], 0.0);
  EXPECT_EQ(in_cycles(mem.client_stats(1).queued_max), 7);
  // Every stats field is described.
  for (const auto& [key, value] : clients["a"].items())
    EXPECT_TRUE(mem.stat_group().descriptions()["clients"].contains(key)) << key;
}

// Per-client traffic: a writes 100 B (4 bus cycles) and reads 64 B (2);
// b reads 32 B (1) and writes 8 B (1).
TEST(Memory, PerClientStatistics) {
  Memory mem("mem", kSize, 20, 32, kCycle);
  std::vector<uint8_t> buf(100, 0x5a);
  Client a("a", mem, [&](Client& c) {
    c.port.write(0, buf.data(), 100);
    sc_core::wait(group_delay(c.port) * kCycle);
    c.port.read(0, buf.data(), 64);
    sc_core::wait(group_delay(c.port) * kCycle);
  });
  std::vector<uint8_t> buf_b(32);
  Client b("b", mem, [&](Client& c) {
    c.port.read(200, buf_b.data(), 32);
    sc_core::wait(group_delay(c.port) * kCycle);
    c.port.write(300, buf_b.data(), 8);
    sc_core::wait(group_delay(c.port) * kCycle);
  });
  sc_core::sc_start();

  ASSERT_EQ(mem.num_clients(), 2u);
  // Named after the stage owning the port.
  EXPECT_EQ(mem.client_name(0), "a");
  EXPECT_EQ(mem.client_name(1), "b");
  const MemoryClientStats& sa = mem.client_stats(0);
  EXPECT_EQ(sa.requests, 2u);
  EXPECT_EQ(sa.reads, 1u);
  EXPECT_EQ(sa.writes, 1u);
  EXPECT_EQ(sa.bytes_read, 64u);
  EXPECT_EQ(sa.bytes_written, 100u);
  EXPECT_EQ(sa.busy_cycles, 6u);
  const MemoryClientStats& sb = mem.client_stats(1);
  EXPECT_EQ(sb.bytes_read, 32u);
  EXPECT_EQ(sb.bytes_written, 8u);
  EXPECT_EQ(sb.busy_cycles, 2u);

  // Whatever the order of grants, the bus was busy 4 + 2 + 1 + 1 cycles.
  const nlohmann::json j = mem.stat_group().to_json();
  EXPECT_EQ(j["busy_cycles"], 8);
  EXPECT_EQ(j["size_bytes"], kSize);
  EXPECT_EQ(j["latency"], 20);
  EXPECT_EQ(j["bytes_per_cycle"], 32);
  EXPECT_EQ(j["clients"]["a"]["bytes_written"], 100);
  EXPECT_EQ(j["clients"]["b"]["bytes_read"], 32);
  EXPECT_EQ(j["clients"]["b"]["requests"], 2);
  EXPECT_DOUBLE_EQ(j["utilization"].get<double>(), 8.0 / in_cycles(sc_core::sc_time_stamp()));
}

// A raw TLM initiator bound straight to the socket, between two named ports:
// its b_transport goes through the arbiter like a port's request.
struct RawInitiator : sc_core::sc_module {
  tlm_utils::simple_initiator_socket<RawInitiator> socket{"socket"};
  explicit RawInitiator(sc_core::sc_module_name name) : sc_core::sc_module(name) {}
};

TEST(Memory, ErrorsAndDebugTransport) {
  Memory mem("mem", kSize, 20, 32, kCycle);
  Client named("named", mem, [](Client&) {});
  RawInitiator raw("raw");
  raw.socket.bind(mem.socket);
  std::vector<tlm::tlm_response_status> status;
  std::vector<double> delays;
  std::array<uint8_t, 8> buf{};
  std::array<uint8_t, 8> be{0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff};
  unsigned dbg_clipped = 0, dbg_outside = 0;
  Client driver("driver", mem, [&](Client&) {
    const auto access = [&](uint64_t addr, unsigned len, bool byte_enable, unsigned width) {
      tlm::tlm_generic_payload t;
      t.set_command(tlm::TLM_READ_COMMAND);
      t.set_address(addr);
      t.set_data_ptr(buf.data());
      t.set_data_length(len);
      t.set_streaming_width(width);
      if (byte_enable) {
        t.set_byte_enable_ptr(be.data());
        t.set_byte_enable_length(8);
      }
      t.set_response_status(tlm::TLM_INCOMPLETE_RESPONSE);
      sc_time d = 3 * kCycle;
      raw.socket->b_transport(t, d);
      status.push_back(t.get_response_status());
      delays.push_back(in_cycles(d));
    };
    access(kSize - 4, 8, false, 8);          // straddles the end
    access(uint64_t{1} << 40, 4, false, 4);  // far beyond
    access(kSize - 8, 8, false, 8);          // the last 8 bytes: fine
    access(0, 8, true, 8);                   // byte enables unsupported
    access(0, 8, false, 4);                  // streaming unsupported

    tlm::tlm_generic_payload t;
    t.set_command(tlm::TLM_READ_COMMAND);
    t.set_address(kSize - 4);
    t.set_data_ptr(buf.data());
    t.set_data_length(8);
    dbg_clipped = raw.socket->transport_dbg(t);
    t.set_address(kSize);
    dbg_outside = raw.socket->transport_dbg(t);
  });
  sc_core::sc_start();

  EXPECT_EQ(status, (std::vector<tlm::tlm_response_status>{
                        tlm::TLM_ADDRESS_ERROR_RESPONSE, tlm::TLM_ADDRESS_ERROR_RESPONSE,
                        tlm::TLM_OK_RESPONSE, tlm::TLM_BYTE_ENABLE_ERROR_RESPONSE,
                        tlm::TLM_BURST_ERROR_RESPONSE}));
  // Errors take no time; the good read arrives at 3 and takes 1 + 20 (its
  // round takes a delta, no simulated time, so the delay is from 0).
  EXPECT_EQ(delays, (std::vector<double>{3, 3, 24, 3, 3}));
  EXPECT_EQ(dbg_clipped, 4u);
  EXPECT_EQ(dbg_outside, 0u);

  // Clients are numbered in the order they were added: the two named ports,
  // then, at the end of elaboration, the raw socket bound directly.
  ASSERT_EQ(mem.num_clients(), 3u);
  EXPECT_EQ(mem.client_name(0), "named");
  EXPECT_EQ(mem.client_name(1), "driver");
  EXPECT_EQ(mem.client_name(2), "client2");
  EXPECT_EQ(mem.client_stats(2).errors, 4u);
  EXPECT_EQ(mem.client_stats(2).requests, 1u);
  EXPECT_EQ(mem.busy_cycles(), 1u);

  EXPECT_THROW(mem.data(kSize - 4, 8), std::out_of_range);
  EXPECT_NO_THROW(mem.data(kSize - 8, 8));
}

TEST(Memory, PortReportsErrorResponses) {
  Memory mem("mem", kSize, 20, 32, kCycle);
  Client a("a", mem, [](Client& c) {
    uint8_t b[8];
    c.port.read(kSize, b, 8);
    ADD_FAILURE() << "no error raised";
  });
  try {
    sc_core::sc_start();
    ADD_FAILURE() << "sc_start returned normally";
  } catch (const sc_core::sc_report& r) {
    EXPECT_NE(std::string(r.what()).find("a.mem: read of 8 bytes at 4096"), std::string::npos)
        << r.what();
  }
}

TEST(Memory, RejectsZeroBandwidthAndDuplicateNames) {
  Memory mem("mem", kSize, 20, 32, kCycle);
  RawInitiator r1("r1"), r2("r2");
  mem.bind(r1.socket, "dup");
  EXPECT_THROW(mem.bind(r2.socket, "dup"), std::invalid_argument);
  EXPECT_THROW(Memory("m0", kSize, 20, 0, kCycle), std::invalid_argument);
}

}  // namespace
}  // namespace gpusim
