#include "traces/vcd_writer.h"

namespace gpusim {
namespace {

// Short identifiers from the printable range '!'..'~', as VCD allows.
std::string identifier(size_t n) {
  std::string id;
  do {
    id += static_cast<char>('!' + n % 94);
    n /= 94;
  } while (n);
  return id;
}

// A vector's bit range, "[4:0]"; empty for one bit.
std::string range(unsigned width) {
  return width > 1 ? "[" + std::to_string(width - 1) + ":0]" : "";
}

}  // namespace

VcdWriter::VcdWriter(const std::string& path, uint64_t cycle_ps, uint64_t start, uint64_t end)
    : m_file(path),
      m_cycle_ps(cycle_ps),
      m_start(start),
      m_end(end),
      m_timescale(timescale_for(cycle_ps)) {}

VcdWriter::Timescale VcdWriter::timescale_for(uint64_t cycle_ps) {
  // Coarsest first: 100 s, 10 s, 1 s, 100 ms, ... 1 fs (which divides any
  // period of whole picoseconds).
  static const char* const units[] = {"s", "ms", "us", "ns", "ps", "fs"};
  const uint64_t period_fs = cycle_ps * 1000;
  uint64_t unit_fs = 1000000000000000;  // 1 s
  for (const char* unit : units) {
    for (const uint64_t m : {100, 10, 1}) {
      if (period_fs != 0 && period_fs % (m * unit_fs) == 0) {
        return {std::to_string(m) + " " + unit, period_fs / (m * unit_fs)};
      }
    }
    unit_fs /= 1000;
  }
  return {"1 fs", period_fs == 0 ? 1 : period_fs};
}

size_t VcdWriter::add(const std::string& scope, const std::string& name, unsigned width,
                      uint64_t initial) {
  Signal s;
  s.scope = scope;
  s.name = name;
  s.id = identifier(m_signals.size());
  s.width = width;
  s.value = s.written = initial;
  m_signals.push_back(s);
  return m_signals.size() - 1;
}

std::string VcdWriter::path(size_t signal) const {
  const Signal& s = m_signals[signal];
  return s.scope + "." + s.name + range(s.width);
}

void VcdWriter::begin() {
  std::string h = "$version gpusim $end\n";
  h += "$comment simulated time; one clock cycle is " + std::to_string(m_cycle_ps) + " ps, " +
       std::to_string(m_timescale.per_cycle) + " time unit" +
       (m_timescale.per_cycle == 1 ? "" : "s") + " $end\n$timescale " + m_timescale.text +
       " $end\n";
  // Scopes are dotted paths; open and close them as consecutive signals'
  // paths differ.
  std::vector<std::string> open;
  for (const Signal& s : m_signals) {
    std::vector<std::string> path;
    for (size_t a = 0, b; a <= s.scope.size(); a = b + 1) {
      b = s.scope.find('.', a);
      if (b == std::string::npos) b = s.scope.size();
      path.push_back(s.scope.substr(a, b - a));
    }
    size_t common = 0;
    while (common < open.size() && common < path.size() && open[common] == path[common]) ++common;
    for (size_t k = open.size(); k > common; --k) h += "$upscope $end\n";
    for (size_t k = common; k < path.size(); ++k) h += "$scope module " + path[k] + " $end\n";
    open = path;
    h += "$var wire " + std::to_string(s.width) + " " + s.id + " " + s.name +
         (s.width > 1 ? " " + range(s.width) : "") + " $end\n";
  }
  for (size_t k = open.size(); k > 0; --k) h += "$upscope $end\n";
  h += "$enddefinitions $end\n";
  out(h);
}

void VcdWriter::emit(const Signal& s, uint64_t value) {
  char buf[96];
  size_t n = 0;
  if (s.width == 1) {
    buf[n++] = value ? '1' : '0';
  } else {
    buf[n++] = 'b';
    int top = 63;
    while (top > 0 && !((value >> top) & 1)) --top;
    for (int b = top; b >= 0; --b) buf[n++] = ((value >> b) & 1) ? '1' : '0';
    buf[n++] = ' ';
  }
  out(buf, n);
  out(s.id);
  out("\n", 1);
  ++m_changes;
}

void VcdWriter::stamp(uint64_t cycle) {
  if (m_stamped && cycle == m_last_stamp) return;
  out("#" + std::to_string(cycle * m_timescale.per_cycle) + "\n");
  m_stamped = true;
  m_last_stamp = cycle;
}

void VcdWriter::dumpvars(bool use_written) {
  stamp(m_start);
  out("$dumpvars\n");
  for (const Signal& s : m_signals) emit(s, use_written ? s.written : s.value);
  out("$end\n");
  m_dumped = true;
}

void VcdWriter::end_cycle(uint64_t cycle) {
  if (m_dirty.empty()) return;
  if (cycle >= m_start && cycle < m_end) {
    bool changes = true;
    if (!m_dumped) {
      // $dumpvars holds the values at `start`: this cycle's when it is the
      // start, else those before this cycle's changes (none came between).
      dumpvars(cycle > m_start);
      changes = cycle > m_start;
    }
    for (size_t i : m_dirty) {
      const Signal& s = m_signals[i];
      if (!changes || s.value == s.written) continue;
      stamp(cycle);
      emit(s, s.value);
    }
  }
  for (size_t i : m_dirty) {
    Signal& s = m_signals[i];
    s.written = s.value;
    s.dirty = false;
  }
  m_dirty.clear();
}

void VcdWriter::finish(uint64_t cycle) {
  if (m_closed) return;
  m_closed = true;
  end_cycle(cycle);
  if (!m_dumped && m_start <= cycle && m_start < m_end) dumpvars(false);
  if (m_dumped) stamp(cycle < m_end ? cycle : m_end);
  m_file.close();
}

}  // namespace gpusim
