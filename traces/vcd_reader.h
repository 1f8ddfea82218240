// A minimal reader of IEEE 1364 value change dumps, enough for the
// signals.vcd a trace holds (docs/traces.md): nested scopes, `$var`s of any
// width, scalar and binary vector changes, `$dumpvars`. Values are unsigned
// integers; x and z bits read as VcdReader::kUnknown.
//
// The header is parsed once on construction; the value changes are streamed
// from the file on every pass, so a long trace costs memory only for what
// the caller keeps (histograms keep one counter per distinct value).
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace gpusim {

struct VcdSignal {
  std::string scope;  // dotted path of enclosing scopes: "gpu.primitive_setup"
  std::string name;   // "busy"
  unsigned width = 1;
};

class VcdReader {
 public:
  static constexpr uint64_t kUnknown = ~uint64_t{0};
  // Time spent at each value (file time units, or cycles: see the constructor).
  using Histogram = std::map<uint64_t, uint64_t>;

  // Parses the header up to $enddefinitions; InputError (one line naming the
  // file and line) when it is not a VCD. Times are the file's time units,
  // or with `cycle_ps` (the clock period in picoseconds) clock cycles: the
  // file's times divided by the period in `$timescale` units, which must be
  // whole, as every time stamp must be on a cycle boundary (InputError
  // otherwise). A file whose `$comment` says "one time unit is one clock
  // cycle" (traces written before signals.vcd was in simulated time) is read
  // as cycles already.
  explicit VcdReader(const std::string& path, uint64_t cycle_ps = 0);

  const std::string& path() const { return m_path; }
  const std::vector<VcdSignal>& signals() const { return m_signals; }
  // "1 ns", as declared.
  const std::string& timescale() const { return m_timescale; }
  // File time units per reported time unit (1 without cycle_ps).
  uint64_t units_per_time() const { return m_per_time; }
  // The signal named `name` directly inside scope `scope` (dotted path).
  std::optional<size_t> find(const std::string& scope, const std::string& name) const;

  // Every value change in file order (time never decreases): time, signal
  // index, new value. $dumpvars values come as changes at their time.
  void for_each_change(const std::function<void(uint64_t, size_t, uint64_t)>& fn) const;
  // Per signal, its (time, value) changes.
  std::vector<std::vector<std::pair<uint64_t, uint64_t>>> changes() const;
  // Per signal, the time spent at each value within [start, end). Time
  // before a signal's first value is not counted; its last value holds to
  // `end`.
  std::vector<Histogram> histograms(uint64_t start, uint64_t end) const;

 private:
  std::string m_path;
  std::string m_timescale;
  std::vector<VcdSignal> m_signals;
  // Identifier code -> signals (a code may name several aliases).
  std::unordered_map<std::string, std::vector<size_t>> m_ids;
  uint64_t m_per_time = 1;
  uint64_t m_body_offset = 0;  // file offset just after $enddefinitions $end
  uint64_t m_body_line = 1;
};

}  // namespace gpusim
