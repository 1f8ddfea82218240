// The testbench driver: lays a scene out in GPU memory (vertex and index
// buffers, framebuffer), programs the per-draw state, streams commands
// (clear, draws, end of frame) into the GPU and runs the simulation to
// completion. Each run_gpu() gets a fresh SystemC simulation context, so a
// process can run several frames one after the other; a GpuRunner runs
// them on one GPU, reset between frames.
//
// A run that does not complete cleanly throws SimulationError: the watchdog
// fired, every process blocked before the frame completed, a stage reported
// an internal error, or the stages' counters do not balance
// (docs/robustness.md).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "hw/draw_state.h"
#include "hw/framebuffer.h"
#include "hw/gpu_config.h"
#include "stages/gpu.h"
#include "testbench/scene/scene.h"
#include "testbench/sim/conservation.h"

namespace gpusim {

class OutputFiles;
class Progress;

// The scene as the GPU sees it: register state and an initial memory image.
struct LoadedFrame {
  FrameState frame;
  std::vector<uint8_t> memory;  // byte 0 = GPU address 0
};
LoadedFrame load_frame(const Scene& scene);
// load_frame in two steps, so that the image can be built where it is used
// (run_gpu: in the GPU's memory, with no second copy): the frame's state
// and the image's size in bytes, then the draws' arrays written into an
// image of that size whose other bytes (framebuffers, padding) are zero.
FrameState layout_frame(const Scene& scene, uint64_t* memory_bytes);
void write_frame_arrays(const Scene& scene, const FrameState& frame, uint8_t* memory);
// The output frame in `memory` after `frame` (a load_frame result) ran: the
// resolved colour (or the colour buffer with one sample and no
// supersampling) and sample 0's depth, at the scene's width x height. The
// render target's colour and depth are laid out as `config` says
// (surfaces.tiled, hw/surface_layout.h); the resolve's output is row-major.
Framebuffer read_framebuffer(Memory& memory, const FrameState& frame, const GpuConfig& config);

struct GpuRunOptions {
  bool record_last_writer = false;  // per-pixel primitive id, for --check
  // Phases (build, simulate, read back) timed and, when it is shown, the
  // simulation's state reported (testbench/sim/progress.h); null: neither.
  Progress* progress = nullptr;
  bool watchdog = true;  // the hang detector (testbench/sim/watchdog.h)
  // Called once the scene's vertex arrays are in the GPU's memory, before
  // the simulation starts; run_gpu reads no Draw array after it, so the
  // caller may free them (gpusim run without --check: a large mesh's arrays
  // are then held once, not twice, while simulating).
  std::function<void()> scene_arrays_copied;
  // Elaboration order of the raster units; no result may depend on it.
  Gpu::UnitOrder unit_order = Gpu::UnitOrder::ascending;
  // Stages put in the place of FIFOs (stages/topology.h); must outlive the run.
  const Interposers* interposers = nullptr;
  // Stages whose only inputs and outputs are FIFOs run ahead of the kernel's
  // time (temporal decoupling, hw/pipeline_stage.h): the same frames and
  // statistics, fewer context switches. Not with tracing (the probes see
  // operations in the kernel's order) nor with the fault injection below.
  bool temporal_decoupling = true;
  // Random stalls at every FIFO boundary when stall_probability > 0, each
  // FIFO's stream seeded by stall_seed_of(its name, stall_seed).
  double stall_probability = 0.0;
  unsigned stall_max_cycles = 8;
  uint64_t stall_seed = 1;

  // Tracing (docs/traces.md): when trace_dir is set, the run is recorded into
  // that directory (created if missing). The trace files are written under
  // temporary names registered in *trace_files, which the caller commits
  // together with its own files (stats.json, frame.exr) or discards. Filters
  // as the command line gives them; bad syntax or an unknown stage throws
  // InputError before anything is simulated or written.
  std::string trace_dir;
  OutputFiles* trace_files = nullptr;
  std::string trace_scene;  // the scene's path, for manifest.json
  std::string trace_stages, trace_window, trace_prims;
  std::string trace_formats;  // --trace-formats: "vcd,timeline"; empty: every format

  // Test-only fault injection (docs/robustness.md, "Watchdog"): production
  // runs leave these at their defaults. FIFOs by name, as in stats.json.
  bool fault_withhold_end_of_frame = false;  // the host never sends end_of_frame: a lost item
  std::string fault_disconnected_fifo;       // the FIFO never delivers: a deadlock
  // (Unknown FIFO names throw std::invalid_argument.)
  std::string fault_stalled_fifo;  // its neighbours stay busy: the watchdog fires
};

// The cycle model did not finish the frame cleanly. what() is a report: a
// headline, then (for hangs) one line per stage and per FIFO.
class SimulationError : public std::runtime_error {
 public:
  enum class Kind {
    watchdog,      // no item moved for watchdog_cycles
    deadlock,      // every process blocked before the frame completed
    model_error,   // a stage reported an internal error (SC_REPORT_ERROR)
    conservation,  // the stages' counters do not balance
  };
  SimulationError(Kind kind, const std::string& report)
      : std::runtime_error(report), m_kind(kind) {}
  Kind kind() const { return m_kind; }

 private:
  Kind m_kind;
};

struct GpuRunResult {
  bool completed = false;  // every unit finished the frame (always, when run_gpu returns)
  uint64_t cycles = 0;
  double wall_seconds = 0.0;
  Framebuffer framebuffer;
  std::vector<int64_t> last_writer;  // when recorded
  PipelineCounts counts;             // the pipeline counters, the golden model's
  nlohmann::json timing;             // Gpu::stats_json
  NetlistTables netlist;             // the GPU's stages and FIFOs (Topology::trace_tables)
  size_t decoupled_stages = 0;       // run ahead of the kernel's time (temporal_decoupling)
};

class TraceFilter;
struct TraceFormats;

// Runs frames one after the other on one elaborated GPU, as a replay does:
// the first frame elaborates it (in a fresh simulation context) and each
// later one resets it (Gpu::reset) at the first cycle boundary after the
// previous frame's end, so that every frame's result is, to the bit, the
// one a freshly elaborated GPU gives it. A frame whose netlist differs (a
// resolve stage or none), a frame after a failed one, and every frame of a
// traced run or one with an injected fault is elaborated afresh.
class GpuRunner {
 public:
  // `options` apply to every frame.
  GpuRunner(const GpuConfig& config, GpuRunOptions options);
  ~GpuRunner();
  GpuRunner(const GpuRunner&) = delete;
  GpuRunner& operator=(const GpuRunner&) = delete;

  // Throws SimulationError when the frame does not complete cleanly.
  GpuRunResult run(const Scene& scene);
  // GPUs elaborated so far.
  unsigned elaborations() const { return m_elaborations; }

 private:
  struct Model;
  void elaborate(FrameState frame, uint64_t memory_bytes, const TraceFilter& trace_filter,
                 const TraceFormats& trace_formats);
  GpuRunResult run_frame(const Scene& scene, uint64_t memory_bytes);
  void drop_model();

  const GpuConfig m_config;  // the stages keep references to it
  const GpuRunOptions m_options;
  std::unique_ptr<Model> m_model;
  unsigned m_elaborations = 0;
};

// One frame on a GPU of its own (a GpuRunner's first frame). Throws
// SimulationError when the frame does not complete cleanly.
GpuRunResult run_gpu(const Scene& scene, const GpuConfig& config, const GpuRunOptions& options);

}  // namespace gpusim
