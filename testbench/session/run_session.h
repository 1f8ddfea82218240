// `gpusim run` as a library: a scene through the cycle model, its frame,
// PNG and stats.json (and a trace) written together, and with `check` the
// golden model's frame and counters compared bit for bit. The command line
// parses its options into a RunRequest and prints the RunOutcome.
#pragma once

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "hw/gpu_config.h"
#include "hw/pipeline_counts.h"
#include "testbench/golden/golden_model.h"
#include "testbench/scene/scene.h"
#include "testbench/sim/gpu_run.h"
#include "testbench/sim/progress.h"

namespace gpusim {

struct RunRequest {
  std::string scene;  // the scene file
  GpuConfig config;
  std::string out_dir = "out";
  bool check = false;       // render the golden model too and compare
  bool lockstep = false;    // no temporal decoupling
  uint64_t memory_mib = 0;  // the memory limit; 0: the machine's
  // A trace (docs/traces.md) into trace_dir when set, with its filters.
  std::string trace_dir, trace_stages, trace_window, trace_prims;
  std::string trace_formats;  // empty: every format
  // Called with a line for stderr as soon as it is known (the automatic
  // camera's note, before the simulation starts).
  std::function<void(const std::string&)> note;
};

// The first pixel whose colour or depth differs, with the primitive that
// last wrote it in each model.
struct PixelDifference {
  int x = 0, y = 0;
  std::string cycle, golden;  // "colour (r, g, b, a) depth d"
  int64_t cycle_writer = -1, golden_writer = -1;
};

struct CheckReport {
  std::optional<PixelDifference> pixel;  // none: every pixel equal
  std::vector<CountDifference> counts;   // a: the cycle model, b: the golden model
  bool ok() const { return !pixel && counts.empty(); }
};

struct RunOutcome {
  Scene scene;  // as the models saw it (its vertex arrays freed without check)
  GpuRunResult result;
  nlohmann::json stats;                  // stats.json as written
  std::vector<std::string> trace_files;  // the trace's files when traced: "manifest.json", ...
  std::optional<CheckReport> check;      // with RunRequest::check
  std::vector<std::string> warnings;     // frame_warnings()
};

// Throws InputError for bad input (nothing written) and SessionError when
// the simulation fails (hang, model error, unbalanced counters).
RunOutcome run_session(const RunRequest& request, Progress& progress);

// The cycle model's frame and counters against the golden model's.
// `supersample` maps an output pixel to its render-target pixels (the last
// writers are recorded per render-target pixel).
CheckReport compare_with_golden(const golden::Result& golden, const GpuRunResult& gpu,
                                unsigned supersample);

}  // namespace gpusim
