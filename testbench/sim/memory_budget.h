// Up-front resource checks (docs/robustness.md, "Limits"): before a model
// allocates anything large, the command line estimates what the run will
// hold at its peak (framebuffers, the GPU's memory image, per-pixel maps,
// output images, the scene's own arrays) and refuses a request that cannot
// fit, at once and with the figures, instead of thrashing or being killed
// half way through.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "hw/gpu_config.h"
#include "testbench/scene/scene.h"

namespace gpusim {

struct MemoryEstimate {
  struct Part {
    std::string what;
    uint64_t bytes = 0;
  };
  std::vector<Part> parts;  // summed: an upper bound of the peak

  uint64_t total() const;
  // "2.3 GiB (framebuffer 8192x8192: 768 MiB, ...)"
  std::string describe() const;
};

// golden: golden::render without the last-writer map, and the output images. cycle: run_gpu (the
// GPU's memory image, read back) and the output images; with `check`, also the per-pixel
// last-writer map and a golden render to compare with.
MemoryEstimate estimate_golden_memory(const Scene& scene);
MemoryEstimate estimate_cycle_memory(const Scene& scene, const GpuConfig& config, bool check);

struct MemoryLimit {
  uint64_t bytes = 0;
  std::string source;  // "physical memory", "cgroup memory.max", "--memory-limit"
};
// The machine's physical memory, or the control group's limit when lower.
MemoryLimit default_memory_limit();

// Throws InputError "<scene>: needs about X (...) but the limit is Y (<source>)"
// when the estimate exceeds the limit.
void check_memory(const MemoryEstimate& estimate, const MemoryLimit& limit,
                  const std::string& scene_path);

// The GPU's registers hold 32-bit vertex and index counts: a draw beyond them
// throws InputError naming the draw.
void check_scene_limits(const Scene& scene);

// 1536 -> "1.5 KiB"; exact bytes below 1 KiB.
std::string format_bytes(uint64_t bytes);

}  // namespace gpusim
