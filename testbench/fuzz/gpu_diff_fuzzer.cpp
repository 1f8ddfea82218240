// libFuzzer entry point of fuzz target 2, the cycle model's setup and
// rasterization against the golden model's (gpu_diff_target.h).
#include <cstdio>
#include <cstdlib>

#include "testbench/fuzz/gpu_diff_target.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  setenv("SC_COPYRIGHT_MESSAGE", "DISABLE", 0);
  gpusim::fuzz::diff_instances();  // elaborate the GPUs once
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string problem = gpusim::fuzz::check_gpu_diff_input(data, size);
  if (!problem.empty()) {
    std::fprintf(stderr, "gpu_diff_fuzzer: %s\n", problem.c_str());
    std::abort();
  }
  return 0;
}

// libsystemc defines main() and needs sc_main; libFuzzer's main() is used.
int sc_main(int, char**) {
  return 0;
}
