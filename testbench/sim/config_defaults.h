// What follows from the stages' specs (hw/stage_spec.h) and the elaborated
// netlist rather than being written by hand: the default configuration file
// (testbench/configs/default.json, `gpusim config --defaults`) and the stage
// and FIFO tables of docs/gpu-config.md (`gpusim config --markdown`).
// sim_config_defaults_test fails when the checked-in files differ from
// these; scripts/regenerate rewrites them.
#pragma once

#include <string>
#include <vector>

namespace gpusim {

// The pipeline's stage kinds and FIFO kinds in pipeline order, as a default
// GPU with every optional stage elaborates them, then any registered kind
// it left out, by name. Elaborates a GPU: call with no simulation running.
struct PipelineKinds {
  struct Fifo {
    std::string kind, writer, reader;  // writer "host" for the host
    bool per_unit = false;
  };
  std::vector<std::string> stages;
  std::vector<Fifo> fifos;
};
PipelineKinds pipeline_kinds();

// The default configuration: every key at its default, stages and FIFOs in
// pipeline order, each stage's cost with what one ii is spent on and why,
// each FIFO with its endpoints, as comments (the loader accepts them).
std::string default_config_text(const PipelineKinds& kinds);

// docs/gpu-config.md's tables: "stages" (stage, item, ii, latency, why) or
// "fifos" (FIFO, from → to, per unit); docs/architecture.md's "costs" (stage,
// busy per token, notes). std::invalid_argument for another name.
std::string markdown_table(const PipelineKinds& kinds, const std::string& name);

}  // namespace gpusim
