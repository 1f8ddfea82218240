// Fuzz target 1: the scene parser (docs/robustness.md, "Fuzzing").
//
// The input bytes are a scene file's contents, loaded by
// load_scene_from_string() as if read from kSceneFuzzPath, a path inside
// assimp's OBJ test models so that relative mesh names ("box.obj",
// "spider.obj") resolve to real meshes. The properties:
//   - the loader either returns a scene or throws InputError, whose message
//     is one line starting with the file's name; any other exception, crash,
//     hang or sanitizer report is a finding;
//   - a loaded scene's resolved settings serialise (stats.json);
//   - a small loaded scene (<= 64x64 pixels, <= 4096 vertex slots) renders
//     with the golden model, whose counters obey the spec's bookkeeping.
// Header-only so that testbench/tests/robust_fuzz_regressions_test.cpp replays
// the seed corpus and every past finding through the same checks in the
// normal and sanitizer builds.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "testbench/golden/golden_model.h"
#include "testbench/scene/scene.h"
#include "testbench/sim/gpu_run.h"

namespace gpusim::fuzz {

inline const std::string kSceneFuzzPath = "/usr/share/assimp/models/OBJ/fuzz_scene.json";

// "" when every property holds, else what went wrong.
inline std::string check_scene_input(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  Scene scene;
  try {
    scene = load_scene_from_string(text, kSceneFuzzPath);
  } catch (const InputError& e) {
    const std::string m = e.what();
    if (m.rfind(kSceneFuzzPath + ": ", 0) != 0) return "error not naming the file: " + m;
    if (m.find('\n') != std::string::npos || m.find('\r') != std::string::npos) {
      return "error of more than one line: " + m;
    }
    return "";
  }
  // stats.json holds the resolved settings (throws on invalid UTF-8).
  try {
    (void)scene.resolved.dump();
  } catch (const std::exception& e) {
    return std::string("resolved settings do not serialise: ") + e.what();
  }
  uint64_t slots = 0;
  for (const Draw& d : scene.draws) slots += d.vertex_count();
  const uint64_t pixels = static_cast<uint64_t>(scene.framebuffer.width) *
                          static_cast<uint64_t>(scene.framebuffer.height);
  if (pixels <= 64 * 64 && slots <= 4096) {
    const golden::Result r = golden::render(scene);
    for (const std::string& e : pipeline_count_errors(r.stats)) {
      return "golden counters do not balance: " + e;
    }
    if (r.framebuffer.width != scene.framebuffer.width ||
        r.framebuffer.height != scene.framebuffer.height) {
      return "golden framebuffer has the wrong size";
    }
  }
  return "";
}

}  // namespace gpusim::fuzz
