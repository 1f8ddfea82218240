// The testbench driver: lays a scene out in GPU memory (vertex and index
// buffers, framebuffer), programs the per-draw state, streams commands
// (clear, draws, end of frame) into the GPU and runs the simulation to
// completion. Each run_gpu() gets a fresh SystemC simulation context, so a
// process can run several frames one after the other.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <vector>

#include "hw/draw_state.h"
#include "hw/framebuffer.h"
#include "hw/gpu_config.h"
#include "testbench/scene/scene.h"

namespace gpusim {

// The scene as the GPU sees it: register state and an initial memory image.
struct LoadedFrame {
  FrameState frame;
  std::vector<uint8_t> memory;  // byte 0 = GPU address 0
};
LoadedFrame load_frame(const Scene& scene);

// Assembled triangles of a draw with this many vertex slots (spec section 3).
uint64_t triangle_count(PrimitiveType type, uint64_t slots);

struct GpuRunOptions {
  bool record_last_writer = false;  // per-pixel primitive id, for --check
  bool progress = false;            // a progress line on stderr
  // Random stalls at every FIFO boundary when stall_probability > 0.
  double stall_probability = 0.0;
  unsigned stall_max_cycles = 8;
  uint64_t stall_seed = 1;
};

struct GpuRunResult {
  bool completed = false;  // every unit finished the frame
  uint64_t cycles = 0;
  double wall_seconds = 0.0;
  Framebuffer framebuffer;
  std::vector<int64_t> last_writer;  // when recorded
  nlohmann::json counts;             // pipeline counters, named as the golden model's
  nlohmann::json timing;             // Gpu::stats_json
};

GpuRunResult run_gpu(const Scene& scene, const GpuConfig& config, const GpuRunOptions& options);

}  // namespace gpusim
