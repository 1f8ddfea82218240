// `gpusim replay` as a library: an apitrace trace of a fixed-function OpenGL
// program through the GL driver (testbench/gl/gl_driver.h) onto the cycle
// model or the golden model, frame by frame, each frame's EXR, PNG and
// stats_N.json written together (docs/replay.md). The command line parses
// its options into a ReplayRequest and prints each frame as it completes.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "hw/gpu_config.h"
#include "testbench/gl/feature_report.h"
#include "testbench/sim/progress.h"

namespace gpusim {

struct ReplayRequest {
  std::string trace;
  uint32_t first = 0, last = UINT32_MAX;  // frames to render, inclusive; UINT32_MAX: to the end
  bool cycle = true;                      // the cycle model, else the golden model
  GpuConfig config;
  std::string out_dir = "replay";
};

struct ReplayedFrame {
  uint32_t index = 0, end_call = 0;
  size_t draws = 0;
  uint64_t vertices = 0, primitives = 0;
  uint64_t cycles = 0;  // the cycle model's
  double driver_seconds = 0.0, render_seconds = 0.0;
  bool unsupported = false;  // the frame used a feature the driver does not support
};

struct ReplayOutcome {
  uint32_t rendered = 0, frames_seen = 0;
  double driver_seconds = 0.0, render_seconds = 0.0;  // summed over the rendered frames
  gl::FeatureReport features;                         // of the rendered frames
};

struct ReplayCallbacks {
  std::function<void()> opened;                     // the trace is open, the directory made
  std::function<void(const ReplayedFrame&)> frame;  // a frame's files are written
};

// Throws InputError for a bad trace and SessionError ("<trace> frame N")
// when a frame's simulation fails. Fewer frames than asked for is the
// caller's to report (the outcome says how many there were).
ReplayOutcome replay_session(const ReplayRequest& request, Progress& progress,
                             const ReplayCallbacks& callbacks);

}  // namespace gpusim
