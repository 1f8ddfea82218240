// A fixed-function OpenGL 1.x driver for the simulated GPU: it executes the
// calls of an apitrace trace (TraceCall values, testbench/gl/apitrace_reader.h)
// on a GL state machine and, per frame, translates what was drawn into what
// the GPU's command processor and registers take: a gpusim::Scene of draws
// (object-space arrays, matrices, RenderState, material) and per-frame
// lights. Consecutive geometry with the same state is batched into one draw.
//
// The supported subset, the translation rules, the mapping of GL's lighting
// onto the GPU's (docs/pipeline-spec.md, section 2) and what is reported as
// unsupported are in docs/replay.md, "The driver". Anything the GPU cannot
// express is counted in the frame's FeatureReport, never silently changed.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "testbench/gl/apitrace_reader.h"
#include "testbench/gl/feature_report.h"
#include "testbench/scene/scene.h"

namespace gpusim::gl {

// One frame: the calls from the previous frame end to a swap.
struct DriverFrame {
  Scene scene;              // for run_gpu() or golden::render()
  uint32_t index = 0;       // frames numbered from 0 in trace order
  uint32_t end_call = 0;    // the swap call's number (apitrace dump-images names its image by it)
  uint64_t gl_calls = 0;    // calls executed, display-list contents included
  uint64_t vertices = 0;    // vertices the program submitted
  uint64_t primitives = 0;  // GL primitives (triangles after decomposition, lines, points)
  FeatureReport features;   // of this frame only
  // The driver's statistics for stats_N.json.
  nlohmann::json to_json() const;
};

class GlDriver {
 public:
  GlDriver();
  ~GlDriver();
  GlDriver(const GlDriver&) = delete;
  GlDriver& operator=(const GlDriver&) = delete;

  // Executes one call of the trace. Returns true when the call ended a frame
  // (a swap): take_frame() then returns it. Throws InputError (one line naming
  // the call) for a malformed call: missing or mistyped arguments.
  bool call(const TraceCall& call);
  DriverFrame take_frame();

  // Without capture, frames keep their state changes but no geometry (frames
  // before the ones a replay renders).
  void set_capture(bool capture);

 private:
  struct State;
  std::unique_ptr<State> m;
};

}  // namespace gpusim::gl
