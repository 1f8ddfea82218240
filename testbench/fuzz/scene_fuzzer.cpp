// libFuzzer entry point of fuzz target 1, the scene parser (scene_target.h).
#include <cstdio>
#include <cstdlib>

#include "testbench/fuzz/scene_target.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string problem = gpusim::fuzz::check_scene_input(data, size);
  if (!problem.empty()) {
    std::fprintf(stderr, "scene_fuzzer: %s\n", problem.c_str());
    std::abort();
  }
  return 0;
}

// libsystemc defines main() and needs sc_main; libFuzzer's main() is used.
int sc_main(int, char**) {
  return 0;
}
