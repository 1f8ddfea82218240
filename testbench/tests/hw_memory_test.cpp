// Memory data, timing and statistics. Clock 1 ns, latency 20 cycles, 32 bytes
// per cycle: a request of len bytes on an idle bus completes after
// ceil(len / 32) + 20 cycles. One sc_start per TEST (ctest: one process each).
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <functional>
#include <numeric>
#include <vector>

#include "hw/memory.h"

namespace gpusim {
namespace {

using sc_core::sc_time;

const sc_time kCycle(1, sc_core::SC_NS);
constexpr uint64_t kSize = 4096;
double in_cycles(sc_time t) {
  return t / kCycle;
}

// A client stage: one MemoryPort and one thread running `body`.
struct Client : sc_core::sc_module {
  MemoryPort port{"mem"};
  std::function<void(Client&)> body;
  SC_HAS_PROCESS(Client);
  Client(sc_core::sc_module_name name, Memory& memory, std::function<void(Client&)> b)
      : sc_core::sc_module(name), body(std::move(b)) {
    port.bind(memory);
    SC_THREAD(run);
  }
  void run() { body(*this); }
};

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
    sc_time d = c.port.write(128, data.data(), data.size());
    delays.push_back(in_cycles(d));
    sc_core::wait(d);
    d = c.port.read(128, back.data(), back.size());
    delays.push_back(in_cycles(d));
    sc_core::wait(d);
    d = c.port.read(1000, back_door.data(), back_door.size());  // 16 bytes: 1 cycle
    delays.push_back(in_cycles(d));
    sc_core::wait(d);
    delays.push_back(in_cycles(c.port.read(2000, odd.data(), 33)));  // 2 cycles
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

// One client issues requests without waiting in between:
//   64 B, arrives 0:             bus [0,2)   -> 2 + 20 = 22
//   64 B, arrives 0:             bus [2,4)   -> 24 (queued 2)
//   64 B, incoming delay 10:     bus [10,12) -> 32 (bus idle from 4 to 10)
//   64 B, incoming delay 1:      bus [12,14) -> 34 (queued 11: no backfilling)
TEST(Memory, BackToBackRequestsQueueOnTheBus) {
  Memory mem("mem", kSize, 20, 32, kCycle);
  std::vector<double> delays;
  Client a("a", mem, [&](Client& c) {
    std::array<uint8_t, 64> buf{};
    delays.push_back(in_cycles(c.port.read(0, buf.data(), 64)));
    delays.push_back(in_cycles(c.port.read(64, buf.data(), 64)));
    delays.push_back(in_cycles(c.port.read(128, buf.data(), 64, 10 * kCycle)));
    delays.push_back(in_cycles(c.port.read(192, buf.data(), 64, kCycle)));
  });
  sc_core::sc_start();
  EXPECT_EQ(delays, (std::vector<double>{22, 24, 32, 34}));
  EXPECT_EQ(in_cycles(mem.bus_free()), 14);
  EXPECT_EQ(mem.client_stats(0).busy_cycles, 8u);
  EXPECT_EQ(in_cycles(mem.client_stats(0).queued), 13);
  EXPECT_EQ(mem.stats_json()["clients"]["a.mem"]["queued_cycles"], 13.0);
}

// Two clients at the same instant share the bus in call order. At t=0 both
// read 64 B (whoever calls first gets 22, the other 24). At t=30, `b` one
// delta after `a`: a reads 96 B -> bus [30,33) -> 23; b reads 32 B -> bus
// [33,34) -> 24.
TEST(Memory, ConcurrentClientsShareTheBandwidth) {
  Memory mem("mem", kSize, 20, 32, kCycle);
  double a0 = 0, b0 = 0, a1 = 0, b1 = 0;
  std::array<uint8_t, 96> buf_a{}, buf_b{};
  Client a("a", mem, [&](Client& c) {
    a0 = in_cycles(c.port.read(0, buf_a.data(), 64));
    sc_core::wait(30 * kCycle);
    a1 = in_cycles(c.port.read(0, buf_a.data(), 96));
  });
  Client b("b", mem, [&](Client& c) {
    b0 = in_cycles(c.port.read(512, buf_b.data(), 64));
    sc_core::wait(30 * kCycle);
    sc_core::wait(sc_core::SC_ZERO_TIME);
    b1 = in_cycles(c.port.read(512, buf_b.data(), 32));
  });
  sc_core::sc_start();
  EXPECT_EQ(std::min(a0, b0), 22);
  EXPECT_EQ(std::max(a0, b0), 24);
  EXPECT_EQ(a1, 23);
  EXPECT_EQ(b1, 24);
  EXPECT_EQ(mem.busy_cycles(), 2u + 2u + 3u + 1u);
}

// Per-client traffic: a writes 100 B (4 bus cycles) and reads 64 B (2);
// b reads 32 B (1) and writes 8 B (1).
TEST(Memory, PerClientStatistics) {
  Memory mem("mem", kSize, 20, 32, kCycle);
  std::vector<uint8_t> buf(100, 0x5a);
  Client a("a", mem, [&](Client& c) {
    sc_core::wait(c.port.write(0, buf.data(), 100));
    sc_core::wait(c.port.read(0, buf.data(), 64));
  });
  std::vector<uint8_t> buf_b(32);
  Client b("b", mem, [&](Client& c) {
    sc_core::wait(c.port.read(200, buf_b.data(), 32));
    sc_core::wait(c.port.write(300, buf_b.data(), 8));
  });
  sc_core::sc_start();

  ASSERT_EQ(mem.num_clients(), 2u);
  EXPECT_EQ(mem.client_name(0), "a.mem");
  EXPECT_EQ(mem.client_name(1), "b.mem");
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

  // Whatever the order of calls, the bus was busy 4 + 2 + 1 + 1 cycles.
  const nlohmann::json j = mem.stats_json();
  EXPECT_EQ(j["busy_cycles"], 8);
  EXPECT_EQ(j["size_bytes"], kSize);
  EXPECT_EQ(j["latency"], 20);
  EXPECT_EQ(j["bytes_per_cycle"], 32);
  EXPECT_EQ(j["clients"]["a.mem"]["bytes_written"], 100);
  EXPECT_EQ(j["clients"]["b.mem"]["bytes_read"], 32);
  EXPECT_EQ(j["clients"]["b.mem"]["requests"], 2);
  EXPECT_DOUBLE_EQ(j["utilization"].get<double>(), 8.0 / in_cycles(sc_core::sc_time_stamp()));
}

// A raw TLM initiator bound straight to the socket, after a named port.
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
  // Errors take no time; the good read arrives at 3 and takes 1 + 20.
  EXPECT_EQ(delays, (std::vector<double>{3, 3, 24, 3, 3}));
  EXPECT_EQ(dbg_clipped, 4u);
  EXPECT_EQ(dbg_outside, 0u);

  // Clients are numbered in bind order: the two named ports, then the raw
  // socket bound directly.
  ASSERT_EQ(mem.num_clients(), 3u);
  EXPECT_EQ(mem.client_name(0), "named.mem");
  EXPECT_EQ(mem.client_name(1), "client1");
  EXPECT_EQ(mem.client_name(2), "driver.mem");
  EXPECT_EQ(mem.client_stats(1).errors, 4u);
  EXPECT_EQ(mem.client_stats(1).requests, 1u);
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
