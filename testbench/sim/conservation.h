// The conservation ledger (docs/robustness.md, "Conservation"): after a run,
// the stages' counters must account for every item. Two kinds of rule:
//  - from the netlist alone, for every stage and FIFO: a FIFO delivered
//    every item it took; a stage read what its input FIFOs delivered and
//    wrote what its output FIFOs took (PipelineStage counts tokens_in and
//    tokens_out at every read and write);
//  - each stage's own rules (items in = items dropped + items out, counters
//    that must agree with the stage before it), which its spec declares in
//    its own files (StageSpec::conservation, hw/stage_spec.h); this ledger
//    runs them over a run's statistics.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hw/draw_state.h"
#include "hw/pipeline_counts.h"
#include "hw/trace_probe.h"

namespace gpusim {

// The rules over a Gpu::stats_json() dump of a one-frame run of `frame` on
// the netlist `netlist` (Topology::trace_tables()): one line per violated
// rule, naming the stage or FIFO and both sides' figures. A counter missing
// from the dump is a violation too. Takes the dump, not the GPU, so tests
// can check it on doctored counters.
std::vector<std::string> conservation_errors(const nlohmann::json& stats,
                                             const NetlistTables& netlist, const FrameState& frame);

// The spec's bookkeeping (docs/pipeline-spec.md, section 13) over a set of
// pipeline counters, named as golden::Stats::to_json() names them: one line
// per violated identity, empty when they hold.
std::vector<std::string> pipeline_count_errors(const PipelineCounts& counts);

}  // namespace gpusim
