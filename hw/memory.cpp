#include "hw/memory.h"

#include <algorithm>
#include <climits>
#include <cstring>
#include <stdexcept>

namespace gpusim {

Memory::Memory(sc_core::sc_module_name name, uint64_t size, unsigned latency_cycles,
               unsigned bytes_per_cycle, sc_core::sc_time cycle)
    : sc_core::sc_module(name),
      socket("socket"),
      m_data(size),
      m_latency(latency_cycles),
      m_bytes_per_cycle(bytes_per_cycle),
      m_cycle(cycle),
      m_latency_time(sc_core::sc_time::from_value(cycle.value() * latency_cycles)) {
  if (bytes_per_cycle == 0) throw std::invalid_argument("Memory: bytes_per_cycle must be >= 1");
  socket.register_b_transport(this, &Memory::b_transport);
  socket.register_transport_dbg(this, &Memory::transport_dbg);
}

unsigned Memory::bind(tlm::tlm_initiator_socket<>& initiator, const std::string& client_name) {
  for (const auto& c : m_clients) {
    if (c.name == client_name) {
      throw std::invalid_argument(std::string(name()) + ": client '" + client_name +
                                  "' bound twice");
    }
  }
  initiator.bind(socket);
  // The socket numbers initiators in bind order, counting those bound to it
  // directly, so ask it rather than counting here.
  const unsigned index = socket.size() - 1;
  client(static_cast<int>(index)).name = client_name;
  return index;
}

void Memory::add_clients(size_t up_to) {
  while (m_clients.size() <= up_to) {
    m_clients.push_back({"client" + std::to_string(m_clients.size()), {}});
  }
}

void Memory::b_transport(int id, tlm::tlm_generic_payload& trans, sc_core::sc_time& delay) {
  Client& c = client(id);
  const tlm::tlm_command cmd = trans.get_command();
  const uint64_t addr = trans.get_address();
  const uint64_t len = trans.get_data_length();
  trans.set_dmi_allowed(false);
  if (trans.get_byte_enable_ptr() != nullptr) {
    ++c.stats.errors;
    trans.set_response_status(tlm::TLM_BYTE_ENABLE_ERROR_RESPONSE);
    return;
  }
  if (trans.get_streaming_width() < len) {
    ++c.stats.errors;
    trans.set_response_status(tlm::TLM_BURST_ERROR_RESPONSE);
    return;
  }
  if (!in_range(addr, len)) {
    ++c.stats.errors;
    trans.set_response_status(tlm::TLM_ADDRESS_ERROR_RESPONSE);
    return;
  }
  if (cmd == tlm::TLM_IGNORE_COMMAND) {
    trans.set_response_status(tlm::TLM_OK_RESPONSE);
    return;
  }

  if (cmd == tlm::TLM_READ_COMMAND) {
    std::memcpy(trans.get_data_ptr(), &m_data[addr], len);
    ++c.stats.reads;
    c.stats.bytes_read += len;
  } else {
    std::memcpy(&m_data[addr], trans.get_data_ptr(), len);
    ++c.stats.writes;
    c.stats.bytes_written += len;
  }

  // The bus model of the header comment. (The time is read from this
  // module's simulation context inline: the same as sc_time_stamp().)
  const sc_core::sc_time now = simcontext()->time_stamp();
  const sc_core::sc_time arrival = now + delay;
  const sc_core::sc_time start = arrival > m_bus_free ? arrival : m_bus_free;
  const uint64_t busy = (len + m_bytes_per_cycle - 1) / m_bytes_per_cycle;
  m_bus_free = start + sc_core::sc_time::from_value(m_cycle.value() * busy);
  delay = (m_bus_free - now) + m_latency_time;

  ++c.stats.requests;
  c.stats.busy_cycles += busy;
  c.stats.queued += start - arrival;
  m_busy_cycles += busy;
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

nlohmann::json Memory::stats_json() const {
  const double elapsed = sc_core::sc_time_stamp() / m_cycle;
  nlohmann::json clients = nlohmann::json::object();
  for (const auto& c : m_clients) {
    const MemoryClientStats& s = c.stats;
    clients[c.name] = {
        {"requests", s.requests},
        {"reads", s.reads},
        {"writes", s.writes},
        {"bytes_read", s.bytes_read},
        {"bytes_written", s.bytes_written},
        {"busy_cycles", s.busy_cycles},
        {"queued_cycles", s.queued / m_cycle},
        {"errors", s.errors},
    };
  }
  return {
      {"size_bytes", m_data.size()},
      {"latency", m_latency},
      {"bytes_per_cycle", m_bytes_per_cycle},
      {"busy_cycles", m_busy_cycles},
      {"utilization", elapsed > 0 ? static_cast<double>(m_busy_cycles) / elapsed : 0.0},
      {"clients", clients},
  };
}

nlohmann::json Memory::descriptions() {
  const auto d = [](const char* unit, const char* text) {
    return nlohmann::json{{"unit", unit}, {"description", text}};
  };
  return {
      {"size_bytes", d("bytes", "memory size")},
      {"latency", d("cycles", "from the end of a bus transfer to its completion")},
      {"bytes_per_cycle", d("bytes", "data bus width")},
      {"busy_cycles", d("cycles", "cycles the bus moved data")},
      {"utilization", d("ratio", "busy_cycles over the cycles elapsed")},
      {"clients",
       {{"requests", d("requests", "successful reads and writes")},
        {"reads", d("requests", "reads")},
        {"writes", d("requests", "writes")},
        {"bytes_read", d("bytes", "bytes read")},
        {"bytes_written", d("bytes", "bytes written")},
        {"busy_cycles", d("cycles", "bus cycles its requests occupied")},
        {"queued_cycles", d("cycles", "summed waits for the bus")},
        {"errors", d("requests", "requests answered with an error")}}},
  };
}

MemoryPort::MemoryPort(const char* name) : m_socket(name) {}

void MemoryPort::bind(Memory& memory) {
  memory.bind(m_socket, m_socket.name());
}

sc_core::sc_time MemoryPort::read(uint64_t addr, void* dst, uint64_t len, sc_core::sc_time delay) {
  return transport(tlm::TLM_READ_COMMAND, addr, dst, len, delay);
}

sc_core::sc_time MemoryPort::write(uint64_t addr, const void* src, uint64_t len,
                                   sc_core::sc_time delay) {
  // The payload's data pointer is non-const, but a write only reads it.
  return transport(tlm::TLM_WRITE_COMMAND, addr, const_cast<void*>(src), len, delay);
}

sc_core::sc_time MemoryPort::transport(tlm::tlm_command cmd, uint64_t addr, void* data,
                                       uint64_t len, sc_core::sc_time delay) {
  if (len > UINT_MAX) {
    SC_REPORT_ERROR("gpusim/memory", (std::string(m_socket.name()) + ": request of " +
                                      std::to_string(len) + " bytes exceeds TLM's 32-bit length")
                                         .c_str());
  }
  m_trans.set_command(cmd);
  m_trans.set_address(addr);
  m_trans.set_data_ptr(static_cast<unsigned char*>(data));
  m_trans.set_data_length(static_cast<unsigned int>(len));
  m_trans.set_streaming_width(static_cast<unsigned int>(len));
  m_trans.set_byte_enable_ptr(nullptr);
  m_trans.set_byte_enable_length(0);
  m_trans.set_dmi_allowed(false);
  m_trans.set_response_status(tlm::TLM_INCOMPLETE_RESPONSE);
  m_socket->b_transport(m_trans, delay);
  if (!m_trans.is_response_ok()) {
    SC_REPORT_ERROR("gpusim/memory", (std::string(m_socket.name()) + ": " +
                                      (cmd == tlm::TLM_READ_COMMAND ? "read" : "write") + " of " +
                                      std::to_string(len) + " bytes at " + std::to_string(addr) +
                                      ": " + m_trans.get_response_string())
                                         .c_str());
  }
  return delay;
}

}  // namespace gpusim
