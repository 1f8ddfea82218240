#include "stages/command_processor.h"

#include <string>

namespace gpusim {

const StageSpec& CommandProcessor::spec() {
  static const StageSpec s{"command_processor", StagePlacement::front_end,
                           /*optional=*/false,  {/*ii=*/1, /*latency=*/2},
                           "command",           "decode one command word",
                           "commands read",     "commands forwarded to vertex fetch",
                           {"commands"}};
  return s;
}
GPUSIM_REGISTER_STAGE(CommandProcessor);

CommandProcessor::CommandProcessor(sc_core::sc_module_name name, const GpuConfig& config,
                                   const FrameState& frame)
    : PipelineStage(name, spec(), -1, config, frame), in("in"), out("out") {
  SC_HAS_PROCESS(CommandProcessor);
  SC_THREAD(run);
}

void CommandProcessor::run() {
  for (;;) {
    const Command cmd = receive(in);
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
    work(m_cost.ii);
    emit(out, cmd);
  }
}

}  // namespace gpusim
