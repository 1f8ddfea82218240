#include "testbench/session/golden_session.h"

#include <chrono>

#include "testbench/io/message_text.h"
#include "testbench/session/frame_warnings.h"
#include "testbench/session/session_steps.h"
#include "testbench/sim/conservation.h"
#include "testbench/sim/memory_budget.h"

namespace gpusim {

GoldenOutcome golden_session(const GoldenRequest& request, Progress& progress) {
  GoldenOutcome outcome;
  Scene& scene = outcome.scene;
  nlohmann::json driver = nlohmann::json::object();
  scene = prepare_scene(request.scene, request.note, driver, progress);
  check_memory(estimate_golden_memory(scene), memory_limit(request.memory_mib), request.scene);
  progress.begin("render", "rendering with the golden model");
  const auto start = std::chrono::steady_clock::now();
  // Nothing compares it with the cycle model: no per-pixel last writers.
  outcome.result = golden::render(scene, golden::RenderOptions{false});
  outcome.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::vector<std::string> errors = pipeline_count_errors(outcome.result.stats);
  if (!errors.empty()) {
    std::string report = "golden model: the counters do not balance:";
    for (const std::string& e : errors) report += "\n  " + e;
    throw SessionError(request.scene, SimulationError(SimulationError::Kind::conservation, report));
  }
  // No wall-clock figures in stats.json: the same input gives the same bytes.
  outcome.stats = {
      {"model", "golden"},
      {"scene", request.scene},
      {"settings", scene.resolved},
      {"stats", outcome.result.stats.to_json()},
  };
  outcome.stats.update(driver);
  progress.begin("write", "frame.exr, frame.png, stats.json into " + printable(request.out_dir));
  write_frame_outputs(request.out_dir, outcome.result.framebuffer, outcome.stats, progress);
  progress.end();
  outcome.warnings = frame_warnings(scene, outcome.result.stats);
  return outcome;
}

}  // namespace gpusim
