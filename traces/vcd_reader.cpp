#include "traces/vcd_reader.h"

#include <cerrno>
#include <cstring>
#include <fstream>

#include "hw/input_error.h"

namespace gpusim {
namespace {

// Whitespace-separated tokens with their line numbers, read through a
// buffer (an istream >> string per token costs several times more).
class Tokens {
 public:
  Tokens(const std::string& path, uint64_t offset, uint64_t line) : m_path(path), m_line(line) {
    m_in.open(path, std::ios::binary);
    if (!m_in) throw InputError(path + ": cannot open: " + std::strerror(errno));
    m_in.seekg(static_cast<std::streamoff>(offset));
    m_offset = offset;
  }

  // The next token into `tok`; false at the end of the file.
  bool next(std::string& tok) {
    tok.clear();
    int c;
    while ((c = get()) != EOF && is_space(c)) {
    }
    if (c == EOF) return false;
    m_token_line = m_line;
    do {
      tok += static_cast<char>(c);
    } while ((c = get()) != EOF && !is_space(c));
    return true;
  }

  // Skips tokens up to and including "$end".
  void skip_to_end(const char* what) {
    std::string tok;
    while (next(tok)) {
      if (tok == "$end") return;
    }
    fail(std::string("unterminated ") + what);
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(m_path + ": line " + std::to_string(m_token_line) + ": " + what);
  }
  uint64_t offset() const { return m_offset; }
  uint64_t line() const { return m_line; }

 private:
  static bool is_space(int c) { return c == ' ' || c == '\n' || c == '\t' || c == '\r'; }
  int get() {
    if (m_pos == m_len) {
      m_in.read(m_buf, sizeof m_buf);
      m_len = static_cast<size_t>(m_in.gcount());
      m_pos = 0;
      if (m_len == 0) return EOF;
    }
    const int c = static_cast<unsigned char>(m_buf[m_pos++]);
    ++m_offset;
    if (c == '\n') ++m_line;
    return c;
  }

  std::string m_path;
  std::ifstream m_in;
  char m_buf[1 << 16];
  size_t m_pos = 0, m_len = 0;
  uint64_t m_offset = 0;
  uint64_t m_line = 1, m_token_line = 1;
};

uint64_t parse_time(const Tokens& t, const std::string& tok) {
  if (tok.size() < 2 || tok.size() > 21) t.fail("bad timestamp \"" + tok + "\"");
  uint64_t v = 0;
  for (size_t i = 1; i < tok.size(); ++i) {
    if (tok[i] < '0' || tok[i] > '9') t.fail("bad timestamp \"" + tok + "\"");
    const uint64_t d = static_cast<uint64_t>(tok[i] - '0');
    if (v > (UINT64_MAX - d) / 10) t.fail("timestamp out of range \"" + tok + "\"");
    v = v * 10 + d;
  }
  return v;
}

// Binary digits to a value; any x or z bit makes it unknown.
uint64_t parse_bits(const Tokens& t, const std::string& digits) {
  if (digits.empty()) t.fail("empty vector value");
  uint64_t v = 0;
  bool unknown = false;
  for (const char c : digits) {
    if (c == '0' || c == '1') {
      if (v >> 63) t.fail("vector value wider than 64 bits");
      v = v << 1 | static_cast<uint64_t>(c - '0');
    } else if (c == 'x' || c == 'X' || c == 'z' || c == 'Z') {
      unknown = true;
    } else {
      t.fail("bad vector value \"b" + digits + "\"");
    }
  }
  return unknown ? VcdReader::kUnknown : v;
}

// A $timescale ("1 ns", "100ps") in femtoseconds; 0 when not one.
uint64_t timescale_fs(const std::string& text) {
  static const char* const units[] = {"fs", "ps", "ns", "us", "ms", "s"};
  size_t n = 0;
  while (n < text.size() && text[n] >= '0' && text[n] <= '9') ++n;
  const std::string m = text.substr(0, n);
  std::string unit = text.substr(n);
  if (!unit.empty() && unit[0] == ' ') unit.erase(0, 1);
  if (m != "1" && m != "10" && m != "100") return 0;
  uint64_t fs = std::stoull(m);
  for (const char* u : units) {
    if (unit == u) return fs;
    fs *= 1000;
  }
  return 0;
}

}  // namespace

VcdReader::VcdReader(const std::string& path, uint64_t cycle_ps) : m_path(path) {
  Tokens t(path, 0, 1);
  std::vector<std::string> scopes;
  std::string tok;
  bool any = false, cycles_already = false;
  while (t.next(tok)) {
    any = true;
    if (tok == "$enddefinitions") {
      t.skip_to_end("$enddefinitions");
      if (!scopes.empty()) t.fail("$enddefinitions inside scope " + scopes.back());
      if (cycle_ps != 0 && !cycles_already) {
        const uint64_t unit = timescale_fs(m_timescale);
        if (unit == 0) t.fail("$timescale \"" + m_timescale + "\" is not a time unit");
        if (cycle_ps * 1000 % unit != 0) {
          t.fail("the clock period, " + std::to_string(cycle_ps) +
                 " ps, is not a whole number of $timescale units (" + m_timescale + ")");
        }
        m_per_time = cycle_ps * 1000 / unit;
      }
      m_body_offset = t.offset();
      m_body_line = t.line();
      return;
    }
    if (tok == "$scope") {
      std::string type, name;
      if (!t.next(type) || !t.next(name)) t.fail("unterminated $scope");
      scopes.push_back(name);
      t.skip_to_end("$scope");
    } else if (tok == "$upscope") {
      if (scopes.empty()) t.fail("$upscope without a $scope");
      scopes.pop_back();
      t.skip_to_end("$upscope");
    } else if (tok == "$var") {
      std::string type, width, id, name;
      if (!t.next(type) || !t.next(width) || !t.next(id) || !t.next(name)) {
        t.fail("unterminated $var");
      }
      VcdSignal s;
      std::string scope;
      for (size_t i = 0; i < scopes.size(); ++i) scope += (i ? "." : "") + scopes[i];
      s.scope = scope;
      s.name = name;
      char* end = nullptr;
      const unsigned long w = std::strtoul(width.c_str(), &end, 10);
      if (width.empty() || *end != '\0' || w == 0 || w > 64) {
        t.fail("$var " + name + ": width \"" + width + "\" is not in 1..64");
      }
      s.width = static_cast<unsigned>(w);
      m_ids[id].push_back(m_signals.size());
      m_signals.push_back(std::move(s));
      t.skip_to_end("$var");  // an optional bit range, e.g. [4:0]
    } else if (tok == "$timescale") {
      std::string part;
      while (t.next(part) && part != "$end") m_timescale += (m_timescale.empty() ? "" : " ") + part;
    } else if (tok == "$comment") {
      std::string text, part;
      while (t.next(part) && part != "$end") text += (text.empty() ? "" : " ") + part;
      if (text.find("one time unit is one clock cycle") != std::string::npos) cycles_already = true;
    } else if (tok[0] == '$') {
      t.skip_to_end(tok.c_str());  // $date, $version
    } else {
      t.fail("unexpected \"" + tok + "\" in the header");
    }
  }
  if (!any) throw InputError(path + ": empty file, not a value change dump");
  t.fail("no $enddefinitions: truncated, or not a value change dump");
}

std::optional<size_t> VcdReader::find(const std::string& scope, const std::string& name) const {
  for (size_t i = 0; i < m_signals.size(); ++i) {
    if (m_signals[i].scope == scope && m_signals[i].name == name) return i;
  }
  return std::nullopt;
}

void VcdReader::for_each_change(const std::function<void(uint64_t, size_t, uint64_t)>& fn) const {
  Tokens t(m_path, m_body_offset, m_body_line);
  std::string tok, id;
  uint64_t time = 0;
  const auto emit = [&](const std::string& code, uint64_t value) {
    const auto it = m_ids.find(code);
    if (it == m_ids.end()) t.fail("value change for undeclared identifier \"" + code + "\"");
    for (const size_t s : it->second) fn(time, s, value);
  };
  while (t.next(tok)) {
    const char c = tok[0];
    if (c == '#') {
      const uint64_t next = parse_time(t, tok);
      if (next < time * m_per_time)
        t.fail("time goes backwards: " + tok + " after #" + std::to_string(time * m_per_time));
      if (next % m_per_time != 0) {
        t.fail("time " + tok + " is not on a clock cycle boundary (" + std::to_string(m_per_time) +
               " time units per cycle)");
      }
      time = next / m_per_time;
    } else if (c == '0' || c == '1' || c == 'x' || c == 'X' || c == 'z' || c == 'Z') {
      if (tok.size() < 2) t.fail("scalar change \"" + tok + "\" without an identifier");
      emit(tok.substr(1), c == '0' ? 0 : c == '1' ? 1 : kUnknown);
    } else if (c == 'b' || c == 'B') {
      if (!t.next(id)) t.fail("vector change \"" + tok + "\" without an identifier");
      emit(id, parse_bits(t, tok.substr(1)));
    } else if (c == 'r' || c == 'R') {
      // Real values are not part of a trace; read as unknown rather than fail.
      if (!t.next(id)) t.fail("real change \"" + tok + "\" without an identifier");
      emit(id, kUnknown);
    } else if (tok == "$comment") {
      t.skip_to_end("$comment");
    } else if (c == '$') {
      // $dumpvars, $dumpall, $dumpon, $dumpoff and their $end: the values
      // inside are ordinary changes.
    } else {
      t.fail("unexpected \"" + tok + "\"");
    }
  }
}

std::vector<std::vector<std::pair<uint64_t, uint64_t>>> VcdReader::changes() const {
  std::vector<std::vector<std::pair<uint64_t, uint64_t>>> out(m_signals.size());
  for_each_change([&](uint64_t time, size_t s, uint64_t v) { out[s].emplace_back(time, v); });
  return out;
}

std::vector<VcdReader::Histogram> VcdReader::histograms(uint64_t start, uint64_t end) const {
  std::vector<Histogram> out(m_signals.size());
  struct Held {
    bool known = false;
    uint64_t value = 0, since = 0;
  };
  std::vector<Held> held(m_signals.size());
  const auto close = [&](size_t s, uint64_t until) {
    const Held& h = held[s];
    if (!h.known) return;
    const uint64_t a = std::max(h.since, start), b = std::min(until, end);
    if (b > a) out[s][h.value] += b - a;
  };
  for_each_change([&](uint64_t time, size_t s, uint64_t v) {
    close(s, time);
    held[s] = {true, v, time};
  });
  for (size_t s = 0; s < m_signals.size(); ++s) close(s, end);
  return out;
}

}  // namespace gpusim
