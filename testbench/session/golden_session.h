// `gpusim golden` as a library: a scene through the golden model, its frame,
// PNG and stats.json written together. The command line prints the outcome.
#pragma once

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "testbench/golden/golden_model.h"
#include "testbench/scene/scene.h"
#include "testbench/sim/progress.h"

namespace gpusim {

struct GoldenRequest {
  std::string scene;
  std::string out_dir;
  uint64_t memory_mib = 0;  // the memory limit; 0: the machine's
  // Called with a line for stderr as soon as it is known (the automatic
  // camera's note).
  std::function<void(const std::string&)> note;
};

struct GoldenOutcome {
  Scene scene;
  golden::Result result;  // without last writers
  double seconds = 0.0;   // the render's wall time
  nlohmann::json stats;   // stats.json as written
  std::vector<std::string> warnings;
};

// Throws InputError for bad input (nothing written) and SessionError when
// the golden model's counters do not balance.
GoldenOutcome golden_session(const GoldenRequest& request, Progress& progress);

}  // namespace gpusim
