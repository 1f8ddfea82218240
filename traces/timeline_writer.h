// timeline.json (docs/traces.md): the JSON object form of the Chrome / Perfetto
// Trace Event Format, streamed event by event. Times are microseconds with
// three decimals: each cycle boundary is rounded once to the nearest
// nanosecond (integer arithmetic, halves up) and a slice's `dur` is the
// difference of its rounded ends, so viewers that round `ts` and `dur` to
// nanoseconds see exactly these values and consecutive slices never overlap.
// The same run gives the same bytes.
#pragma once

#include <cstdint>
#include <string>

#include "traces/buffered_file.h"

namespace gpusim {

class TimelineWriter {
 public:
  // other_data: the "otherData" object, as JSON text.
  TimelineWriter(const std::string& path, uint64_t cycle_ps, const std::string& other_data);
  void process_name(int pid, const std::string& name);
  void thread_name(int pid, int tid, const std::string& name, int sort_index);
  // An X event; args_json: the members of "args" after cycle_in and cycle_out.
  // `name` must need no JSON escaping (the recorder's names do not).
  void complete(int pid, int tid, const std::string& name, const char* category, uint64_t cycle_in,
                uint64_t cycle_out, const std::string& args_json);
  // A C event: counter `name` (no escaping needed) takes `value` (args
  // {"occupancy": value}).
  void counter(int pid, int tid, const std::string& name, uint64_t cycle, uint64_t value);
  void finish();
  uint64_t events() const { return m_events; }

  // cycles × cycle_ps picoseconds rounded to the nearest nanosecond.
  static uint64_t nanoseconds(uint64_t cycles, uint64_t cycle_ps);
  // That time in microseconds as written ("12.345", "2.000").
  static std::string microseconds(uint64_t cycles, uint64_t cycle_ps);

 private:
  void event(const char* text, size_t n);
  void event(const std::string& text);

  BufferedFile m_file;
  uint64_t m_cycle_ps;
  uint64_t m_events = 0;
};

// A JSON string literal of `s`, quotes included.
std::string json_quote(const std::string& s);

}  // namespace gpusim
