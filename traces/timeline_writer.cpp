#include "traces/timeline_writer.h"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <cstring>

namespace gpusim {

std::string json_quote(const std::string& s) {
  std::string q = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      q += '\\';
      q += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      q += buf;
    } else {
      q += c;
    }
  }
  return q + "\"";
}

namespace {

// Appending into a fixed line buffer: events are written by the million, so
// they are formatted without temporaries or printf.
class Line {
 public:
  Line& operator<<(const char* s) { return append(s, std::strlen(s)); }
  Line& operator<<(const std::string& s) { return append(s.data(), s.size()); }
  Line& operator<<(uint64_t v) {
    m_n = static_cast<size_t>(std::to_chars(m_buf + m_n, m_buf + kMax, v).ptr - m_buf);
    return *this;
  }
  Line& operator<<(int v) {
    m_n = static_cast<size_t>(std::to_chars(m_buf + m_n, m_buf + kMax, v).ptr - m_buf);
    return *this;
  }
  // `ns` nanoseconds as microseconds with three decimals ("12.345", "2.000").
  Line& us(uint64_t ns) {
    *this << ns / 1000;
    const char digits[4] = {'.', static_cast<char>('0' + ns / 100 % 10),
                            static_cast<char>('0' + ns / 10 % 10),
                            static_cast<char>('0' + ns % 10)};
    return append(digits, 4);
  }
  const char* data() const { return m_buf; }
  size_t size() const { return m_n; }

 private:
  static constexpr size_t kMax = 1024;
  Line& append(const char* s, size_t n) {
    n = std::min(n, kMax - m_n);
    std::memcpy(m_buf + m_n, s, n);
    m_n += n;
    return *this;
  }
  char m_buf[kMax];
  size_t m_n = 0;
};

}  // namespace

uint64_t TimelineWriter::nanoseconds(uint64_t cycles, uint64_t cycle_ps) {
  const unsigned __int128 ps = static_cast<unsigned __int128>(cycles) * cycle_ps;
  return static_cast<uint64_t>((ps + 500) / 1000);
}

std::string TimelineWriter::microseconds(uint64_t cycles, uint64_t cycle_ps) {
  Line l;
  l.us(nanoseconds(cycles, cycle_ps));
  return std::string(l.data(), l.size());
}

TimelineWriter::TimelineWriter(const std::string& path, uint64_t cycle_ps,
                               const std::string& other_data)
    : m_file(path), m_cycle_ps(cycle_ps) {
  m_file.write("{\"displayTimeUnit\": \"ns\",\n\"otherData\": " + other_data +
               ",\n\"traceEvents\": [\n");
}

void TimelineWriter::event(const char* text, size_t n) {
  if (m_events++) m_file.write(",\n", 2);
  m_file.write(text, n);
}

void TimelineWriter::event(const std::string& text) {
  event(text.data(), text.size());
}

void TimelineWriter::process_name(int pid, const std::string& name) {
  event("{\"ph\": \"M\", \"name\": \"process_name\", \"ts\": 0, \"pid\": " + std::to_string(pid) +
        ", \"tid\": 0, \"args\": {\"name\": " + json_quote(name) + "}}");
}

void TimelineWriter::thread_name(int pid, int tid, const std::string& name, int sort_index) {
  const std::string ids =
      "\"ts\": 0, \"pid\": " + std::to_string(pid) + ", \"tid\": " + std::to_string(tid);
  event("{\"ph\": \"M\", \"name\": \"thread_name\", " + ids +
        ", \"args\": {\"name\": " + json_quote(name) + "}}");
  event("{\"ph\": \"M\", \"name\": \"thread_sort_index\", " + ids +
        ", \"args\": {\"sort_index\": " + std::to_string(sort_index) + "}}");
}

void TimelineWriter::complete(int pid, int tid, const std::string& name, const char* category,
                              uint64_t cycle_in, uint64_t cycle_out, const std::string& args_json) {
  // Names are ours (stage names, numbers): nothing to escape.
  Line l;
  l << "{\"ph\": \"X\", \"name\": \"" << name << "\", \"cat\": \"" << category << "\", \"ts\": ";
  // Both ends rounded once, the duration their difference: slices that
  // touch in cycles touch in the text, and none overlaps its successor.
  const uint64_t ns_in = nanoseconds(cycle_in, m_cycle_ps);
  l.us(ns_in) << ", \"dur\": ";
  l.us(nanoseconds(cycle_out, m_cycle_ps) - ns_in)
      << ", \"pid\": " << pid << ", \"tid\": " << tid << ", \"args\": {\"cycle_in\": " << cycle_in
      << ", \"cycle_out\": " << cycle_out;
  if (!args_json.empty()) l << ", " << args_json;
  l << "}}";
  event(l.data(), l.size());
}

void TimelineWriter::counter(int pid, int tid, const std::string& name, uint64_t cycle,
                             uint64_t value) {
  Line l;
  l << "{\"ph\": \"C\", \"name\": \"" << name << "\", \"ts\": ";
  l.us(nanoseconds(cycle, m_cycle_ps)) << ", \"pid\": " << pid << ", \"tid\": " << tid
                                       << ", \"args\": {\"occupancy\": " << value << "}}";
  event(l.data(), l.size());
}

void TimelineWriter::finish() {
  m_file.write("\n]}\n");
  m_file.close();
}

}  // namespace gpusim
