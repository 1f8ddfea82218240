#include "hw/memory.h"

#include <algorithm>
#include <cstring>
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
}

unsigned Memory::add_client(const std::string& client_name) {
  for (const auto& c : m_clients) {
    if (c.name == client_name) {
      throw std::invalid_argument(std::string(name()) + ": client '" + client_name +
                                  "' bound twice");
    }
  }
  m_clients.push_back({client_name, {}});
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

nlohmann::json Memory::stats_json() const {
  const double elapsed = sc_core::sc_time_stamp() / m_cycle;
  nlohmann::json clients = nlohmann::json::object();
  for (unsigned i = 0; i < num_clients(); ++i) {
    const MemoryClientStats s = client_stats(i);
    clients[client_name(i)] = {
        {"requests", s.requests},
        {"reads", s.reads},
        {"writes", s.writes},
        {"bytes_read", s.bytes_read},
        {"bytes_written", s.bytes_written},
        {"busy_cycles", s.busy_cycles},
        {"queued_cycles", s.queued / m_cycle},
        {"queued_cycles_mean", s.requests ? s.queued / m_cycle / s.requests : 0.0},
        {"queued_cycles_max", s.queued_max / m_cycle},
        {"errors", s.errors},
    };
  }
  nlohmann::json channels = nlohmann::json::array();
  for (unsigned i = 0; i < num_channels(); ++i) {
    const MemoryArbiter::ChannelStats s = channel_stats(i);
    channels.push_back({
        {"channel", i},
        {"requests", s.requests},
        {"reads", s.reads},
        {"writes", s.writes},
        {"bytes_read", s.bytes_read},
        {"bytes_written", s.bytes_written},
        {"busy_cycles", s.busy_cycles},
        {"utilization", elapsed > 0 ? static_cast<double>(s.busy_cycles) / elapsed : 0.0},
        {"queued_cycles", s.queued / m_cycle},
        {"queued_cycles_mean", s.requests ? s.queued / m_cycle / s.requests : 0.0},
        {"queued_cycles_max", s.queued_max / m_cycle},
    });
  }
  const uint64_t busy = busy_cycles();
  const double bus_cycles = elapsed * num_channels();
  return {
      {"size_bytes", m_data.size()},
      {"latency", m_latency},
      {"bytes_per_cycle", m_bytes_per_cycle},
      {"interleave_bytes", uint64_t{1} << m_interleave_shift},
      {"busy_cycles", busy},
      {"utilization", bus_cycles > 0 ? static_cast<double>(busy) / bus_cycles : 0.0},
      {"clients", clients},
      {"channels", channels},
  };
}

nlohmann::json Memory::descriptions() {
  const auto& d = stat_description;
  return {
      {"size_bytes", d("bytes", "memory size")},
      {"latency", d("cycles", "from the end of a bus transfer to its completion")},
      {"bytes_per_cycle", d("bytes", "data bus width of one channel")},
      {"interleave_bytes", d("bytes", "consecutive bytes on one channel before the next")},
      {"busy_cycles", d("cycles", "cycles the buses moved data, all channels added up")},
      {"utilization",
       d("ratio", "busy_cycles over the cycles elapsed times the channels: the mean channel's")},
      {"clients",
       {{"requests", d("requests", "successful reads and writes")},
        {"reads", d("requests", "reads")},
        {"writes", d("requests", "writes")},
        {"bytes_read", d("bytes", "bytes read")},
        {"bytes_written", d("bytes", "bytes written")},
        {"busy_cycles", d("cycles", "bus cycles its requests occupied")},
        {"queued_cycles",
         d("cycles", "summed waits for the bus (arrival to start of transfer) of all requests")},
        {"queued_cycles_mean", d("cycles", "queued_cycles over requests: the mean wait")},
        {"queued_cycles_max", d("cycles", "the longest wait of one request")},
        {"errors", d("requests", "requests answered with an error")}}},
      {"channels",
       {{"channel", d("index", "the channel: addresses a with (a / interleave_bytes) % channels")},
        {"requests", d("requests", "requests and pieces of requests it moved")},
        {"reads", d("requests", "reads among them")},
        {"writes", d("requests", "writes among them")},
        {"bytes_read", d("bytes", "bytes read through it")},
        {"bytes_written", d("bytes", "bytes written through it")},
        {"busy_cycles", d("cycles", "cycles its bus moved data")},
        {"utilization", d("ratio", "busy_cycles over the cycles elapsed")},
        {"queued_cycles", d("cycles", "summed waits for its bus (arrival to start of transfer)")},
        {"queued_cycles_mean", d("cycles", "queued_cycles over requests: the mean wait")},
        {"queued_cycles_max", d("cycles", "the longest wait of one request")}}},
  };
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
