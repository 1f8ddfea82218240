// Superdense simulated time, and how a process in the kernel's time reaches
// one. Temporal decoupling (hw/pipeline_stage.h, hw/fifo.h) stamps every
// operation of a stage that runs ahead of the kernel with the superdense
// time the kernel-timed model would have made it at.
#pragma once

#include <cstdint>
#include <cstdlib>
#include <string>
#include <systemc>

namespace gpusim {

// An sc_time value and the delta cycle within it
// (sc_delta_count_at_current_time(): 0 for processes woken by time, k + 1
// for those woken by a delta notification in delta k). Ordered
// lexicographically.
struct SuperdenseTime {
  uint64_t t = 0;
  uint64_t d = 0;

  SuperdenseTime next_delta() const { return {t, d + 1}; }
  friend bool operator<(const SuperdenseTime& a, const SuperdenseTime& b) {
    return a.t < b.t || (a.t == b.t && a.d < b.d);
  }
  friend bool operator==(const SuperdenseTime& a, const SuperdenseTime& b) {
    return a.t == b.t && a.d == b.d;
  }
  friend bool operator!=(const SuperdenseTime& a, const SuperdenseTime& b) { return !(a == b); }
};

inline SuperdenseTime later(const SuperdenseTime& a, const SuperdenseTime& b) {
  return a < b ? b : a;
}

// The kernel's superdense time in simulation context `c`.
inline SuperdenseTime kernel_stamp(const sc_core::sc_simcontext& c) {
  return {c.time_stamp().value(), c.delta_count_at_current_time()};
}
inline SuperdenseTime kernel_stamp() {
  return kernel_stamp(*sc_core::sc_get_curr_simcontext());
}

// From a thread: waits until the kernel reaches `s` (a timed wait lands in
// delta 0, each zero-time wait one delta on). False if the kernel had
// already passed `s`: the caller's later actions would move, a model error
// the caller reports.
inline bool wait_until(const SuperdenseTime& s) {
  const sc_core::sc_simcontext& c = *sc_core::sc_get_curr_simcontext();
  const uint64_t t = c.time_stamp().value();
  if (s.t > t) sc_core::wait(sc_core::sc_time::from_value(s.t - t));
  while (kernel_stamp(c) < s) sc_core::wait(sc_core::SC_ZERO_TIME);
  return kernel_stamp(c) == s;
}

// The model error of an action taken after the kernel had passed the time
// it was stamped with: `who`'s `what` (SC_REPORT_ERROR, which throws).
[[noreturn]] inline void report_behind_kernel(const std::string& who, const std::string& what) {
  SC_REPORT_ERROR(
      "gpusim/decoupling",
      (who + ": " + what + " is behind the kernel's time (temporal decoupling)").c_str());
  std::abort();  // not reached
}

}  // namespace gpusim
