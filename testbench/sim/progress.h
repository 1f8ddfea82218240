// What gpusim is doing, on stderr, and how long each phase took, for the
// summary (docs/robustness.md, "Progress"). A command is a sequence of named
// phases (load, build, simulate, read back, check, write); each is timed on
// the host's clock whatever the mode, so the summary can report where the
// wall time went, and shown according to the mode:
//  - terminal: one line rewritten in place (\r), at most 5 times a second,
//    cleared when a phase ends so that stdout's summary starts on a clean
//    line;
//  - lines: full lines, for logs: one when a phase starts, one when it ends,
//    and its state at most once per interval (1 s by default) in between;
//  - quiet: nothing.
// Wall times are for people: they never reach stats.json, and nothing here
// feeds back into the simulation (the simulate phase's state is read by a
// thread that wakes on simulated time only, testbench/sim/gpu_run.cpp).
#pragma once

#include <chrono>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace gpusim {

class Progress {
 public:
  enum class Mode { quiet, terminal, lines };
  // --progress forces it, --quiet silences it; otherwise it is shown when
  // stderr is a terminal.
  static Mode mode_for(bool force, bool quiet, bool terminal);

  // `interval`: seconds between state lines in lines mode.
  explicit Progress(Mode mode, std::ostream& out, double interval = 1.0);
  // interrupt()s.
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  // Whether anything is shown (run_gpu adds its reporting thread only then).
  bool shown() const { return m_mode != Mode::quiet; }

  // Ends the current phase, if any, and starts `phase`; `what` says what it
  // is doing ("reading scene.json").
  void begin(const std::string& phase, const std::string& what);
  // The current phase's state ("12 of 40 primitives assembled, ..."): shown
  // when the mode's interval has passed since the last line, or at once when
  // `now` (a step the user should see, such as a mesh being imported).
  void update(const std::string& state, bool now = false);
  // Ends the current phase and records its wall time.
  void end();
  // Before an error message: clears a line left on the terminal; the phase
  // is not recorded.
  void interrupt();

  // Every ended phase and its wall time, in order (a phase begun twice
  // appears twice).
  const std::vector<std::pair<std::string, double>>& phases() const { return m_phases; }
  // "load 0.412 s, build 0.020 s, ...; total 2.310 s", the total being the
  // time since construction.
  std::string wall_summary() const;

 private:
  using Clock = std::chrono::steady_clock;
  void show(const std::string& text);
  void clear_terminal_line();

  Mode m_mode;
  std::ostream& m_out;
  double m_interval;
  Clock::time_point m_created = Clock::now();
  std::string m_phase;  // empty between phases
  Clock::time_point m_phase_start;
  Clock::time_point m_last_shown;
  size_t m_terminal_width = 0;  // characters of the line on the terminal
  size_t m_columns = 79;        // the terminal's width, less one
  std::vector<std::pair<std::string, double>> m_phases;
};

}  // namespace gpusim
