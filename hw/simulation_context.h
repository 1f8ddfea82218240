// SystemC elaborates one model per simulation context and cannot restart a
// finished one, so each elaboration after the first in a process gets a fresh
// context (the old one is left behind: SystemC cannot delete a context
// safely). Call it before constructing a model; the first call keeps the
// context SystemC started with.
#pragma once

#include <systemc>

namespace gpusim {

inline sc_core::sc_simcontext* fresh_simulation_context() {
  static bool used = false;
  if (used) {
    sc_core::sc_curr_simcontext = new sc_core::sc_simcontext;
    sc_core::sc_default_global_context = sc_core::sc_curr_simcontext;
  }
  used = true;
  return sc_core::sc_get_curr_simcontext();
}

// Makes `context` (a fresh_simulation_context() result) the one sc_start()
// runs again: a model kept across frames (GpuRunner) runs in its own while
// others are elaborated in between.
inline void use_simulation_context(sc_core::sc_simcontext* context) {
  sc_core::sc_curr_simcontext = context;
  sc_core::sc_default_global_context = context;
}

}  // namespace gpusim
