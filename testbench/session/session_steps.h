// The steps the sessions share (run, golden, replay): loading a scene with
// its progress shown, the driver's rewriting of its draws, the memory limit
// a run is checked against, and a frame's outputs written all together.
#pragma once

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "hw/framebuffer.h"
#include "testbench/scene/scene.h"
#include "testbench/sim/gpu_run.h"
#include "testbench/sim/memory_budget.h"
#include "testbench/sim/progress.h"

namespace gpusim {

// A simulation that failed inside a session, with what it was running: the
// scene's path, or "<trace> frame N". The command line reports
// "gpusim: <where>: <report>".
class SessionError : public SimulationError {
 public:
  SessionError(std::string where, const SimulationError& e)
      : SimulationError(e), m_where(std::move(where)) {}
  const std::string& where() const { return m_where; }

 private:
  std::string m_where;
};

// The --memory-limit option: MiB, 0 for the machine's.
MemoryLimit memory_limit(uint64_t mib);

// A session's scene, ready for a model: loaded (the load phase), `note`
// called with the automatic camera's note if the loader framed the meshes,
// the draws rewritten by the driver's visibility option (docs/painter.md;
// a painter's frame adds its sort's figures to `stats_sections` under
// "painter", the sort a phase of its own), and checked against the limits.
Scene prepare_scene(const std::string& path, const std::function<void(const std::string&)>& note,
                    nlohmann::json& stats_sections, Progress& progress);

// frame.exr, frame.png and stats.json into dir, committed together, each
// named on the progress display as it starts.
void write_frame_outputs(const std::string& dir, const Framebuffer& fb, const nlohmann::json& stats,
                         Progress& progress);

}  // namespace gpusim
