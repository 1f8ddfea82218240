#include "stages/command_processor.h"

#include <string>

namespace gpusim {

CommandProcessor::CommandProcessor(sc_core::sc_module_name name, const GpuConfig& config,
                                   const FrameState& frame)
    : sc_core::sc_module(name),
      in("in"),
      out("out"),
      m_config(config),
      m_frame(frame),
      m_cost(config.stage("command_processor")),
      m_cycle(config.cycle().value()),
      m_latency(clock_cycles(m_cost.latency)) {
  SC_HAS_PROCESS(CommandProcessor);
  SC_THREAD(run);
}

void CommandProcessor::run() {
  for (;;) {
    const Command cmd = in->read();
    ++m_tokens_in;
    switch (cmd.kind) {
      case PacketKind::work:
        // A draw id outside the frame's registers is a driver bug: stop here
        // rather than let fetch read garbage.
        if (cmd.draw_id >= m_frame.draws.size()) {
          SC_REPORT_ERROR("gpusim/command_processor",
                          (std::string(name()) + ": draw " + std::to_string(cmd.draw_id) +
                           " does not exist (" + std::to_string(m_frame.draws.size()) + " draws)")
                              .c_str());
        }
        ++m_draws;
        break;
      case PacketKind::clear:
        ++m_clears;
        break;
      case PacketKind::end_of_frame:
        ++m_frames;
        break;
    }
    m_busy_cycles += m_cost.ii;
    sc_core::wait(clock_cycles(m_cost.ii));
    out->write(cmd, sc_core::sc_time_stamp() + m_latency);
    ++m_tokens_out;
  }
}

}  // namespace gpusim
