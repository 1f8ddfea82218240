// What a pipeline stage is, declared once in the stage's own files (gem5's
// SimObject params, VCML's properties): its kind, where it sits, its default
// cost and why, what its token counters count, and the FIFOs it reads. The
// stage's .cpp registers the spec at static initialisation:
//
//   const StageSpec& Clipper::spec() {
//     static const StageSpec s{"clipper", StagePlacement::front_end, ...};
//     return s;
//   }
//   GPUSIM_REGISTER_STAGE(Clipper);
//
// and everything that lists the pipeline's parts follows from the registry:
// the configuration's stage and FIFO keys and their defaults
// (hw/gpu_config.h), `gpusim config --defaults`, the generated tables of
// docs/gpu-config.md and testbench/configs/default.json, and the netlist's
// check that it elaborated what the configuration names. Nothing in hw/
// names a stage; the order of the pipeline is the elaborated netlist's
// (stages/topology.h), the registry's is by kind.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "hw/gpu_config.h"

namespace gpusim {

enum class StagePlacement {
  front_end,  // one instance, before the units
  per_unit,   // one instance per raster unit, named <kind>_<unit>
  shared,     // one instance the units feed (the resolve)
};
const char* to_string(StagePlacement p);

struct StageSpec {
  std::string kind;  // configuration key, stats.json and trace name: "tile_rasterizer"
  StagePlacement placement = StagePlacement::front_end;
  // Elaborated only in frames that need it; its keys are accepted always.
  bool optional = false;
  StageCost cost;           // the default ii and latency
  std::string item;         // what one ii is spent on: "stamp"
  std::string cost_reason;  // why the default cost, one line
  std::string tokens_in;    // what the tokens_in counter counts: "setup packets read"
  std::string tokens_out;
  // The FIFO kinds the stage reads, by the name of its input port's FIFO
  // (the key of fifo_depths): a FIFO belongs to its reader, so putting a
  // stage in front of another renames nothing.
  std::vector<std::string> inputs;
};

class StageRegistry {
 public:
  // Registers a spec; a kind or FIFO kind registered twice is a programming
  // error (std::logic_error).
  static void add(const StageSpec& spec);
  // nullptr when no stage of that kind is linked in.
  static const StageSpec* find(std::string_view kind);
  // Every registered spec, by kind.
  static std::vector<const StageSpec*> all();
  // Every FIFO kind some stage reads, sorted.
  static std::vector<std::string> fifo_kinds();
  // Stage kinds and FIFO kinds that a frame may leave out: the optional
  // stages and the FIFOs they read. Sorted.
  static std::vector<std::string> optional_kinds();
};

// Registers a stage's spec when the program starts.
struct StageRegistration {
  explicit StageRegistration(const StageSpec& spec) { StageRegistry::add(spec); }
};

#define GPUSIM_REGISTER_STAGE(Class)                                           \
  static const ::gpusim::StageRegistration gpusim_stage_registration_##Class { \
    Class::spec()                                                              \
  }

}  // namespace gpusim
