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

}  // namespace

VcdWriter::VcdWriter(const std::string& path, uint64_t cycle_ps, uint64_t start, uint64_t end)
    : m_file(path), m_cycle_ps(cycle_ps), m_start(start), m_end(end) {}

std::string VcdWriter::timescale_for(uint64_t cycle_ps) {
  static const char* const units[] = {"fs", "ps", "ns", "us", "ms", "s"};
  uint64_t fs = cycle_ps * 1000;
  for (const char* unit : units) {
    for (uint64_t m : {1, 10, 100}) {
      if (fs == m) return std::to_string(m) + " " + unit;
    }
    if (fs % 1000 != 0) return "";
    fs /= 1000;
  }
  return "";
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

void VcdWriter::begin() {
  std::string h = "$version gpusim $end\n";
  const std::string ts = timescale_for(m_cycle_ps);
  if (ts.empty()) {
    h += "$comment one time unit is one clock cycle of " + std::to_string(m_cycle_ps) +
         " ps $end\n$timescale 1 ps $end\n";
  } else {
    h += "$comment one time unit is one clock cycle $end\n$timescale " + ts + " $end\n";
  }
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
         (s.width > 1 ? " [" + std::to_string(s.width - 1) + ":0]" : "") + " $end\n";
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
  out("#" + std::to_string(cycle) + "\n");
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
