#include "testbench/sim/watchdog.h"

#include <algorithm>
#include <sstream>

namespace gpusim {
namespace {

// Items a FIFO's reader could take: none when a test fault withholds them.
size_t visible(const FifoChannel& f) {
  return f.withheld() ? 0 : f.occupancy();
}

std::string held(const Topology::FifoNode& f) {
  return f.name + " (" + std::to_string(f.channel->occupancy()) + "/" +
         std::to_string(f.channel->capacity()) + (f.channel->withheld() ? ", withheld" : "") + ")";
}

}  // namespace

uint64_t progress_count(const Gpu& gpu) {
  uint64_t n = gpu.topology().items_moved();
  const Memory& m = gpu.memory();
  for (unsigned i = 0; i < m.num_clients(); ++i) n += m.client_stats(i).requests;
  return n;
}

bool transfers_in_flight(const Gpu& gpu, sc_core::sc_time memory_latency) {
  return gpu.memory().bus_free() + memory_latency > sc_core::sc_time_stamp();
}

sc_core::sc_event_or_list activity_events(const Topology& topology) {
  sc_core::sc_event_or_list events;
  for (const Topology::FifoNode& f : topology.fifos()) {
    events |= f.channel->written_event();
    events |= f.channel->read_event();
  }
  return events;
}

void wait_for_activity(const Topology& topology, const sc_core::sc_event_or_list& events) {
  for (const Topology::FifoNode& f : topology.fifos()) f.channel->watch(true);
  sc_core::wait(events);
  for (const Topology::FifoNode& f : topology.fifos()) f.channel->watch(false);
}

NetlistSample sample(const Topology& topology) {
  NetlistSample s;
  for (const Topology::FifoNode& f : topology.fifos()) {
    const FifoStats st = f.channel->stats();
    s.reader_blocked.push_back(st.reader_blocked);
    s.writer_blocked.push_back(st.writer_blocked);
  }
  s.at = sc_core::sc_time_stamp();
  return s;
}

std::vector<StageState> stage_states(const Topology& topology, const NetlistSample& before,
                                     const NetlistSample& after) {
  const auto grew = [](const std::vector<sc_core::sc_time>& a,
                       const std::vector<sc_core::sc_time>& b,
                       size_t i) { return i < a.size() && i < b.size() && b[i] > a[i]; };
  std::vector<StageState> states;
  for (const Topology::StageNode& s : topology.stages()) {
    StageState state = StageState::busy;
    // Blocked reading an empty FIFO: only a write can wake it. (Blocked on a
    // FIFO that holds items: waiting for one still in flight, so busy.)
    for (size_t f : s.inputs) {
      if (grew(before.reader_blocked, after.reader_blocked, f) &&
          visible(*topology.fifos()[f].channel) == 0) {
        state = StageState::waiting_on_input;
      }
    }
    for (size_t f : s.outputs) {
      if (grew(before.writer_blocked, after.writer_blocked, f))
        state = StageState::waiting_on_output;
    }
    states.push_back(state);
  }
  return states;
}

std::string fifo_report(const Topology& topology) {
  std::ostringstream os;
  os << "  FIFOs (items held/depth; items written, read):";
  for (const Topology::FifoNode& f : topology.fifos()) {
    const FifoStats s = f.channel->stats();
    os << "\n    " << f.name << ": " << f.channel->occupancy() << "/" << f.channel->capacity()
       << "; " << s.written << " written, " << s.read << " read";
    if (s.injected_stalls > 0) os << "; " << s.injected_stalls << " injected stalls";
    if (f.channel->withheld()) os << "; withheld from its reader (test fault)";
  }
  return os.str();
}

std::string state_report(const Topology& topology, const NetlistSample& before,
                         const NetlistSample& after) {
  const std::vector<StageState> states = stage_states(topology, before, after);
  const auto& fifos = topology.fifos();
  std::string busy;
  bool all_on_input = true;
  std::ostringstream lines;
  lines << "  stages:";
  for (size_t i = 0; i < topology.stages().size(); ++i) {
    const Topology::StageNode& s = topology.stages()[i];
    std::string text = "busy";
    for (size_t f : s.inputs) {
      // Blocked on a FIFO that holds items: the next one is still in flight.
      if (after.reader_blocked.size() > f && after.reader_blocked[f] > before.reader_blocked[f] &&
          visible(*fifos[f].channel) > 0) {
        text = "busy (receiving: the next item in " + held(fifos[f]) + " is in flight)";
      }
    }
    if (states[i] == StageState::waiting_on_input) {
      for (size_t f : s.inputs) text = "waiting on input " + held(fifos[f]);
    } else if (states[i] == StageState::waiting_on_output) {
      for (size_t f : s.outputs) {
        if (fifos[f].channel->occupancy() == fifos[f].channel->capacity())
          text = "waiting on output " + held(fifos[f]);
      }
      if (text == "busy") text = "waiting on output";
    }
    const std::string name = s.stage->basename();
    if (states[i] == StageState::busy) busy += (busy.empty() ? "" : ", ") + name;
    if (states[i] != StageState::waiting_on_input) all_on_input = false;
    lines << "\n    " << name << ": " << text << "; " << s.stage->tokens_in() << " tokens in, "
          << s.stage->tokens_out() << " out";
  }
  bool all_empty = true;
  for (const Topology::FifoNode& f : fifos) all_empty = all_empty && f.channel->occupancy() == 0;

  std::string verdict;
  if (!busy.empty()) {
    verdict = "busy without moving an item: " + busy +
              " (a stage stuck, or one item costing more than watchdog_cycles, which the "
              "configuration can raise)";
  } else if (all_on_input && all_empty) {
    verdict =
        "every stage waits for input and every FIFO is empty: an item was lost (the "
        "frame's end never reached every ROP)";
  } else {
    verdict =
        "every stage waits on a FIFO, readers on empty ones and writers on full ones: a "
        "deadlock";
  }
  return verdict + "\n" + lines.str() + "\n" + fifo_report(topology);
}

Watchdog::Watchdog(sc_core::sc_module_name name, const Gpu& gpu, const GpuConfig& config)
    : sc_core::sc_module(name), m_gpu(gpu), m_config(config) {
  SC_HAS_PROCESS(Watchdog);
  SC_THREAD(run);
}

void Watchdog::run() {
  for (;;) {
    watch_frame();
    if (fired()) return;
    sc_core::wait(m_gpu.reset_event());  // the next frame
  }
}

void Watchdog::watch_frame() {
  const sc_core::sc_time start = sc_core::sc_time_stamp();
  const Topology& topology = m_gpu.topology();
  const uint64_t limit = m_config.watchdog_cycles;
  const sc_core::sc_time cycle = m_config.cycle();
  const sc_core::sc_time window = m_config.cycles(limit);
  const sc_core::sc_time period = m_config.cycles(std::max<uint64_t>(1, limit / 4));
  const sc_core::sc_time memory_latency = m_config.cycles(m_config.memory.latency);
  const sc_core::sc_event_or_list activity = activity_events(topology);
  uint64_t last = progress_count(m_gpu);
  sc_core::sc_time last_progress = sc_core::sc_time_stamp();
  NetlistSample previous = sample(topology);
  for (;;) {
    sc_core::wait(period, m_gpu.unit_done_events());
    if (m_gpu.frame_done()) return;
    const sc_core::sc_time now = sc_core::sc_time_stamp();
    const NetlistSample current = sample(topology);
    const uint64_t count = progress_count(m_gpu);
    // Progress: an item moved, a memory request was made, or transfers are
    // still in flight.
    if (count != last || transfers_in_flight(m_gpu, memory_latency)) {
      last = count;
      last_progress = now;
      previous = current;
      continue;
    }
    const std::vector<StageState> states = stage_states(topology, previous, current);
    const bool any_busy = std::find(states.begin(), states.end(), StageState::busy) != states.end();
    if (!any_busy) {
      // Every stage waits on a FIFO: only an item moving could change that,
      // and nothing is left to move one. Stop counting so the kernel runs
      // out of events (run_gpu reports the deadlock); resume if one moves.
      wait_for_activity(topology, activity | m_gpu.unit_done_events());
      if (m_gpu.frame_done()) return;
      last = progress_count(m_gpu);
      last_progress = sc_core::sc_time_stamp();
      previous = sample(topology);
      continue;
    }
    if (now - last_progress < window) {
      previous = current;
      continue;
    }
    std::ostringstream head;
    head << "watchdog: no item moved through any FIFO or the memory for "
         << static_cast<uint64_t>((now - last_progress) / cycle) << " cycles (watchdog_cycles "
         << limit << "; last progress by cycle "
         << static_cast<uint64_t>((last_progress - start) / cycle) << ", now cycle "
         << static_cast<uint64_t>((now - start) / cycle) << "): ";
    m_report = head.str() + state_report(topology, previous, current);
    // SystemC reports every sc_stop() as an info line on stdout ("Simulation
    // stopped by user."); the report above says why it stopped.
    sc_core::sc_report_handler::set_actions("/OSCI/SystemC", sc_core::SC_INFO,
                                            sc_core::SC_DO_NOTHING);
    sc_core::sc_stop();
    return;
  }
}

}  // namespace gpusim
