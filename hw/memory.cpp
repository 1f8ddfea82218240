#include "hw/memory.h"

#include <algorithm>
#include <cstring>
#include <functional>
#include <stdexcept>

#include "hw/stats.h"

namespace gpusim {

// --- MemoryArbiter -------------------------------------------------------------

MemoryArbiter::MemoryArbiter(const char* name, unsigned latency_cycles, unsigned bytes_per_cycle,
                             sc_core::sc_time cycle, unsigned channels)
    : sc_core::sc_prim_channel(name),
      m_bytes_per_cycle(bytes_per_cycle),
      m_cycle(cycle.value()),
      m_latency(cycle.value() * latency_cycles),
      m_channels(channels) {
  if (bytes_per_cycle == 0) throw std::invalid_argument("Memory: bytes_per_cycle must be >= 1");
  if (channels == 0) throw std::invalid_argument("Memory: channels must be >= 1");
}

unsigned MemoryArbiter::add_client() {
  m_clients.emplace_back();
  for (Channel& ch : m_channels) {
    ch.queues.emplace_back();
    ch.heads.push_back(0);
  }
  return static_cast<unsigned>(m_clients.size() - 1);
}

void MemoryArbiter::reset() {
  for (Client& c : m_clients) c = Client{};
  for (Channel& ch : m_channels) {
    ch = Channel{};
    ch.queues.resize(m_clients.size());
    ch.heads.assign(m_clients.size(), 0);
  }
  m_active_channels.clear();
}

sc_core::sc_time MemoryArbiter::bus_free() const {
  uint64_t t = 0;
  for (const Channel& ch : m_channels) t = std::max(t, ch.bus_free);
  return sc_core::sc_time::from_value(t);
}

uint64_t MemoryArbiter::busy_cycles() const {
  uint64_t n = 0;
  for (const Channel& ch : m_channels) n += ch.busy_cycles;
  return n;
}

MemoryArbiter::ChannelStats MemoryArbiter::channel_stats(unsigned channel) const {
  const Channel& ch = m_channels.at(channel);
  ChannelStats s;
  s.requests = ch.requests;
  s.reads = ch.reads;
  s.writes = ch.writes;
  s.bytes_read = ch.bytes_read;
  s.bytes_written = ch.bytes_written;
  s.busy_cycles = ch.busy_cycles;
  s.queued = sc_core::sc_time::from_value(ch.queued);
  s.queued_max = sc_core::sc_time::from_value(ch.queued_max);
  s.bus_free = sc_core::sc_time::from_value(ch.bus_free);
  return s;
}

// Channels are independent: each round is arbitrated per channel, in
// channel order (which cannot matter: no state is shared between them).
void MemoryArbiter::update() {
  for (const unsigned c : m_active_channels) arbitrate(c);
  m_active_channels.clear();
}

// Each client's queue is already in arrival order unless the client issued
// a later arrival before an earlier one; a stable sort then keeps its issue
// order among equal arrivals. The round is then a merge of the queues: the
// earliest arrival at any queue's head goes next, and among the queues whose
// heads arrive at that time the one nearest the pointer (in round-robin
// order) gives all its requests of that arrival; the pointer moves past it.
// Per grant this costs a scan of the clients active in the round, a handful,
// instead of a sort of the whole round (an end-of-frame flush issues
// thousands of rows at once).
void MemoryArbiter::arbitrate(unsigned channel) {
  Channel& ch = m_channels[channel];
  const auto by_arrival = [](const Request& a, const Request& b) { return a.arrival < b.arrival; };
  for (const unsigned c : ch.active) {
    std::vector<Request>& q = ch.queues[c];
    if (!std::is_sorted(q.begin(), q.end(), by_arrival))
      std::stable_sort(q.begin(), q.end(), by_arrival);
  }
  const unsigned n = num_clients();
  for (;;) {
    bool found = false;
    unsigned best = 0, best_rank = n;
    uint64_t arrival = 0;
    for (const unsigned c : ch.active) {
      if (ch.heads[c] == ch.queues[c].size()) continue;
      const uint64_t a = ch.queues[c][ch.heads[c]].arrival;
      const unsigned rank = c >= ch.next ? c - ch.next : c + n - ch.next;
      if (!found || a < arrival || (a == arrival && rank < best_rank)) {
        found = true;
        best = c;
        best_rank = rank;
        arrival = a;
      }
    }
    if (!found) break;
    const std::vector<Request>& q = ch.queues[best];
    size_t& head = ch.heads[best];
    do {
      grant(channel, best, q[head++]);
    } while (head < q.size() && q[head].arrival == arrival);
    ch.next = best + 1 < n ? best + 1 : 0;
  }
  for (const unsigned c : ch.active) {
    ch.queues[c].clear();
    ch.heads[c] = 0;
  }
  ch.active.clear();
}

void MemoryArbiter::grant(unsigned channel, unsigned client, const Request& r) {
  Channel& ch = m_channels[channel];
  const uint64_t start = std::max(r.arrival, ch.bus_free);
  ch.bus_free = start + r.busy * m_cycle;
  if (m_probe) m_probe->transfer(channel, start, ch.bus_free);
  const sc_core::sc_time done = sc_core::sc_time::from_value(ch.bus_free + m_latency);
  MemoryCompletion& c = r.sink->done;
  sc_core::sc_time& last = r.write ? c.writes : c.reads;
  if (done > last) last = done;
  r.sink->pending = false;
  const uint64_t wait = start - r.arrival;
  Client& cl = m_clients[client];
  cl.busy_cycles += r.busy;
  cl.queued += wait;
  cl.queued_max = std::max(cl.queued_max, wait);
  ++ch.requests;
  ++(r.write ? ch.writes : ch.reads);
  (r.write ? ch.bytes_written : ch.bytes_read) += r.len;
  ch.busy_cycles += r.busy;
  ch.queued += wait;
  ch.queued_max = std::max(ch.queued_max, wait);
}

// --- Memory --------------------------------------------------------------------

Memory::Memory(sc_core::sc_module_name name, uint64_t size, unsigned latency_cycles,
               unsigned bytes_per_cycle, sc_core::sc_time cycle, unsigned channels,
               unsigned interleave_bytes)
    : sc_core::sc_module(name),
      socket("socket"),
      m_data(size),
      m_latency(latency_cycles),
      m_bytes_per_cycle(bytes_per_cycle),
      m_interleave_shift(0),
      m_cycle(cycle),
      m_arbiter("arbiter", latency_cycles, bytes_per_cycle, cycle, channels) {
  if (interleave_bytes == 0 || (interleave_bytes & (interleave_bytes - 1)) != 0)
    throw std::invalid_argument("Memory: interleave_bytes must be a power of two");
  while ((1u << m_interleave_shift) < interleave_bytes) ++m_interleave_shift;
  socket.register_b_transport(this, &Memory::b_transport);
  socket.register_transport_dbg(this, &Memory::transport_dbg);
  declare_stats(channels);
}

void Memory::reset(uint64_t start) {
  m_arbiter.reset();
  for (Client& c : m_clients) c.stats = MemoryClientStats{};
  m_start = sc_core::sc_time::from_value(start);
}

unsigned Memory::add_client(const std::string& client_name) {
  for (const auto& c : m_clients) {
    if (c.name == client_name) {
      throw std::invalid_argument(std::string(name()) + ": client '" + client_name +
                                  "' bound twice");
    }
  }
  m_clients.push_back({client_name, {}});
  declare_client_stats(num_clients() - 1);
  return m_arbiter.add_client();
}

unsigned Memory::bind(tlm::tlm_initiator_socket<>& initiator, const std::string& client_name) {
  const unsigned client = add_client(client_name);
  initiator.bind(socket);
  // The socket numbers initiators in bind order, counting those bound to it
  // directly, so ask it rather than counting here.
  const size_t id = socket.size() - 1;
  if (m_socket_client.size() <= id) m_socket_client.resize(id + 1, -1);
  m_socket_client[id] = static_cast<int>(client);
  return client;
}

void Memory::end_of_elaboration() {
  // One backward path per initiator bound (socket.size() counts a stand-in
  // binder when none is).
  m_socket_client.resize(socket.get_base_port().size(), -1);
  for (int& client : m_socket_client) {
    if (client < 0) client = static_cast<int>(add_client("client" + std::to_string(num_clients())));
  }
}

bool Memory::issue(unsigned client, bool write, uint64_t addr, void* data, uint64_t len,
                   sc_core::sc_time offset, MemoryArbiter::Sink& sink) {
  MemoryClientStats& s = m_clients[client].stats;
  if (!in_range(addr, len)) {
    ++s.errors;
    return false;
  }
  if (write) {
    std::memcpy(m_data.data() + addr, data, len);
    ++s.writes;
    s.bytes_written += len;
  } else {
    std::memcpy(data, m_data.data() + addr, len);
    ++s.reads;
    s.bytes_read += len;
  }
  ++s.requests;
  if (num_channels() == 1) {
    m_arbiter.request(client, 0, offset, len, write, sink);
    return true;
  }
  // One piece per interleave block: consecutive blocks belong to different
  // channels whenever there are two or more.
  const uint64_t block = uint64_t{1} << m_interleave_shift;
  uint64_t at = addr;
  const uint64_t end = addr + len;
  do {
    const uint64_t piece_end = std::min(end, (at | (block - 1)) + 1);
    m_arbiter.request(client, channel_of(at), offset, piece_end - at, write, sink);
    at = piece_end;
  } while (at < end);
  return true;
}

void Memory::b_transport(int id, tlm::tlm_generic_payload& trans, sc_core::sc_time& delay) {
  const unsigned client = static_cast<unsigned>(m_socket_client.at(static_cast<size_t>(id)));
  MemoryClientStats& s = m_clients[client].stats;
  const tlm::tlm_command cmd = trans.get_command();
  const uint64_t addr = trans.get_address();
  const uint64_t len = trans.get_data_length();
  trans.set_dmi_allowed(false);
  if (trans.get_byte_enable_ptr() != nullptr) {
    ++s.errors;
    trans.set_response_status(tlm::TLM_BYTE_ENABLE_ERROR_RESPONSE);
    return;
  }
  if (trans.get_streaming_width() < len) {
    ++s.errors;
    trans.set_response_status(tlm::TLM_BURST_ERROR_RESPONSE);
    return;
  }
  if (!in_range(addr, len)) {
    ++s.errors;
    trans.set_response_status(tlm::TLM_ADDRESS_ERROR_RESPONSE);
    return;
  }
  if (cmd == tlm::TLM_IGNORE_COMMAND) {
    trans.set_response_status(tlm::TLM_OK_RESPONSE);
    return;
  }
  // A group of one request: wait for its round, then annotate the delay
  // from now, as every TLM timing annotation is.
  MemoryArbiter::Sink sink;
  issue(client, cmd == tlm::TLM_WRITE_COMMAND, addr, trans.get_data_ptr(), len, delay, sink);
  sc_core::wait(sc_core::SC_ZERO_TIME);
  delay = sink.done.last() - sc_core::sc_time_stamp();
  trans.set_response_status(tlm::TLM_OK_RESPONSE);
}

// Debug transport transfers what fits in the store, as TLM-2.0 prescribes.
unsigned int Memory::transport_dbg(int /*id*/, tlm::tlm_generic_payload& trans) {
  const uint64_t addr = trans.get_address();
  if (addr >= m_data.size()) return 0;
  const uint64_t len = std::min<uint64_t>(trans.get_data_length(), m_data.size() - addr);
  if (trans.get_command() == tlm::TLM_READ_COMMAND) {
    std::memcpy(trans.get_data_ptr(), &m_data[addr], len);
  } else if (trans.get_command() == tlm::TLM_WRITE_COMMAND) {
    std::memcpy(&m_data[addr], trans.get_data_ptr(), len);
  } else {
    return 0;
  }
  return static_cast<unsigned int>(len);
}

uint8_t* Memory::data(uint64_t addr, uint64_t len) {
  if (!in_range(addr, len)) {
    throw std::out_of_range(std::string(name()) + ": backdoor access [" + std::to_string(addr) +
                            ", +" + std::to_string(len) + ") beyond " +
                            std::to_string(m_data.size()) + " bytes");
  }
  return m_data.data() + addr;
}

void Memory::debug_read(uint64_t addr, void* dst, uint64_t len) const {
  if (!in_range(addr, len)) {
    throw std::out_of_range(std::string(name()) + ": backdoor read [" + std::to_string(addr) +
                            ", +" + std::to_string(len) + ") beyond " +
                            std::to_string(m_data.size()) + " bytes");
  }
  std::memcpy(dst, m_data.data() + addr, len);
}

void Memory::debug_write(uint64_t addr, const void* src, uint64_t len) {
  std::memcpy(data(addr, len), src, len);
}

MemoryClientStats Memory::client_stats(unsigned index) const {
  MemoryClientStats s = m_clients.at(index).stats;
  s.busy_cycles = m_arbiter.client_busy_cycles(index);
  s.queued = m_arbiter.client_queued(index);
  s.queued_max = m_arbiter.client_queued_max(index);
  return s;
}

namespace {

// The wait figures a client and a channel both report.
template <typename Totals>
void declare_waits(StatGroup& g, std::function<Totals()> totals, sc_core::sc_time cycle,
                   const char* queued_description) {
  g.formula("queued_cycles", "cycles", queued_description,
            [totals, cycle] { return totals().queued / cycle; });
  g.formula("queued_cycles_mean", "cycles", "queued_cycles over requests: the mean wait",
            [totals, cycle] {
              const Totals s = totals();
              return s.requests ? s.queued / cycle / s.requests : 0.0;
            });
  g.formula("queued_cycles_max", "cycles", "the longest wait of one request",
            [totals, cycle] { return totals().queued_max / cycle; });
}

}  // namespace

void Memory::declare_stats(unsigned channels) {
  StatGroup& g = m_stats;
  g.gauge("size_bytes", "bytes", "memory size", [this] { return size(); });
  g.gauge("latency", "cycles", "from the end of a bus transfer to its completion",
          [this] { return m_latency; });
  g.gauge("bytes_per_cycle", "bytes", "data bus width of one channel",
          [this] { return m_bytes_per_cycle; });
  g.gauge("interleave_bytes", "bytes", "consecutive bytes on one channel before the next",
          [this] { return uint64_t{1} << m_interleave_shift; });
  g.gauge("busy_cycles", "cycles", "cycles the buses moved data, all channels added up",
          [this] { return busy_cycles(); });
  g.formula("utilization", "ratio",
            "busy_cycles over the cycles elapsed times the channels: the mean channel's", [this] {
              const double bus_cycles =
                  (sc_core::sc_time_stamp() - m_start) / m_cycle * num_channels();
              return bus_cycles > 0 ? static_cast<double>(busy_cycles()) / bus_cycles : 0.0;
            });
  m_client_stats = &g.collection("clients", StatGroup::Layout::object, StatGroup::Describe::merged);

  StatCollection& list =
      g.collection("channels", StatGroup::Layout::array, StatGroup::Describe::merged);
  for (unsigned i = 0; i < channels; ++i) {
    StatGroup& c = list.make("channel" + std::to_string(i));
    const std::function<MemoryArbiter::ChannelStats()> totals = [this, i] {
      return channel_stats(i);
    };
    c.gauge("channel", "index", "the channel: addresses a with (a / interleave_bytes) % channels",
            [i] { return i; });
    c.gauge("requests", "requests", "requests and pieces of requests it moved",
            [totals] { return totals().requests; });
    c.gauge("reads", "requests", "reads among them", [totals] { return totals().reads; });
    c.gauge("writes", "requests", "writes among them", [totals] { return totals().writes; });
    c.gauge("bytes_read", "bytes", "bytes read through it",
            [totals] { return totals().bytes_read; });
    c.gauge("bytes_written", "bytes", "bytes written through it",
            [totals] { return totals().bytes_written; });
    c.gauge("busy_cycles", "cycles", "cycles its bus moved data",
            [totals] { return totals().busy_cycles; });
    c.formula("utilization", "ratio", "busy_cycles over the cycles elapsed", [this, totals] {
      const double elapsed = (sc_core::sc_time_stamp() - m_start) / m_cycle;
      return elapsed > 0 ? static_cast<double>(totals().busy_cycles) / elapsed : 0.0;
    });
    declare_waits(c, totals, m_cycle, "summed waits for its bus (arrival to start of transfer)");
  }
}

void Memory::declare_client_stats(unsigned index) {
  StatGroup& c = m_client_stats->make(m_clients[index].name);
  const std::function<MemoryClientStats()> totals = [this, index] { return client_stats(index); };
  c.gauge("requests", "requests", "successful reads and writes",
          [totals] { return totals().requests; });
  c.gauge("reads", "requests", "reads", [totals] { return totals().reads; });
  c.gauge("writes", "requests", "writes", [totals] { return totals().writes; });
  c.gauge("bytes_read", "bytes", "bytes read", [totals] { return totals().bytes_read; });
  c.gauge("bytes_written", "bytes", "bytes written", [totals] { return totals().bytes_written; });
  c.gauge("busy_cycles", "cycles", "bus cycles its requests occupied",
          [totals] { return totals().busy_cycles; });
  declare_waits(c, totals, m_cycle,
                "summed waits for the bus (arrival to start of transfer) of all requests");
  c.gauge("errors", "requests", "requests answered with an error",
          [totals] { return totals().errors; });
}

// --- MemoryPort ----------------------------------------------------------------

MemoryPort::MemoryPort(const char* name) : sc_core::sc_object(name) {}

void MemoryPort::bind(Memory& memory) {
  // The client is the stage that owns the port: one name for one thing.
  const sc_core::sc_object* owner = get_parent_object();
  m_client_name = owner ? owner->basename() : basename();
  m_client = memory.add_client(m_client_name);
  m_memory = &memory;
}

void MemoryPort::fail(bool write, uint64_t addr, uint64_t len) const {
  const std::string what =
      m_memory ? "beyond the " + std::to_string(m_memory->size()) + "-byte memory" : "not bound";
  SC_REPORT_ERROR("gpusim/memory",
                  (std::string(name()) + ": " + (write ? "write" : "read") + " of " +
                   std::to_string(len) + " bytes at " + std::to_string(addr) + ": " + what)
                      .c_str());
}

}  // namespace gpusim
