// A memory client for the memory's unit tests: one MemoryPort and one thread
// running `body`, on a 1 ns clock.
#pragma once

#include <functional>
#include <systemc>
#include <utility>

#include "hw/memory.h"

namespace gpusim {

inline const sc_core::sc_time kCycle(1, sc_core::SC_NS);
inline double in_cycles(sc_core::sc_time t) {
  return t / kCycle;
}

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

}  // namespace gpusim
