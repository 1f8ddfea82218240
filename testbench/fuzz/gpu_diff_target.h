// Fuzz target 2: primitive setup and rasterization, differential
// (docs/robustness.md, "Fuzzing"). The input bytes decode into a frame of up
// to four raw draws in clip space (mvp = identity, no lighting): vertex
// coordinates from a grid of exact values, from a table of special values
// (NaN, infinities, FLT_MAX, denormals, w = 0, 2^-32, ...) or raw float bits;
// indices in and out of range; every primitive type and render state. The
// frame is rendered by the cycle model and by the golden model, and the
// colour buffer, the depth buffer and the pipeline counters must agree bit
// for bit. So the cycle model's arithmetic (clipper, setup's snapping, edge
// equations and fill rule, the tile rasterizer's hierarchical walk and
// incremental edge stepping, depth, interpolation, blending) is checked
// against the golden model's plain per-pixel evaluation of the spec.
//
// Driving the real SystemC modules costs a kernel run per frame, so the GPUs
// are elaborated once per process (a SystemC context cannot elaborate twice)
// and reused: nine instances with different framebuffers (1x1, 13x7, 64x48,
// 8192x2; every colour and depth format; and five small antialiased ones
// covering 1, 2, 4, 8 and 16 samples and supersampling 1, 2 and 3) and
// configurations (units, tile and stamp sizes, FIFO depths, caches, samples
// per pass), one chosen by the input's first byte (mod 9).
// Between frames the frame's registers (draws, clear values) and the memory
// image change, as a driver would program them, and the host resets the GPU
// (Gpu::reset), so a finding replays on its own; the framebuffer's size and
// formats are fixed per instance. The draws are unlit.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "stages/gpu.h"
#include "testbench/golden/golden_model.h"
#include "testbench/sim/gpu_run.h"

namespace gpusim::fuzz {

// Reads the input; past its end every byte is 0.
class ByteReader {
 public:
  ByteReader(const uint8_t* data, size_t size) : m_data(data), m_size(size) {}
  uint8_t byte() { return m_pos < m_size ? m_data[m_pos++] : 0; }
  float raw_float() {
    uint32_t bits = 0;
    for (int i = 0; i < 4; ++i) bits |= uint32_t{byte()} << (8 * i);
    float f;
    std::memcpy(&f, &bits, 4);
    return f;
  }
  // A coordinate: a grid value (scale * (b - 32) / 16 + offset), a special
  // value, or raw float bits.
  float value(float scale, float offset) {
    static const float specials[] = {0.0f,
                                     -0.0f,
                                     1.0f,
                                     -1.0f,
                                     0.5f,
                                     std::numeric_limits<float>::quiet_NaN(),
                                     std::numeric_limits<float>::infinity(),
                                     -std::numeric_limits<float>::infinity(),
                                     std::numeric_limits<float>::max(),
                                     -std::numeric_limits<float>::max(),
                                     std::numeric_limits<float>::denorm_min(),
                                     std::numeric_limits<float>::min(),
                                     1e-30f,
                                     1e30f,
                                     3e38f,
                                     -3e38f,
                                     1e6f,
                                     -1e6f,
                                     0x1p-32f,
                                     0x1p-33f,
                                     1.0f + 0x1p-23f,
                                     1.0f - 0x1p-24f,
                                     32768.0f,
                                     65536.0f,
                                     1e-7f,
                                     2.0f,
                                     -2.0f,
                                     0.999999f};
    const uint8_t s = byte();
    if (s < 0x80) return scale * static_cast<float>(static_cast<int>(s) - 32) / 16.0f + offset;
    if (s < 0xC0) return specials[(s - 0x80) % (sizeof specials / sizeof specials[0])];
    return raw_float();
  }

 private:
  const uint8_t* m_data;
  size_t m_size;
  size_t m_pos = 0;
};

// One GPU and its driver, elaborated once.
class DiffInstance {
 public:
  DiffInstance(const std::string& name, int width, int height, ColorFormat cf, DepthFormat df,
               const GpuConfig& config, unsigned samples = 1, unsigned supersample = 1)
      : m_config(config) {
    m_output.width = width;
    m_output.height = height;
    m_output.color_format = cf;
    m_output.depth_format = df;
    m_output.samples = samples;
    m_output.supersample = supersample;
    Scene empty;
    empty.framebuffer = m_output;
    // The render target (supersample times the output on each side): its
    // size and sample count decide the netlist (a Resolve stage or none).
    m_frame = load_frame(empty).frame;
    m_gpu = std::make_unique<Gpu>(name.c_str(), m_config, m_frame, uint64_t{1} << 20);
    // No watchdog (testbench/sim/watchdog.h): frames are simulated until
    // the kernel runs out of events, which a watchdog would never let happen.
    m_host = std::make_unique<Host>((name + "_host").c_str(), *m_gpu);
  }

  // The scene's framebuffer (the output; the render target is
  // supersample times larger).
  const FramebufferDesc& framebuffer() const { return m_output; }

  // Renders `scene` (its framebuffer must be this instance's) with both
  // models: "" when they agree, else the first difference.
  std::string check(const Scene& scene) {
    LoadedFrame loaded = load_frame(scene);
    m_frame = loaded.frame;
    Memory& mem = m_gpu->memory();
    mem.reset_contents(loaded.memory.size());
    std::memcpy(mem.data(0, loaded.memory.size()), loaded.memory.data(), loaded.memory.size());
    m_host->draws = scene.draws.size();
    m_host->go.notify(sc_core::SC_ZERO_TIME);
    sc_core::sc_start();  // returns when every stage is idle again

    if (!m_gpu->frame_done()) return "the frame did not complete (a hang)";
    // This frame's counts: the host reset the GPU at its start.
    const PipelineCounts counts = m_gpu->pipeline_counts();
    const golden::Result want = golden::render(scene);
    const Framebuffer got = read_framebuffer(m_gpu->memory(), m_frame, m_config);
    std::ostringstream os;
    if (counts != want.stats) {
      os << "counters differ: cycle model " << counts << ", golden " << want.stats << "\n";
    }
    for (int y = 0; y < got.height && os.tellp() == 0; ++y) {
      for (int x = 0; x < got.width; ++x) {
        const size_t p = got.pixel_index(x, y);
        if (std::equal(got.color_at(x, y), got.color_at(x, y) + 4,
                       want.framebuffer.color_at(x, y)) &&
            got.depth[p] == want.framebuffer.depth[p]) {
          continue;
        }
        os << "pixel x=" << x << " y=" << y << " differs: cycle model colour "
           << got.color_at(x, y)[0] << "," << got.color_at(x, y)[1] << "," << got.color_at(x, y)[2]
           << "," << got.color_at(x, y)[3] << " depth " << got.depth[p] << "; golden "
           << want.framebuffer.color_at(x, y)[0] << "," << want.framebuffer.color_at(x, y)[1] << ","
           << want.framebuffer.color_at(x, y)[2] << "," << want.framebuffer.color_at(x, y)[3]
           << " depth " << want.framebuffer.depth[p] << "\n";
        break;
      }
    }
    return os.str();
  }

 private:
  // Streams one frame's commands each time `go` is notified.
  class Host : public sc_core::sc_module {
   public:
    SC_HAS_PROCESS(Host);
    Host(sc_core::sc_module_name name, Gpu& gpu) : sc_core::sc_module(name), m_gpu(gpu) {
      SC_THREAD(stream);
    }
    sc_core::sc_event go;
    size_t draws = 0;

   private:
    void stream() {
      for (bool first = true;; first = false) {
        sc_core::wait(go);
        // Every frame after the first on a GPU reset to its elaborated
        // state (Gpu::reset), so a finding replays on its own.
        if (!first) m_gpu.reset();
        Fifo<Command>& q = m_gpu.command_queue();
        q.write(Command{PacketKind::clear, 0});
        for (size_t i = 0; i < draws; ++i)
          q.write(Command{PacketKind::work, static_cast<uint32_t>(i)});
        q.write(Command{PacketKind::end_of_frame, 0});
      }
    }
    Gpu& m_gpu;
  };

  GpuConfig m_config;
  FramebufferDesc m_output;
  FrameState m_frame;
  std::unique_ptr<Gpu> m_gpu;
  std::unique_ptr<Host> m_host;
};

inline std::vector<std::unique_ptr<DiffInstance>>& diff_instances() {
  static std::vector<std::unique_ptr<DiffInstance>> instances = [] {
    std::vector<std::unique_ptr<DiffInstance>> v;
    GpuConfig a;  // defaults
    GpuConfig b;
    b.units = 3;
    b.tile_size = 8;
    b.stamp = {2, 2};
    b.fifo_depth = 1;
    b.vertex_cache_entries = 3;
    b.tile_cache_entries = 1;
    b.hierarchical_z.enabled = true;  // with edge tiles, float32 depth, many frames
    b.hierarchical_z.update_latency = 0;
    GpuConfig c;
    c.units = 2;
    c.stamp = {8, 2};
    c.fifo_depth = 2;
    c.vertex_cache_entries = 0;
    GpuConfig d;
    d.units = 5;
    d.tile_size = 32;
    d.stamp = {8, 8};
    d.memory = {3, 7};
    d.hierarchical_z.enabled = true;
    v.push_back(std::make_unique<DiffInstance>("fuzz_gpu0", 1, 1, ColorFormat::rgba8,
                                               DepthFormat::unorm24, a));
    v.push_back(std::make_unique<DiffInstance>("fuzz_gpu1", 13, 7, ColorFormat::rgba16f,
                                               DepthFormat::float32, b));
    v.push_back(std::make_unique<DiffInstance>("fuzz_gpu2", 64, 48, ColorFormat::rgba8,
                                               DepthFormat::unorm16, c));
    v.push_back(std::make_unique<DiffInstance>("fuzz_gpu3", 8192, 2, ColorFormat::rgba16f,
                                               DepthFormat::unorm24, d));
    // Antialiased frames (docs/pipeline-spec.md, section 14), small: every
    // sample count, supersampling 2 and 3, alone and with multisampling.
    GpuConfig e = b;
    e.samples_per_pass = 3;
    GpuConfig f;
    f.units = 4;
    f.tile_size = 8;
    f.stamp = {4, 2};
    f.samples_per_pass = 16;
    v.push_back(std::make_unique<DiffInstance>("fuzz_gpu4", 24, 16, ColorFormat::rgba8,
                                               DepthFormat::unorm24, a, 4, 1));
    v.push_back(std::make_unique<DiffInstance>("fuzz_gpu5", 13, 7, ColorFormat::rgba16f,
                                               DepthFormat::float32, e, 2, 3));
    v.push_back(std::make_unique<DiffInstance>("fuzz_gpu6", 11, 9, ColorFormat::rgba8,
                                               DepthFormat::unorm16, f, 8, 1));
    v.push_back(std::make_unique<DiffInstance>("fuzz_gpu7", 9, 6, ColorFormat::rgba16f,
                                               DepthFormat::unorm24, c, 16, 2));
    v.push_back(std::make_unique<DiffInstance>("fuzz_gpu8", 10, 6, ColorFormat::rgba8,
                                               DepthFormat::float32, d, 1, 3));
    // Run the initialisation phase, so every host waits for `go` before the
    // first frame notifies it.
    sc_core::sc_start(sc_core::SC_ZERO_TIME);
    return v;
  }();
  return instances;
}

// Decodes the input into a scene for instance `index` (see the header).
inline Scene decode_diff_scene(const uint8_t* data, size_t size, size_t& index) {
  ByteReader in(data, size);
  index = in.byte() % diff_instances().size();
  Scene s;
  s.path = "gpu_diff_fuzz";
  s.framebuffer = diff_instances()[index]->framebuffer();
  static const float clear_values[] = {0.0f, 1.0f, 0.5f, 0.25f, 0.75f, 1e-7f, 0.999999f, 2.0f};
  s.framebuffer.clear_color = glm::vec4(clear_values[in.byte() % 8], clear_values[in.byte() % 8],
                                        clear_values[in.byte() % 8], clear_values[in.byte() % 8]);
  s.framebuffer.clear_depth = std::min(1.0f, clear_values[in.byte() % 8]);
  const int draws = in.byte() % 5;
  for (int k = 0; k < draws; ++k) {
    Draw d;
    d.name = "draws[" + std::to_string(k) + "]";
    const uint8_t flags = in.byte(), state = in.byte();
    RenderState& st = d.state;
    if ((flags & 3) == 3) {
      // Lines and points, or triangles drawn as lines or points: a byte more
      // picks the kind, the width or size and the line rule.
      const uint8_t lp = in.byte();
      static const float sizes[] = {1.0f, 1.0f, 2.0f, 3.0f, 1.5f, 0.25f, 7.0f, 64.0f};
      st.line_width = st.point_size = sizes[(lp >> 3) % 8];
      st.line_rasterization =
          lp & 0x40 ? LineRasterization::bresenham : LineRasterization::diamond_exit;
      if (lp % 8 < 4) {
        d.primitive = static_cast<PrimitiveType>(static_cast<int>(PrimitiveType::points) + lp % 4);
      } else {
        d.primitive = static_cast<PrimitiveType>(lp % 8 - 4 < 3 ? lp % 8 - 4 : 0);
        st.polygon_mode = lp & 0x80 ? PolygonMode::point : PolygonMode::line;
      }
    } else {
      d.primitive = static_cast<PrimitiveType>(flags & 3);
    }
    const bool indexed = flags & 0x04, colors = flags & 0x08;
    st.shading = flags & 0x10 ? Shading::flat : Shading::gouraud;
    st.depth_test = !(flags & 0x20);
    st.depth_write = !(flags & 0x40);
    st.blend = flags & 0x80;
    st.depth_func = static_cast<CompareFunc>(state % 8);
    st.cull = static_cast<CullMode>((state >> 3) % 3);
    st.front_face = state & 0x20 ? FrontFace::cw : FrontFace::ccw;
    if (state & 0x40) {
      const uint8_t m = in.byte();
      st.color_mask = {bool(m & 1), bool(m & 2), bool(m & 4), bool(m & 8)};
    }
    if (st.blend) {
      st.blend_src = static_cast<BlendFactor>(in.byte() % 11);
      st.blend_dst = static_cast<BlendFactor>(in.byte() % 11);
      st.blend_equation = static_cast<BlendEquation>(in.byte() % 3);
    }
    if (state & 0x80) {
      static const float offsets[] = {0.0f, 1.0f, -1.0f, 2.0f, 0.5f, -4.0f, 1e6f, -1e-3f};
      st.offset_factor = offsets[in.byte() % 8];
      st.offset_units = offsets[in.byte() % 8];
    }
    const int n = in.byte() % 25;
    for (int i = 0; i < n; ++i) {
      glm::vec4 p;
      p.x = in.value(1.0f, 0.0f);
      p.y = in.value(1.0f, 0.0f);
      p.z = in.value(0.5f, 0.0f);
      p.w = in.value(0.125f, 1.0f);  // grid: w in [0.75, 1.75)
      d.positions.push_back(p);
    }
    if (colors) {
      for (int i = 0; i < n; ++i) {
        glm::vec4 c;
        for (int ch = 0; ch < 4; ++ch) c[ch] = in.value(0.25f, 0.5f);  // grid: [0, 2)
        d.colors.push_back(c);
      }
    } else {
      d.material.diffuse =
          glm::vec4(in.byte() / 255.0f, in.byte() / 255.0f, in.byte() / 255.0f, in.byte() / 255.0f);
    }
    if (indexed) {
      const int m = in.byte() % 40;
      for (int i = 0; i < m; ++i) {
        const uint8_t b = in.byte();
        d.indices.push_back(b == 0xFF ? 0xFFFFFFFFu : b % static_cast<uint32_t>(n + 3));
      }
    }
    s.draws.push_back(std::move(d));
  }
  return s;
}

// "" when the models agree on the frame the input decodes to.
inline std::string check_gpu_diff_input(const uint8_t* data, size_t size) {
  size_t index = 0;
  const Scene scene = decode_diff_scene(data, size, index);
  return diff_instances()[index]->check(scene);
}

}  // namespace gpusim::fuzz
