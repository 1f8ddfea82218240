// The one memory of the GPU, shared by every client (vertex fetch, depth
// test, ROP, ...) over a TLM-2.0 loosely-timed interface.
//
// Timing model (docs/gpu-config.md, "memory"): one data bus moving
// bytes_per_cycle bytes per cycle, reserved in call order. A request of len
// bytes that arrives at A = now + incoming delay
//   starts   S = max(A, bus_free)
//   occupies the bus for B = ceil(len / bytes_per_cycle) cycles
//   frees it at D = S + B  (bus_free = D)
// and completes `latency` cycles later; b_transport returns the delay
// (D - now) + latency, measured from now like every TLM annotation. Reads and
// writes cost the same. There is no backfilling: a request arriving earlier
// than a slot already reserved still queues behind it, so results depend only
// on the order of calls, which SystemC makes deterministic. Requests are not
// aligned to clock edges. Errors (bad address, byte enables, streaming) take
// no time and leave the bus untouched.
//
// Clients: the target socket is a multi_passthrough_target_socket, so client
// i is the i-th initiator bound to it. Memory::bind() binds and names one;
// initiators bound directly to `socket` are named "client<i>".
#pragma once

#include <tlm_utils/multi_passthrough_target_socket.h>
#include <tlm_utils/simple_initiator_socket.h>

#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <systemc>
#include <tlm>
#include <vector>

namespace gpusim {

struct MemoryClientStats {
  uint64_t requests = 0;  // successful b_transport reads and writes
  uint64_t reads = 0;
  uint64_t writes = 0;
  uint64_t bytes_read = 0;
  uint64_t bytes_written = 0;
  uint64_t busy_cycles = 0;  // bus cycles its requests occupied
  sc_core::sc_time queued;   // summed waits for the bus: S - A
  uint64_t errors = 0;       // requests answered with an error response
};

class Memory : public sc_core::sc_module {
 public:
  tlm_utils::multi_passthrough_target_socket<Memory> socket;

  // `size` bytes, zero-filled. Timing as in the header comment; `cycle` is the
  // clock period (GpuConfig::cycle()).
  Memory(sc_core::sc_module_name name, uint64_t size, unsigned latency_cycles,
         unsigned bytes_per_cycle, sc_core::sc_time cycle);

  // Binds `initiator` as the next client and names it (names must be unique);
  // returns its index. Elaboration only.
  unsigned bind(tlm::tlm_initiator_socket<>& initiator, const std::string& client_name);

  uint64_t size() const { return m_data.size(); }
  // Grows (or shrinks) the store, zero-filling new bytes. Invalidates data().
  void resize(uint64_t size) { m_data.resize(size); }

  // Backdoor for the testbench: no timing, no statistics. Out-of-range
  // accesses throw std::out_of_range.
  uint8_t* data(uint64_t addr, uint64_t len);
  void debug_read(uint64_t addr, void* dst, uint64_t len) const;
  void debug_write(uint64_t addr, const void* src, uint64_t len);

  // Clients seen so far: the named ones and every index that made a request.
  unsigned num_clients() const { return static_cast<unsigned>(m_clients.size()); }
  const std::string& client_name(unsigned index) const { return m_clients.at(index).name; }
  const MemoryClientStats& client_stats(unsigned index) const { return m_clients.at(index).stats; }
  uint64_t busy_cycles() const { return m_busy_cycles; }
  // When the bus finishes its last reserved transfer.
  sc_core::sc_time bus_free() const { return m_bus_free; }

  // {"size_bytes", "latency", "bytes_per_cycle", "busy_cycles", "utilization",
  //  "clients": {name: {requests, reads, writes, bytes_read, bytes_written,
  //  busy_cycles, queued_cycles, errors}}}; utilization is busy cycles over
  // the cycles elapsed so far.
  nlohmann::json stats_json() const;
  // What each stats_json() field means: {name: {"unit", "description"}}.
  static nlohmann::json descriptions();

 private:
  struct Client {
    std::string name;
    MemoryClientStats stats;
  };

  void b_transport(int id, tlm::tlm_generic_payload& trans, sc_core::sc_time& delay);
  unsigned int transport_dbg(int id, tlm::tlm_generic_payload& trans);
  // Client `id`, created (named "client<id>") on its first request.
  Client& client(int id) {
    const auto index = static_cast<size_t>(id);
    if (index >= m_clients.size()) add_clients(index);
    return m_clients[index];
  }
  void add_clients(size_t up_to);
  bool in_range(uint64_t addr, uint64_t len) const {
    return addr <= m_data.size() && len <= m_data.size() - addr;
  }

  std::vector<uint8_t> m_data;
  unsigned m_latency;
  unsigned m_bytes_per_cycle;
  sc_core::sc_time m_cycle;
  sc_core::sc_time m_latency_time;  // m_latency cycles
  sc_core::sc_time m_bus_free;
  uint64_t m_busy_cycles = 0;
  std::vector<Client> m_clients;
};

// The initiator side a stage owns: one socket and one reusable transaction,
// so a request allocates nothing. Construct it inside the owning module
// (it holds a port), then bind(memory).
class MemoryPort {
 public:
  explicit MemoryPort(const char* name = "mem");

  // Registers as a client named after the socket's hierarchical name.
  void bind(Memory& memory);

  // Performs the access and returns its delay from now (see Memory); the
  // caller decides when to wait. `delay` is the caller's local time offset at
  // which the request is issued. An error response is a model bug and raises
  // SC_REPORT_ERROR.
  sc_core::sc_time read(uint64_t addr, void* dst, uint64_t len,
                        sc_core::sc_time delay = sc_core::SC_ZERO_TIME);
  sc_core::sc_time write(uint64_t addr, const void* src, uint64_t len,
                         sc_core::sc_time delay = sc_core::SC_ZERO_TIME);

  tlm_utils::simple_initiator_socket<MemoryPort>& socket() { return m_socket; }

 private:
  sc_core::sc_time transport(tlm::tlm_command cmd, uint64_t addr, void* data, uint64_t len,
                             sc_core::sc_time delay);

  tlm_utils::simple_initiator_socket<MemoryPort> m_socket;
  tlm::tlm_generic_payload m_trans;
};

}  // namespace gpusim
