#include "testbench/sim/gpu_run.h"

#include <algorithm>
#include <chrono>
#include <climits>
#include <cstdio>
#include <cstring>
#include <memory>
#include <sstream>
#include <systemc>

#include "hw/input_error.h"
#include "hw/simulation_context.h"
#include "hw/surface_layout.h"
#include "stages/gpu.h"
#include "testbench/io/output_file.h"
#include "testbench/sim/conservation.h"
#include "testbench/sim/progress.h"
#include "testbench/sim/watchdog.h"
#include "traces/trace_recorder.h"

namespace gpusim {
namespace {

constexpr uint64_t kAlignment = 64;

uint64_t align(uint64_t v) {
  return (v + kAlignment - 1) / kAlignment * kAlignment;
}

// Host: streams each frame's commands and notes when every unit is done.
// Its thread starts the first frame as the simulation starts and each later
// one at the instant the runner gives (next_frame()), after resetting the
// GPU there, so that every frame starts as the first did.
class Host : public sc_core::sc_module {
 public:
  SC_HAS_PROCESS(Host);
  // `progress`: where the simulate phase's state goes, or null for none.
  Host(sc_core::sc_module_name name, Gpu& gpu, const GpuConfig& config, const FrameState& frame,
       Progress* progress, bool withhold_end_of_frame = false)
      : sc_core::sc_module(name),
        m_gpu(gpu),
        m_frame(frame),
        m_progress(progress),
        m_withhold_end_of_frame(withhold_end_of_frame),
        m_cycle(config.cycle()),
        m_interval(config.cycles(100000)),
        m_memory_latency(config.cycles(config.memory.latency)) {
    SC_THREAD(stream);
    if (progress) SC_THREAD(report_progress);
  }
  bool done = false;
  sc_core::sc_time started, finished;  // the frame's first instant and its end
  uint64_t primitives = 0;             // of every kind in the frame (progress lines)

  // Outside the simulation, the previous frame done and the kernel idle:
  // the next frame starts at the next cycle boundary after now (a timed
  // wake-up, so in the first delta of its time, as the first frame starts).
  void next_frame() {
    const uint64_t now = sc_core::sc_time_stamp().value(), cycle = m_cycle.value();
    m_next.notify(sc_core::sc_time::from_value((now / cycle + 1) * cycle - now));
  }

 private:
  void stream() {
    for (;;) {
      // Before the first wait: the observers the reset woke see the frame
      // under way.
      started = sc_core::sc_time_stamp();
      done = false;
      stream_frame();
      while (!m_gpu.frame_done()) sc_core::wait(m_gpu.unit_done_events());
      finished = sc_core::sc_time_stamp();
      done = true;
      m_stop.notify();
      sc_core::wait(m_next);
      m_gpu.reset();
    }
  }

  void stream_frame() {
    Fifo<Command>& q = m_gpu.command_queue();
    // The frame clear, then the draws with the draw list's clears at their
    // places; a clear token carries no value (FrameState::clear).
    q.write(Command{PacketKind::clear, 0});
    const std::vector<ClearState>& clears = m_frame.clears;
    size_t next_clear = 0;
    for (size_t i = 0; i <= m_frame.draws.size(); ++i) {
      for (; next_clear < clears.size() && clears[next_clear].before_draw == i; ++next_clear)
        q.write(Command{PacketKind::clear, 0});
      if (i < m_frame.draws.size()) q.write(Command{PacketKind::work, static_cast<uint32_t>(i)});
    }
    // (Fault injection: a lost end_of_frame, which the watchdog must catch.)
    if (!m_withhold_end_of_frame) q.write(Command{PacketKind::end_of_frame, 0});
  }

  // Wakes every 100k simulated cycles (a negligible cost) and hands the
  // state to the progress display, which shows it as often as its mode
  // allows. It wakes on simulated time only and only reads the GPU, so the
  // host's clock never reaches the simulation (docs/robustness.md). It
  // starts over with each frame, as the GPU's reset tells it.
  void report_progress() {
    for (;;) {
      report_frame();
      sc_core::wait(m_gpu.reset_event());
    }
  }

  void report_frame() {
    const auto start = std::chrono::steady_clock::now();
    const sc_core::sc_time first = sc_core::sc_time_stamp();
    const sc_core::sc_event_or_list activity = activity_events(m_gpu.topology()) | m_stop;
    uint64_t moved = progress_count(m_gpu);
    const auto state = [&] {
      const uint64_t cycles = static_cast<uint64_t>((sc_core::sc_time_stamp() - first) / m_cycle);
      const double wall =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      char buf[192];
      std::snprintf(buf, sizeof buf,
                    "%llu of %llu primitives assembled, %llu cycles, %llu fragments, %.3g "
                    "cycles/s",
                    static_cast<unsigned long long>(m_gpu.primitives_assembled()),
                    static_cast<unsigned long long>(primitives),
                    static_cast<unsigned long long>(cycles),
                    static_cast<unsigned long long>(m_gpu.fragment_counts().generated),
                    static_cast<double>(cycles) / std::max(wall, 1e-9));
      return std::string(buf);
    };
    while (!done) {
      sc_core::wait(m_interval, m_stop);
      // Nothing moved and no transfer in flight: wait for an item rather
      // than time, so that a deadlock lets the kernel run out of events
      // (docs/robustness.md). Not once the frame is done: nothing moves
      // after it, and the final figures below would never be shown.
      if (!done && progress_count(m_gpu) == moved &&
          !transfers_in_flight(m_gpu, m_memory_latency)) {
        wait_for_activity(m_gpu.topology(), activity);
      }
      moved = progress_count(m_gpu);
      if (!done) m_progress->update(state());
    }
    m_progress->update(state(), true);  // the frame's final figures
  }

  Gpu& m_gpu;
  const FrameState& m_frame;
  Progress* m_progress;
  bool m_withhold_end_of_frame;
  sc_core::sc_time m_cycle;
  sc_core::sc_time m_interval;
  sc_core::sc_time m_memory_latency;
  sc_core::sc_event m_stop;
  sc_core::sc_event m_next;  // the next frame's first instant
};

// Test-only faults (docs/robustness.md, "Watchdog"), by FIFO name.
void inject_faults(const Topology& netlist, const GpuRunOptions& options, const GpuConfig& config) {
  const auto fifo = [&](const std::string& name) {
    const Topology::FifoNode* f = netlist.find_fifo(name);
    if (f == nullptr) throw std::invalid_argument("run_gpu: no FIFO named '" + name + "'");
    return f->channel;
  };
  if (!options.fault_disconnected_fifo.empty()) {
    fifo(options.fault_disconnected_fifo)->withhold_from_reader();
  }
  if (!options.fault_stalled_fifo.empty()) {
    fifo(options.fault_stalled_fifo)
        ->set_stalls(
            RandomStalls(options.fault_stalled_fifo, 0x5EED, 1.0, UINT_MAX, config.cycle()));
  }
}

}  // namespace

// The frame written out: the resolve's output image, or the colour buffer
// itself with one sample and no supersampling; the depth of sample 0 of each
// output pixel's lower-left render-target pixel (docs/pipeline-spec.md,
// section 14).
Framebuffer read_framebuffer(Memory& memory, const FrameState& frame, const GpuConfig& config) {
  const FramebufferDesc& d = frame.framebuffer;  // the render target
  const int k = static_cast<int>(d.supersample);
  const int width = d.width / k, height = d.height / k;
  Framebuffer fb(width, height, d.color_format, d.depth_format);
  const size_t pixels = static_cast<size_t>(width) * height;
  const size_t target_samples = static_cast<size_t>(d.width) * d.height * d.samples;
  const unsigned cb = color_bytes_per_pixel(d.color_format);
  const unsigned zb = depth_bytes_per_pixel(d.depth_format);
  const uint8_t* c = frame.needs_resolve() ? memory.data(frame.resolve_address, pixels * cb)
                                           : memory.data(frame.color_address, pixels * cb);
  const uint8_t* z = memory.data(frame.depth_address, target_samples * zb);
  // Byte offsets of a pixel in the render target's buffers (converted from
  // the tiled layout on readout); the resolve's output is row-major.
  const auto layout = [&](unsigned bytes) {
    return SurfaceLayout(config.surfaces.tiled, d.width, d.height, bytes * d.samples,
                         config.tile_size, config.units);
  };
  const SurfaceLayout color_layout = layout(cb), depth_layout = layout(zb);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const size_t p = fb.pixel_index(x, y);
      const size_t cp = frame.needs_resolve() ? p * cb : color_layout.pixel_offset(x, y);
      for (int ch = 0; ch < 4; ++ch) {
        if (d.color_format == ColorFormat::rgba8) {
          fb.color[p * 4 + ch] = c[cp + ch];
        } else {
          uint16_t h;
          std::memcpy(&h, c + cp + ch * 2, 2);
          fb.color[p * 4 + ch] = h;
        }
      }
      // Sample 0 of render-target pixel (kx, ky).
      const size_t sample0 = depth_layout.pixel_offset(k * x, k * y);
      if (d.depth_format == DepthFormat::unorm16) {
        uint16_t v;
        std::memcpy(&v, z + sample0, 2);
        fb.depth[p] = v;
      } else {
        uint32_t v;
        std::memcpy(&v, z + sample0, 4);
        fb.depth[p] = v;
      }
    }
  }
  return fb;
}

FrameState layout_frame(const Scene& scene, uint64_t* memory_bytes) {
  FrameState f;
  // The render target: supersampling makes it k times the output on each
  // side, multisampling keeps N samples per pixel (docs/pipeline-spec.md,
  // section 14).
  const FramebufferDesc& out_fb = scene.framebuffer;
  const unsigned k = out_fb.supersample;
  f.framebuffer = out_fb;
  f.framebuffer.width = out_fb.width * static_cast<int>(k);
  f.framebuffer.height = out_fb.height * static_cast<int>(k);
  f.global_ambient = scene.global_ambient;
  f.lights = scene.lights;
  f.clears = scene.clears;
  const uint64_t samples =
      static_cast<uint64_t>(f.framebuffer.width) * f.framebuffer.height * out_fb.samples;
  f.color_address = 0;
  f.depth_address = align(samples * color_bytes_per_pixel(out_fb.color_format));
  f.resolve_address = align(f.depth_address + samples * depth_bytes_per_pixel(out_fb.depth_format));
  const uint64_t output_bytes = f.needs_resolve()
                                    ? static_cast<uint64_t>(out_fb.width) * out_fb.height *
                                          color_bytes_per_pixel(out_fb.color_format)
                                    : 0;
  uint64_t end = f.resolve_address + output_bytes;
  // Places `count` items at the next aligned address.
  const auto place = [&end](size_t count, size_t item_bytes) {
    const uint64_t addr = align(end);
    end = addr + count * item_bytes;
    return addr;
  };

  // Every scene texture's levels, one after another, each on and padded to
  // kMaxTextureCacheLine bytes (hw/texture_state.h).
  std::vector<std::vector<TextureLevel>> texture_levels;
  for (const Texture& t : scene.textures) {
    std::vector<TextureLevel>& levels = texture_levels.emplace_back();
    for (const TextureImage& image : t.levels) {
      const uint64_t addr =
          (end + kMaxTextureCacheLine - 1) / kMaxTextureCacheLine * kMaxTextureCacheLine;
      end = addr + (image.texels.size() + kMaxTextureCacheLine - 1) / kMaxTextureCacheLine *
                       kMaxTextureCacheLine;
      levels.push_back({addr, image.width, image.height});
    }
  }
  int64_t next_primitive = 0;
  for (const Draw& d : scene.draws) {
    DrawState s;
    s.primitive = d.primitive;
    s.lighting = d.lighting && !d.normals.empty();
    s.material = d.material;
    s.model_view = d.model_view;
    s.mvp = d.mvp;
    s.normal_matrix = d.normal_matrix;
    s.state = d.state;
    // The driver draws a supersampled frame at k times the size: widths and
    // sizes scale with it (the same float product as the golden model's).
    s.state.line_width = s.state.line_width * static_cast<float>(k);
    s.state.point_size = s.state.point_size * static_cast<float>(k);
    // Viewport and scissor are in output pixels: k times them in the target.
    if (s.state.viewport) s.state.viewport = scaled(*s.state.viewport, static_cast<int>(k));
    if (s.state.scissor) s.state.scissor = scaled(*s.state.scissor, static_cast<int>(k));
    s.first_primitive_id = next_primitive;
    DrawBuffers& b = s.buffers;
    b.vertex_count = static_cast<uint32_t>(d.positions.size());
    b.slot_count = static_cast<uint32_t>(d.vertex_count());
    b.positions = place(d.positions.size(), sizeof(glm::vec4));
    if (s.lighting) b.normals = place(d.normals.size(), sizeof(glm::vec3));
    if (!d.colors.empty()) b.colors = place(d.colors.size(), sizeof(glm::vec4));
    if (d.texture >= 0) {
      // The texture stage's registers; its texels are placed once per scene
      // texture (below), so draws sharing a texture share its memory.
      const Texture& t = scene.textures[static_cast<size_t>(d.texture)];
      b.texcoords = place(d.texcoords.size(), sizeof(glm::vec2));
      s.texture.format = t.format;
      s.texture.sampler = t.sampler;
      s.texture.env = d.texture_env;
      s.texture.levels = texture_levels.at(static_cast<size_t>(d.texture));
    }
    if (!d.indices.empty()) b.indices = place(d.indices.size(), sizeof(uint32_t));
    s.varyings = varying_layout_for(s);  // after the buffers: a Phong layout needs normals
    next_primitive += static_cast<int64_t>(primitive_count(d.primitive, b.slot_count));
    f.draws.push_back(s);
  }
  *memory_bytes = align(end);
  return f;
}

void write_frame_arrays(const Scene& scene, const FrameState& frame, uint8_t* memory) {
  const auto copy = [memory](uint64_t addr, const auto& v) {
    if (addr != kNoBuffer && !v.empty())
      std::memcpy(memory + addr, v.data(), v.size() * sizeof(v[0]));
  };
  for (size_t i = 0; i < scene.draws.size(); ++i) {
    const Draw& d = scene.draws[i];
    const DrawBuffers& b = frame.draws[i].buffers;
    copy(b.positions, d.positions);
    copy(b.normals, d.normals);
    copy(b.colors, d.colors);
    copy(b.texcoords, d.texcoords);
    copy(b.indices, d.indices);
    if (d.texture >= 0) {
      const Texture& t = scene.textures[static_cast<size_t>(d.texture)];
      const std::vector<TextureLevel>& levels = frame.draws[i].texture.levels;
      for (size_t l = 0; l < levels.size(); ++l) copy(levels[l].address, t.levels[l].texels);
    }
  }
}

LoadedFrame load_frame(const Scene& scene) {
  LoadedFrame out;
  uint64_t bytes = 0;
  out.frame = layout_frame(scene, &bytes);
  out.memory.resize(bytes);
  write_frame_arrays(scene, out.frame, out.memory.data());
  return out;
}

// One elaborated GPU and the testbench around it.
struct GpuRunner::Model {
  sc_core::sc_simcontext* context = nullptr;  // the model's own (others may run in between)
  FrameState frame;       // the frame's registers, which every stage reads: reloaded per frame
  bool resolve = false;   // frame.needs_resolve() when elaborated: a Resolve stage or none
  bool textured = false;  // frame.textured() when elaborated: texture units or none
  bool reusable = false;
  std::unique_ptr<Gpu> gpu;
  // Declared after the GPU, so destroyed before it: nothing calls a probe
  // once the run is over.
  std::unique_ptr<TraceRecorder> recorder;
  std::unique_ptr<Host> host;
  std::unique_ptr<Watchdog> watchdog;
  size_t decoupled_stages = 0;
};

GpuRunner::GpuRunner(const GpuConfig& config, GpuRunOptions options)
    : m_config(config), m_options(std::move(options)) {}

GpuRunner::~GpuRunner() {
  drop_model();
}

// SystemC objects leave their own context when destroyed: the model's is
// made current for that, and the caller's restored.
void GpuRunner::drop_model() {
  if (!m_model) return;
  sc_core::sc_simcontext* current = sc_core::sc_get_curr_simcontext();
  use_simulation_context(m_model->context);
  m_model.reset();
  use_simulation_context(current);
}

GpuRunResult GpuRunner::run(const Scene& scene) {
  static_assert(sizeof(glm::vec4) == 16 && sizeof(glm::vec3) == 12, "packed attributes");
  const GpuRunOptions& options = m_options;
  const GpuConfig& config = m_config;
  const bool tracing = !options.trace_dir.empty();
  TraceFilter trace_filter;
  TraceFormats trace_formats;
  if (tracing) {
    if (!kTraceHooks) {
      throw InputError(
          "--trace: this gpusim was built without trace hooks (GPUSIM_TRACE_HOOKS=OFF)");
    }
    if (options.trace_files == nullptr) throw std::invalid_argument("run_gpu: trace_files not set");
    trace_filter =
        TraceFilter::parse(options.trace_stages, options.trace_window, options.trace_prims);
    trace_formats = TraceFormats::parse(options.trace_formats);
  }
  Progress* progress = options.progress;
  uint64_t memory_bytes = 0;
  FrameState frame = layout_frame(scene, &memory_bytes);
  const bool reuse = m_model && m_model->reusable && m_model->resolve == frame.needs_resolve() &&
                     m_model->textured == frame.textured();
  if (progress) {
    progress->begin("build",
                    reuse ? std::string("laying out the scene in GPU memory, resetting the GPU")
                          : "laying out the scene in GPU memory, elaborating " +
                                std::to_string(config.units) + " raster unit" +
                                (config.units == 1 ? "" : "s"));
  }
  // A model whose frame failed is not run again.
  try {
    if (reuse) {
      use_simulation_context(m_model->context);
      // The frame's registers and a zero-filled memory of its size, as a
      // fresh elaboration has them; the host resets the GPU at the frame's
      // first instant.
      m_model->frame = std::move(frame);
      m_model->gpu->memory().reset_contents(memory_bytes);
      m_model->host->next_frame();
    } else {
      elaborate(std::move(frame), memory_bytes, trace_filter, trace_formats);
    }
    return run_frame(scene, memory_bytes);
  } catch (...) {
    drop_model();
    throw;
  }
}

void GpuRunner::elaborate(FrameState frame, uint64_t memory_bytes, const TraceFilter& trace_filter,
                          const TraceFormats& trace_formats) {
  const GpuRunOptions& options = m_options;
  const GpuConfig& config = m_config;
  const bool tracing = !options.trace_dir.empty();
  const bool faults = options.fault_withhold_end_of_frame ||
                      !options.fault_disconnected_fifo.empty() ||
                      !options.fault_stalled_fifo.empty();
  // The old model goes first, in its own context.
  drop_model();
  sc_core::sc_simcontext* context = fresh_simulation_context();
  ++m_elaborations;
  m_model = std::make_unique<Model>();
  Model& m = *m_model;
  m.context = context;
  m.frame = std::move(frame);
  m.resolve = m.frame.needs_resolve();
  m.textured = m.frame.textured();
  // A traced frame writes its own trace files, and a fault breaks the
  // model: neither is reset for another frame.
  m.reusable = !tracing && !faults;
  // The memory image is built in the GPU's own memory (zero-filled, as the
  // framebuffers and the padding start; run_frame writes the arrays): no
  // second copy of it.
  m.gpu = std::make_unique<Gpu>("gpu", config, m.frame, memory_bytes, options.unit_order,
                                options.interposers);
  Gpu& gpu = *m.gpu;
  const Topology& netlist = gpu.topology();
  inject_faults(netlist, options, config);
  if (options.stall_probability > 0.0) {
    // Every FIFO its own stream, seeded by its name (MatchLib's rand_stall):
    // a stage added elsewhere in the netlist changes no other FIFO's stalls.
    for (const Topology::FifoNode& f : netlist.fifos()) {
      f.channel->set_stalls(RandomStalls(f.name, stall_seed_of(f.name, options.stall_seed),
                                         options.stall_probability, options.stall_max_cycles,
                                         config.cycle()));
    }
  }
  if (tracing) {
    const NetlistTables tables = netlist.trace_tables();
    trace_filter.stages_kept(tables);  // an unknown stage fails before anything is written
    const std::string& dir = options.trace_dir;
    create_output_directory(dir);
    OutputFiles& files = *options.trace_files;
    TraceRecorder::Paths paths;
    paths.manifest = files.add(dir + "/manifest.json");
    // Formats not chosen keep empty paths: not written.
    if (trace_formats.vcd) {
      paths.vcd = files.add(dir + "/signals.vcd");
      paths.gtkw = files.add(dir + "/signals.gtkw");
    }
    if (trace_formats.timeline) paths.timeline = files.add(dir + "/timeline.json");
    if (trace_formats.transactions) paths.transactions = files.add(dir + "/transactions.bin");
    if (trace_formats.fragments) paths.fragments = files.add(dir + "/fragments.bin");
    m.recorder = std::make_unique<TraceRecorder>(tables, config, m.frame, trace_filter, paths,
                                                 options.trace_scene);
    gpu.attach_trace(*m.recorder);
  }
  if (options.temporal_decoupling && !tracing && !faults) {
    m.decoupled_stages = gpu.topology().decouple();
  }
  Progress* progress = options.progress;
  m.host = std::make_unique<Host>("host", gpu, config, m.frame,
                                  progress && progress->shown() ? progress : nullptr,
                                  options.fault_withhold_end_of_frame);
  if (options.watchdog) m.watchdog = std::make_unique<Watchdog>("watchdog", gpu, config);
}

GpuRunResult GpuRunner::run_frame(const Scene& scene, uint64_t memory_bytes) {
  const GpuRunOptions& options = m_options;
  const GpuConfig& config = m_config;
  Model& m = *m_model;
  Gpu& gpu = *m.gpu;
  const Topology& netlist = gpu.topology();
  write_frame_arrays(scene, m.frame, gpu.memory().data(0, memory_bytes));
  uint64_t primitives = 0;
  for (const Draw& d : scene.draws) primitives += primitive_count(d.primitive, d.vertex_count());
  m.host->primitives = primitives;
  // The run reads nothing of the scene's arrays from here on.
  if (options.scene_arrays_copied) options.scene_arrays_copied();
  GpuRunResult result;
  if (options.record_last_writer) {
    result.last_writer.assign(static_cast<size_t>(m.frame.framebuffer.width) *
                                  static_cast<size_t>(m.frame.framebuffer.height),
                              -1);
  }
  gpu.set_last_writer(options.record_last_writer ? &result.last_writer : nullptr);
  result.decoupled_stages = m.decoupled_stages;

  Progress* progress = options.progress;
  if (progress) {
    progress->begin("simulate", std::to_string(primitives) + " primitives in " +
                                    std::to_string(scene.draws.size()) + " draw" +
                                    (scene.draws.size() == 1 ? "" : "s"));
  }
  const auto start = std::chrono::steady_clock::now();
  const auto frame_cycle = [&] {
    return static_cast<uint64_t>((sc_core::sc_time_stamp() - m.host->started) / config.cycle());
  };
  try {
    sc_core::sc_start();
  } catch (const sc_core::sc_report& e) {
    // A stage's SC_REPORT_ERROR: a model bug, reported with where items were.
    std::string what = e.what();
    while (!what.empty() && (what.back() == '\n' || what.back() == ' ')) what.pop_back();
    throw SimulationError(SimulationError::Kind::model_error,
                          "model error at cycle " + std::to_string(frame_cycle()) + ": " + what +
                              "\n" + fifo_report(netlist));
  }
  result.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (progress) progress->begin("read back", "the frame and the counters, checking the ledger");

  if (m.watchdog && m.watchdog->fired()) {
    throw SimulationError(SimulationError::Kind::watchdog, m.watchdog->report());
  }
  if (!m.host->done) {
    // The kernel ran out of events: every process waits for one that will
    // never come (the watchdog stops counting once every stage waits on a
    // FIFO). One more cycle of (empty) simulated time tells which FIFOs have
    // a reader or writer blocked on them.
    const uint64_t stopped = frame_cycle();
    const NetlistSample before = sample(netlist);
    sc_core::sc_start(config.cycle());
    const NetlistSample after = sample(netlist);
    throw SimulationError(SimulationError::Kind::deadlock,
                          "deadlock: every process is blocked and the frame is not complete (seen "
                          "at cycle " +
                              std::to_string(stopped) +
                              "): " + state_report(netlist, before, after));
  }

  result.completed = true;
  result.cycles = static_cast<uint64_t>((m.host->finished - m.host->started) / config.cycle());
  result.framebuffer = read_framebuffer(gpu.memory(), m.frame, config);
  result.counts = gpu.pipeline_counts();
  result.timing = gpu.stats_json(result.cycles);

  result.netlist = netlist.trace_tables();
  std::vector<std::string> errors = conservation_errors(result.timing, result.netlist, m.frame);
  for (std::string& e : pipeline_count_errors(result.counts)) errors.push_back("pipeline: " + e);
  if (!errors.empty()) {
    std::string report = "conservation: the stages' counters do not balance (" +
                         std::to_string(errors.size()) + " rule" + (errors.size() == 1 ? "" : "s") +
                         " violated):";
    for (const std::string& e : errors) report += "\n  " + e;
    throw SimulationError(SimulationError::Kind::conservation, report);
  }
  if (m.recorder) m.recorder->finish(result.cycles, sc_core::sc_time_stamp().value());
  // The ROPs keep no pointer into the result once it is returned.
  gpu.set_last_writer(nullptr);
  if (progress) progress->end();
  return result;
}

GpuRunResult run_gpu(const Scene& scene, const GpuConfig& config, const GpuRunOptions& options) {
  return GpuRunner(config, options).run(scene);
}

}  // namespace gpusim
