// The one memory of the GPU, shared by every client (vertex fetch, each depth
// test, each ROP) through an arbiter that decides the order in which their
// requests take the data bus of each channel (one channel by default).
// docs/architecture.md ("Memory") describes the same model for readers of
// the docs; docs/gpu-config.md ("Memory") lists its parameters and
// statistics.
//
// Function and timing are split. A request is functional when it is issued:
// the bytes are copied at once, and an error (an address range beyond the
// store) is reported at once. So a read sees every write issued before it,
// whatever their timing; this cannot show in a frame, where no two clients
// touch the same bytes (each unit owns its tiles, vertex data is only read).
// The timing is decided by the arbiter at the end of the delta cycle in
// which the request was issued: the requests issued during one evaluation
// phase are one arbitration round, resolved in the arbiter's update phase
// (MemoryArbiter is an sc_prim_channel) and granted in this order:
//   1. by arrival time A = now + the caller's local time offset, earliest
//      first;
//   2. among clients whose requests arrive at the same time: round-robin,
//      from the client the pointer designates (clients are numbered in the
//      order they are bound; the pointer starts at client 0) onwards, and the
//      pointer then moves past the last client granted, as in a hardware
//      round-robin arbiter;
//   3. one client's requests arriving at the same time: in issue order, all
//      of them before the next client's (a tile's rows are one burst).
// Every key is a property of the modelled hardware (simulated time, the
// wiring, a client's own sequence), never the order in which the SystemC
// kernel runs the processes of one delta. That order changes whenever a
// process outside the GPU (the progress line, the watchdog) is added, and
// when the bus was reserved in call order it changed the statistics.
// Why this order: earlier arrivals first is what a bus does when it sees
// the requests together; round-robin rather than a fixed priority so that
// no client starves when several keep the bus busy; bursts kept whole so
// that a transfer pays the latency once, as a single client always did.
//
// Bus model, applied to the requests in grant order: one data bus moving
// bytes_per_cycle bytes per cycle. A request of len bytes arriving at A
//   starts   S = max(A, bus_free)
//   occupies the bus for B = ceil(len / bytes_per_cycle) cycles
//   frees it at D = S + B  (bus_free = D)
// and completes at C = D + latency cycles. Reads and writes cost the same.
// There is no backfilling: a request granted in a later round queues behind
// every slot already reserved, even one that starts after its arrival.
// Rounds follow simulated time and, within one time, delta order, which the
// model's own events decide (e.g. a stage whose input arrives a delta later
// asks a delta later). Requests are not aligned to clock edges.
//
// Channels: the memory is `channels` such buses side by side, each with its
// own bus_free, round-robin pointer and statistics, and the same latency
// and width. Address a belongs to channel (a / interleave_bytes) % channels.
// A request is cut into pieces at the interleave boundaries it crosses (with
// one channel it stays whole: no boundary changes the channel); each piece
// is a request of its own on its channel (its own B, its own wait), arriving
// at the request's A, and the group completes when its last piece does. The grant order above holds
// per channel, among that channel's pieces; the channels never wait for each other.
//
// A client learns its completion times only after the round: it issues a
// group of requests (all rows of a tile, a write-back and a fill, all
// attribute bursts of a vertex batch) and then calls MemoryPort::wait_round(),
// which waits one delta (no simulated time passes) if any of them is still
// unresolved and returns when the group's last read and last write complete.
// A delta is the shortest wait that sees the whole round; one per group, not
// per request, keeps the cost to one kernel switch per tile miss or batch.
//
// The TLM-2.0 target socket stays for initiators outside this code base: its
// debug transport reads and writes without timing, and its b_transport is a
// one-request group through the same arbiter (it waits one delta, so it must
// be called from a thread). b_transport answers byte enables, streaming and
// out-of-range addresses with an error response, taking no time.
#pragma once

#include <tlm_utils/multi_passthrough_target_socket.h>

#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <systemc>
#include <tlm>
#include <vector>

#include "hw/stats.h"
#include "hw/superdense_time.h"

namespace gpusim {

// When a group of requests completes (absolute simulated times).
struct MemoryCompletion {
  sc_core::sc_time reads;   // the last read, SC_ZERO_TIME when there was none
  sc_core::sc_time writes;  // the last write, likewise
  sc_core::sc_time last() const { return reads > writes ? reads : writes; }
};

struct MemoryClientStats {
  uint64_t requests = 0;  // successful reads and writes
  uint64_t reads = 0;
  uint64_t writes = 0;
  uint64_t bytes_read = 0;
  uint64_t bytes_written = 0;
  uint64_t busy_cycles = 0;     // bus cycles its requests occupied
  sc_core::sc_time queued;      // summed waits for the bus: S - A
  sc_core::sc_time queued_max;  // the longest single wait S - A
  uint64_t errors = 0;          // requests answered with an error
};

// Told of every bus transfer as the arbiter grants it (Memory::set_probe):
// its channel and the sc_time values at which it starts and ends on that
// channel's bus. Per channel they come in start order (a grant starts at or
// after the channel's bus_free), so a trace can stream them. The trace
// recorder is one (traces/trace_recorder.h).
class MemoryProbe {
 public:
  virtual ~MemoryProbe() = default;
  virtual void transfer(unsigned channel, uint64_t start, uint64_t end) = 0;
};

// The timing half of the memory: collects a delta's requests and grants them
// in the order of the header comment. Knows nothing of addresses or data.
class MemoryArbiter : public sc_core::sc_prim_channel {
 public:
  // Where a group's completions are gathered: the requester owns it and
  // keeps it alive until the round is resolved (pending false).
  struct Sink {
    MemoryCompletion done;
    bool pending = false;  // a request of the group awaits its round
  };

  MemoryArbiter(const char* name, unsigned latency_cycles, unsigned bytes_per_cycle,
                sc_core::sc_time cycle, unsigned channels = 1);

  // The next client number (round-robin position). Elaboration only.
  unsigned add_client();
  // Between frames: no request queued or counted, every bus free and every
  // round-robin pointer at client 0, as elaborated.
  void reset();
  unsigned num_clients() const { return static_cast<unsigned>(m_clients.size()); }

  // Queues a request of `len` bytes on `channel` arriving `offset` after
  // now; its completion goes to `sink` in this delta's update phase.
  void request(unsigned client, unsigned channel, sc_core::sc_time offset, uint64_t len, bool write,
               Sink& sink) {
    Channel& ch = m_channels[channel];
    std::vector<Request>& q = ch.queues[client];
    if (q.empty()) {
      if (m_active_channels.empty()) request_update();
      if (ch.active.empty()) m_active_channels.push_back(channel);
      ch.active.push_back(client);
    }
    const uint64_t arrival = simcontext()->time_stamp().value() + offset.value();
    const uint64_t busy = (len + m_bytes_per_cycle - 1) / m_bytes_per_cycle;
    q.push_back(Request{arrival, busy, len, write, &sink});
    sink.pending = true;
  }

  unsigned num_channels() const { return static_cast<unsigned>(m_channels.size()); }
  // When the last channel finishes its last reserved transfer.
  sc_core::sc_time bus_free() const;
  // Bus cycles of all channels together.
  uint64_t busy_cycles() const;
  uint64_t client_busy_cycles(unsigned client) const { return m_clients.at(client).busy_cycles; }
  sc_core::sc_time client_queued(unsigned client) const {
    return sc_core::sc_time::from_value(m_clients.at(client).queued);
  }
  sc_core::sc_time client_queued_max(unsigned client) const {
    return sc_core::sc_time::from_value(m_clients.at(client).queued_max);
  }
  // One channel's totals: the pieces it granted.
  struct ChannelStats {
    uint64_t requests = 0, reads = 0, writes = 0;
    uint64_t bytes_read = 0, bytes_written = 0;
    uint64_t busy_cycles = 0;
    sc_core::sc_time queued, queued_max;  // as MemoryClientStats
    sc_core::sc_time bus_free;
  };
  ChannelStats channel_stats(unsigned channel) const;
  void set_probe(MemoryProbe* probe) { m_probe = probe; }

 private:
  struct Request {
    uint64_t arrival;  // sc_time value
    uint64_t busy;     // bus cycles
    uint64_t len;      // bytes
    bool write;
    Sink* sink;
  };
  // A client's timing totals over every channel.
  struct Client {
    uint64_t busy_cycles = 0;
    uint64_t queued = 0;      // sc_time value
    uint64_t queued_max = 0;  // sc_time value
  };
  // One bus: per client its requests of this round in issue order, the
  // bus's reservation and round-robin pointer, and its totals.
  struct Channel {
    std::vector<std::vector<Request>> queues;  // per client
    std::vector<size_t> heads;                 // per client: the next one to grant
    std::vector<unsigned> active;              // clients with requests this round
    uint64_t bus_free = 0;
    unsigned next = 0;  // round-robin pointer: the client with the highest priority
    uint64_t requests = 0, reads = 0, writes = 0, bytes_read = 0, bytes_written = 0;
    uint64_t busy_cycles = 0, queued = 0, queued_max = 0;
  };

  void update() override;
  void arbitrate(unsigned channel);
  void grant(unsigned channel, unsigned client, const Request& r);

  uint64_t m_bytes_per_cycle;
  uint64_t m_cycle;    // sc_time value of one clock cycle
  uint64_t m_latency;  // sc_time value of latency_cycles
  std::vector<Client> m_clients;
  std::vector<Channel> m_channels;
  std::vector<unsigned> m_active_channels;  // channels with requests this round
  MemoryProbe* m_probe = nullptr;
};

class Memory : public sc_core::sc_module {
 public:
  // Debug transport, and b_transport through the arbiter (header comment);
  // optional: the GPU's own clients do not use it.
  tlm_utils::multi_passthrough_target_socket_optional<Memory> socket;

  // `size` bytes, zero-filled. Timing as in the header comment; `cycle` is the
  // clock period (GpuConfig::cycle()); `channels` buses interleaved every
  // `interleave_bytes` (a power of two) bytes.
  Memory(sc_core::sc_module_name name, uint64_t size, unsigned latency_cycles,
         unsigned bytes_per_cycle, sc_core::sc_time cycle, unsigned channels = 1,
         unsigned interleave_bytes = 256);

  // Registers a client named `client_name` (unique) and returns its number:
  // clients are numbered in the order they are added, which is their order
  // on the arbiter's round-robin. Elaboration only. MemoryPort::bind() calls
  // it; so does bind() below for a TLM initiator. An initiator bound to
  // `socket` directly becomes a client named "client<n>" at the end of
  // elaboration, after every client added explicitly.
  unsigned add_client(const std::string& client_name);
  unsigned bind(tlm::tlm_initiator_socket<>& initiator, const std::string& client_name);

  // Between frames (Gpu::reset), at the new frame's first instant `start`
  // (an sc_time value): the arbiter and every statistic as elaborated, the
  // utilizations observed from `start`. The contents are the testbench's
  // (reset_contents).
  void reset(uint64_t start);
  // `size` bytes, every one zero: the store as a GPU elaborated with that
  // size starts. Invalidates data().
  void reset_contents(uint64_t size) { m_data.assign(size, 0); }

  uint64_t size() const { return m_data.size(); }

  // Backdoor for the testbench: no timing, no statistics. Out-of-range
  // accesses throw std::out_of_range.
  uint8_t* data(uint64_t addr, uint64_t len);
  void debug_read(uint64_t addr, void* dst, uint64_t len) const;
  void debug_write(uint64_t addr, const void* src, uint64_t len);

  // A timed request of client `client` (MemoryPort's path): copies the data
  // now and queues the timing on the arbiter, completion to `sink`. Returns
  // false, counting an error and queueing nothing, when [addr, addr + len)
  // is not inside the store.
  bool issue(unsigned client, bool write, uint64_t addr, void* data, uint64_t len,
             sc_core::sc_time offset, MemoryArbiter::Sink& sink);

  unsigned num_clients() const { return static_cast<unsigned>(m_clients.size()); }
  const std::string& client_name(unsigned index) const { return m_clients.at(index).name; }
  MemoryClientStats client_stats(unsigned index) const;
  uint64_t busy_cycles() const { return m_arbiter.busy_cycles(); }
  sc_core::sc_time bus_free() const { return m_arbiter.bus_free(); }
  unsigned num_channels() const { return m_arbiter.num_channels(); }
  unsigned channel_of(uint64_t addr) const {
    return static_cast<unsigned>((addr >> m_interleave_shift) % num_channels());
  }
  MemoryArbiter::ChannelStats channel_stats(unsigned channel) const {
    return m_arbiter.channel_stats(channel);
  }
  // Every transfer from now on goes to `probe` too (nullptr: none).
  void set_probe(MemoryProbe* probe) { m_arbiter.set_probe(probe); }

  // Its figures as the stat group "memory": its size, latency, bus width,
  // interleave, busy cycles and utilization (busy cycles over the cycles of
  // all channels so far: the mean channel's), "clients" {name: requests,
  // reads, writes, bytes_read, bytes_written, busy_cycles, queued_cycles,
  // queued_cycles_mean, queued_cycles_max, errors} and "channels"
  // [{channel, requests, reads, writes, bytes_read, bytes_written,
  // busy_cycles, utilization, queued_cycles, queued_cycles_mean,
  // queued_cycles_max}]. queued_cycles_mean is queued_cycles over requests
  // (0 without requests); a client's requests count its issues, a channel's
  // the pieces.
  const StatGroup& stat_group() const { return m_stats; }

 private:
  struct Client {
    std::string name;
    MemoryClientStats stats;  // the functional counts; timing is the arbiter's
  };

  void declare_stats(unsigned channels);
  void declare_client_stats(unsigned index);
  void end_of_elaboration() override;
  void b_transport(int id, tlm::tlm_generic_payload& trans, sc_core::sc_time& delay);
  unsigned int transport_dbg(int id, tlm::tlm_generic_payload& trans);
  bool in_range(uint64_t addr, uint64_t len) const {
    return addr <= m_data.size() && len <= m_data.size() - addr;
  }

  std::vector<uint8_t> m_data;
  unsigned m_latency;
  unsigned m_bytes_per_cycle;
  unsigned m_interleave_shift;  // log2(interleave_bytes)
  sc_core::sc_time m_cycle;
  sc_core::sc_time m_start;  // of the frame: what the utilizations are over
  std::vector<Client> m_clients;
  // Per socket initiator (multi-socket index): its client number.
  std::vector<int> m_socket_client;
  MemoryArbiter m_arbiter;
  StatGroup m_stats{"memory"};
  StatCollection* m_client_stats = nullptr;  // in m_stats
};

// A stage's connection to the memory. Construct it inside the owning module
// (it is an sc_object, named "mem" by default), then bind(memory): the
// client takes the owning module's name (e.g. "depth_test_0").
class MemoryPort : public sc_core::sc_object {
 public:
  explicit MemoryPort(const char* name = "mem");
  const char* kind() const override { return "gpusim_memory_port"; }

  void bind(Memory& memory);
  const std::string& client_name() const { return m_client_name; }

  // A client that runs ahead of the kernel's time (temporal decoupling,
  // hw/pipeline_stage.h) gives its clock: a request must join the
  // arbitration round of the client's own superdense time, so the first
  // request of a group waits until the kernel reaches the clock, and a
  // wait_round() that waits moves the clock on to the kernel's time. The
  // requests' arrival times, rounds and order are then those of a client in
  // the kernel's time, whatever the client did ahead of the kernel between
  // its groups. Before the simulation starts; null: the kernel's time.
  void set_clock(SuperdenseTime* clock) { m_clock = clock; }
  // The client's time: its clock's, or else the kernel's.
  sc_core::sc_time now() const {
    return m_clock ? sc_core::sc_time::from_value(m_clock->t) : sc_core::sc_time_stamp();
  }

  // Issue a request at local time offset `offset` from now: the data moves
  // at once, the timing is decided at the end of this delta (see Memory).
  // An address outside the memory is a model bug and raises
  // SC_REPORT_ERROR.
  void read(uint64_t addr, void* dst, uint64_t len,
            sc_core::sc_time offset = sc_core::SC_ZERO_TIME) {
    issue(false, addr, dst, len, offset);
  }
  void write(uint64_t addr, const void* src, uint64_t len,
             sc_core::sc_time offset = sc_core::SC_ZERO_TIME) {
    // The data pointer is shared with reads, but a write only reads it.
    issue(true, addr, const_cast<void*>(src), len, offset);
  }

  // A read whose own completion the caller wants (a texture cache's line
  // fills: each fragment waits for its own lines, not for the group's last):
  // `sink` receives it in the round's update phase, and the caller keeps it
  // alive until then. wait_round() waits for it as for any other request.
  void read_tracked(uint64_t addr, void* dst, uint64_t len, sc_core::sc_time offset,
                    MemoryArbiter::Sink& sink) {
    if (m_clock && !wait_until(*m_clock)) report_behind_kernel(name(), "a request");
    if (!m_memory || !m_memory->issue(m_client, false, addr, dst, len, offset, sink))
      fail(false, addr, len);
    m_tracked_pending = true;
  }

  // Untimed access to the same store (Memory::debug_read/debug_write): for a
  // client whose timed traffic is smaller than the data it holds (a
  // compressed tile moves its encoded size; the store keeps the decoded
  // bytes). No arbitration, no statistics.
  void debug_read(uint64_t addr, void* dst, uint64_t len) const {
    m_memory->debug_read(addr, dst, len);
  }
  void debug_write(uint64_t addr, const void* src, uint64_t len) {
    m_memory->debug_write(addr, src, len);
  }

  // When the requests issued since the previous call complete: waits one
  // delta first if any of them has not been through its round yet (no
  // simulated time passes). A group whose requests were all resolved
  // already (posted writes from an earlier delta) returns at once; no
  // request at all gives zero times. Threads only, when it waits.
  MemoryCompletion wait_round() {
    if (m_sink.pending || m_tracked_pending) {
      sc_core::wait(sc_core::SC_ZERO_TIME);
      if (m_clock) *m_clock = kernel_stamp();
    }
    m_tracked_pending = false;
    const MemoryCompletion done = m_sink.done;
    m_sink.done = MemoryCompletion{};
    return done;
  }

 private:
  void issue(bool write, uint64_t addr, void* data, uint64_t len, sc_core::sc_time offset) {
    if (m_clock && !wait_until(*m_clock)) report_behind_kernel(name(), "a request");
    if (!m_memory || !m_memory->issue(m_client, write, addr, data, len, offset, m_sink))
      fail(write, addr, len);
  }
  void fail(bool write, uint64_t addr, uint64_t len) const;

  Memory* m_memory = nullptr;
  unsigned m_client = 0;
  std::string m_client_name;
  MemoryArbiter::Sink m_sink;
  bool m_tracked_pending = false;  // a read_tracked() since the last wait_round()
  SuperdenseTime* m_clock = nullptr;
};

}  // namespace gpusim
