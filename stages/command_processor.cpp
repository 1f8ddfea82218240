#include "stages/command_processor.h"

#include <string>

namespace gpusim {

namespace {

// Conservation (testbench/sim/conservation.h): how its counters balance.
void conserve(ConservationLedger& l) {
  const ConservationLedger::Frame& f = l.frame();
  // Commands in = commands out.
  l.equal("draws", l.get("draws"), "draws in the frame", f.draws);
  l.equal("frames", l.get("frames"), "frames run", 1);
  l.equal("clears", l.get("clears"), "clears in the frame", f.clears);
  l.equal("tokens_in", l.get("tokens_in"), "draws + clears + frames",
          l.get("draws") + l.get("clears") + l.get("frames"));
  l.equal("tokens_out", l.get("tokens_out"), "tokens_in", l.get("tokens_in"));
}

}  // namespace

const StageSpec& CommandProcessor::spec() {
  static const StageSpec s{
      "command_processor",
      StagePlacement::front_end,
      /*optional=*/false,
      {/*ii=*/1, /*latency=*/2},
      "command",
      "decode one command word",
      "commands read",
      "commands forwarded to vertex fetch",
      {"commands"},
      &conserve,
      StageTrace{TraceItem::draw, {}, FragmentSite::none},
      {{"", "`ii` per command", "A clear is one command, whatever it clears."}}};
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
