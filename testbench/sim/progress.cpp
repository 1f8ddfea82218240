#include "testbench/sim/progress.h"

#include <sys/ioctl.h>
#include <unistd.h>

#include <cstdio>

namespace gpusim {
namespace {

// A terminal line is redrawn at most this often: faster is flicker.
constexpr double kTerminalInterval = 0.2;

double seconds(std::chrono::steady_clock::duration d) {
  return std::chrono::duration<double>(d).count();
}

std::string format_seconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f s", s);
  return buf;
}

}  // namespace

Progress::Mode Progress::mode_for(bool force, bool quiet, bool terminal) {
  if (quiet) return Mode::quiet;
  if (terminal) return Mode::terminal;
  return force ? Mode::lines : Mode::quiet;
}

Progress::Progress(Mode mode, std::ostream& out, double interval)
    : m_mode(mode), m_out(out), m_interval(interval) {
  // A line wider than the terminal wraps, and \r then returns only to the
  // start of its last row: terminal lines are cut to the width.
  winsize size{};
  if (mode == Mode::terminal && ioctl(STDERR_FILENO, TIOCGWINSZ, &size) == 0 && size.ws_col > 1) {
    m_columns = size.ws_col - 1u;
  }
}

Progress::~Progress() {
  interrupt();
}

void Progress::begin(const std::string& phase, const std::string& what) {
  end();
  m_phase = phase;
  m_phase_start = Clock::now();
  show(what + " ...");
}

void Progress::update(const std::string& state, bool now) {
  if (m_mode == Mode::quiet || m_phase.empty()) return;
  const double interval = m_mode == Mode::terminal ? kTerminalInterval : m_interval;
  if (!now && seconds(Clock::now() - m_last_shown) < interval) return;
  show(state);
}

void Progress::end() {
  if (m_phase.empty()) return;
  const double s = seconds(Clock::now() - m_phase_start);
  m_phases.emplace_back(m_phase, s);
  if (m_mode == Mode::lines) show("done in " + format_seconds(s));
  clear_terminal_line();
  m_phase.clear();
}

void Progress::interrupt() {
  clear_terminal_line();
  m_phase.clear();
}

std::string Progress::wall_summary() const {
  std::string out;
  for (const auto& [phase, s] : m_phases) {
    out += (out.empty() ? "" : ", ") + phase + " " + format_seconds(s);
  }
  return out + (out.empty() ? "" : "; ") + "total " +
         format_seconds(seconds(Clock::now() - m_created));
}

void Progress::show(const std::string& text) {
  if (m_mode == Mode::quiet) return;
  m_last_shown = Clock::now();
  std::string line = m_phase + ": " + text;
  // stdout first: when both go to one log, its lines stay in order.
  std::fflush(stdout);
  if (m_mode == Mode::lines) {
    m_out << line << std::endl;
    return;
  }
  if (line.size() > m_columns) line.resize(m_columns);
  // Spaces over what is left of a longer previous line.
  const size_t pad = m_terminal_width > line.size() ? m_terminal_width - line.size() : 0;
  m_out << '\r' << line << std::string(pad, ' ') << std::flush;
  m_terminal_width = line.size();
}

void Progress::clear_terminal_line() {
  if (m_mode != Mode::terminal || m_terminal_width == 0) return;
  m_out << '\r' << std::string(m_terminal_width, ' ') << '\r' << std::flush;
  m_terminal_width = 0;
}

}  // namespace gpusim
