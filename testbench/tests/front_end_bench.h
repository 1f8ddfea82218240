// The geometry front end as a testbench, shared by the stage tests that run
// it: the chain's own (stages_front_end_test.cpp), the vertex fetch's
// (stages_vertex_fetch_test.cpp), the vertex shader's
// (stages_vertex_shader_test.cpp) and the clipper's lines, points and polygon
// mode (stages_clipper_test.cpp). Scenes are put into a Memory and a
// FrameState as a driver would (load_frame), run through CommandProcessor ->
// VertexFetch -> VertexShader -> Clipper (FrontEndBench), and the
// ClippedPrimitive stream is compared with what golden::shade_vertex,
// assemble_triangles, clip_triangle and to_window give, bit for bit
// (expected_stream, expect_stream). Also the scenes those tests share:
// random lists, strips and fans, a lit sphere, the spider mesh.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <glm/gtc/matrix_transform.hpp>
#include <random>
#include <sstream>
#include <string>
#include <systemc>
#include <vector>

#include "hw/fifo.h"
#include "hw/memory.h"
#include "hw/vertex_packets.h"
#include "stages/clipper.h"
#include "stages/command_processor.h"
#include "stages/vertex_fetch.h"
#include "stages/vertex_shader.h"
#include "testbench/golden/golden_model.h"
#include "testbench/scene/scene.h"

namespace gpusim {
namespace test {

// ---------------------------------------------------------------------------
// The driver's job: arrays into memory, state into registers.

struct LoadedFrame {
  FrameState state;
  std::vector<uint8_t> image;  // memory contents from address 0
};

template <typename T>
uint64_t put(std::vector<uint8_t>& image, const std::vector<T>& data) {
  if (data.empty()) return kNoBuffer;
  // 64-byte aligned, and never at address 0, so a wrong "absent" test shows.
  const uint64_t addr = (image.size() + 64 + 63) / 64 * 64;
  image.resize(addr + data.size() * sizeof(T));
  std::memcpy(image.data() + addr, data.data(), data.size() * sizeof(T));
  return addr;
}

inline LoadedFrame load_frame(const Scene& scene) {
  static_assert(sizeof(glm::vec4) == 16 && sizeof(glm::vec3) == 12, "packed attributes");
  LoadedFrame f;
  f.state.framebuffer = scene.framebuffer;
  f.state.global_ambient = scene.global_ambient;
  f.state.lights = scene.lights;
  int64_t primitive = 0;
  for (const Draw& d : scene.draws) {
    DrawState s;
    s.primitive = d.primitive;
    s.buffers.positions = put(f.image, d.positions);
    s.buffers.normals = put(f.image, d.normals);
    s.buffers.colors = put(f.image, d.colors);
    s.buffers.indices = put(f.image, d.indices);
    s.buffers.vertex_count = static_cast<uint32_t>(d.positions.size());
    s.buffers.slot_count = static_cast<uint32_t>(d.vertex_count());
    s.lighting = d.lighting;
    s.material = d.material;
    s.model_view = d.model_view;
    s.mvp = d.mvp;
    s.normal_matrix = d.normal_matrix;
    s.state = d.state;
    s.first_primitive_id = primitive;
    s.varyings = varying_layout_for(s);
    primitive += static_cast<int64_t>(primitive_count(d.primitive, d.vertex_count()));
    f.state.draws.push_back(s);
  }
  f.image.resize(f.image.size() + 64);
  return f;
}

// ---------------------------------------------------------------------------
// Testbench: source -> CommandProcessor -> VertexFetch -> VertexShader ->
// Clipper -> sink, every stage joined by a Fifo of the configured depth.

struct FrontEndBench : sc_core::sc_module {
  Memory memory;
  Fifo<Command> commands;
  CommandProcessor command_processor;
  Fifo<Command> command_to_fetch;
  VertexFetch fetch;
  Fifo<VertexBatch> fetch_to_shader;
  VertexShader shader;
  Fifo<ShadedBatch> shader_to_clipper;
  Clipper clipper;
  Fifo<ClippedPrimitive> results;

  std::vector<Command> script;
  std::vector<ClippedPrimitive> got;
  std::vector<sc_core::sc_time> times;  // when the sink read each result

  SC_HAS_PROCESS(FrontEndBench);
  FrontEndBench(sc_core::sc_module_name name, const GpuConfig& config, const LoadedFrame& frame)
      : sc_core::sc_module(name),
        memory("memory", frame.image.size(), config.memory.latency, config.memory.bytes_per_cycle,
               config.cycle()),
        commands("commands", config.fifo_depth),
        command_processor("command_processor", config, frame.state),
        command_to_fetch("command_to_fetch", config.fifo_depth_of("command_to_fetch")),
        fetch("vertex_fetch", config, frame.state),
        fetch_to_shader("fetch_to_shader", config.fifo_depth_of("fetch_to_shader")),
        shader("vertex_shader", config, frame.state),
        shader_to_clipper("shader_to_clipper", config.fifo_depth_of("shader_to_clipper")),
        clipper("clipper", config, frame.state),
        results("results", config.fifo_depth_of("clipper_to_setup")) {
    memory.debug_write(0, frame.image.data(), frame.image.size());
    command_processor.in(commands);
    command_processor.out(command_to_fetch);
    fetch.in(command_to_fetch);
    fetch.out(fetch_to_shader);
    fetch.mem.bind(memory);
    shader.in(fetch_to_shader);
    shader.out(shader_to_clipper);
    clipper.in(shader_to_clipper);
    clipper.out(results);
    // clear, every draw, end of frame.
    script.push_back({PacketKind::clear, 0});
    for (uint32_t i = 0; i < frame.state.draws.size(); ++i) script.push_back({PacketKind::work, i});
    script.push_back({PacketKind::end_of_frame, 0});
    SC_THREAD(source);
    SC_THREAD(sink);
  }

  void inject_stalls(uint64_t seed, const GpuConfig& config) {
    const sc_core::sc_time cycle = config.cycle();
    commands.set_stalls(RandomStalls(commands.basename(), seed + 1, 0.3, 7, cycle));
    command_to_fetch.set_stalls(RandomStalls(command_to_fetch.basename(), seed + 2, 0.3, 7, cycle));
    fetch_to_shader.set_stalls(RandomStalls(fetch_to_shader.basename(), seed + 3, 0.3, 7, cycle));
    shader_to_clipper.set_stalls(
        RandomStalls(shader_to_clipper.basename(), seed + 4, 0.3, 7, cycle));
    results.set_stalls(RandomStalls(results.basename(), seed + 5, 0.3, 7, cycle));
  }

  void source() {
    for (const Command& c : script) commands.write(c);
  }
  void sink() {
    for (;;) {
      got.push_back(results.read());
      times.push_back(sc_core::sc_time_stamp());
    }
  }

  uint64_t stat(const StatGroup& g, const char* name) const {
    return g.to_json().at(name).get<uint64_t>();
  }
};

// ---------------------------------------------------------------------------
// What the golden model's rules give, triangle by triangle.

struct ExpectedTriangle {
  uint32_t draw_id = 0;
  int64_t primitive_id = 0;
  std::array<golden::WindowVertex, 3> v;
  std::array<float, 3> x{}, y{};  // unsnapped window x, y (spec section 5)
  glm::vec4 flat_color{0.0f};
};

struct Expected {
  std::vector<ExpectedTriangle> triangles;
  golden::Stats stats;  // the clipper's counters
};

inline bool finite4(const glm::vec4& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w);
}

inline Expected expected_stream(const Scene& scene) {
  Expected e;
  const int width = scene.framebuffer.width, height = scene.framebuffer.height;
  const golden::GuardBand gb = golden::guard_band_for(width, height);
  int64_t id = 0;
  for (uint32_t d = 0; d < scene.draws.size(); ++d) {
    const Draw& draw = scene.draws[d];
    for (const auto& slots : golden::assemble_triangles(draw.primitive, draw.vertex_count())) {
      const int64_t primitive_id = id++;
      ++e.stats.triangles_in;
      std::array<golden::ShadedVertex, 3> tri;
      bool valid = true;
      for (int k = 0; k < 3 && valid; ++k) {
        const uint32_t vi = draw.indices.empty() ? slots[k] : draw.indices[slots[k]];
        valid = vi < draw.positions.size();
        if (valid) tri[k] = golden::shade_vertex(scene, draw, vi);
        valid = valid && finite4(tri[k].clip);
      }
      if (!valid) {
        ++e.stats.triangles_invalid;
        continue;
      }
      const std::vector<golden::ShadedVertex> poly = golden::clip_triangle(tri, gb);
      if (poly.size() < 3) {
        ++e.stats.triangles_clipped_away;
        continue;
      }
      if (!(poly.size() == 3 && poly[0].clip == tri[0].clip && poly[1].clip == tri[1].clip &&
            poly[2].clip == tri[2].clip)) {
        ++e.stats.triangles_clipped;
      }
      for (size_t i = 1; i + 1 < poly.size(); ++i) {
        ExpectedTriangle t;
        t.draw_id = d;
        t.primitive_id = primitive_id;
        t.flat_color = tri[2].color;
        const size_t corner[3] = {0, i, i + 1};
        for (int k = 0; k < 3; ++k) {
          const golden::ShadedVertex& p = poly[corner[k]];
          t.v[k] = golden::to_window(p, width, height);
          t.x[k] = (p.clip.x * t.v[k].inv_w + 1.0f) * (0.5f * static_cast<float>(width));
          t.y[k] = (p.clip.y * t.v[k].inv_w + 1.0f) * (0.5f * static_cast<float>(height));
        }
        e.triangles.push_back(t);
        ++e.stats.triangles_after_clip;
      }
    }
  }
  return e;
}

// The bits of `f`, to compare floats exactly.
inline uint32_t bits(float f) {
  uint32_t b;
  std::memcpy(&b, &f, sizeof b);
  return b;
}

// Varyings holding colour `c` in the layout every draw has today
// (varying_layout_for), and 0 in every other component.
inline bool holds_color(const Varyings& v, const glm::vec4& c) {
  const VaryingLayout layout = varying_layout_for(DrawState{});
  for (unsigned k = 0; k < kMaxVaryings; ++k) {
    const bool in_color = k >= layout.color && k < layout.color + kColorComponents;
    if (bits(v[k]) != bits(in_color ? c[k - layout.color] : 0.0f)) return false;
  }
  return true;
}

// Compares the work triangles of `got` (between the clear and end-of-frame
// tokens) with the expected ones; stops at the first few differences.
inline void expect_stream(const std::vector<ClippedPrimitive>& got, const Expected& want) {
  ASSERT_GE(got.size(), 2u);
  EXPECT_EQ(got.front().kind, PacketKind::clear);
  EXPECT_EQ(got.back().kind, PacketKind::end_of_frame);
  ASSERT_EQ(got.size() - 2, want.triangles.size());
  int failures = 0;
  for (size_t i = 0; i < want.triangles.size() && failures < 5; ++i) {
    const ClippedPrimitive& g = got[i + 1];
    const ExpectedTriangle& w = want.triangles[i];
    std::ostringstream where;
    where << "triangle " << i << " (prim " << w.primitive_id << "): " << g;
    bool ok = g.kind == PacketKind::work && g.primitive_kind == PrimitiveKind::triangle &&
              g.vertex_count == 3 && g.draw_id == w.draw_id && g.primitive_id == w.primitive_id &&
              holds_color(g.flat_varyings, w.flat_color);
    for (int k = 0; k < 3; ++k) {
      const ClippedVertex& gv = g.v[k];
      const golden::WindowVertex& wv = w.v[k];
      ok = ok && snap_to_subpixel(gv.x) == wv.x && snap_to_subpixel(gv.y) == wv.y;
      ok = ok && bits(gv.x) == bits(w.x[k]) && bits(gv.y) == bits(w.y[k]);
      ok = ok && bits(gv.z) == bits(wv.z) && bits(gv.inv_w) == bits(wv.inv_w) &&
           holds_color(gv.varyings_over_w, wv.color_over_w);
    }
    if (!ok) {
      ++failures;
      ADD_FAILURE() << where.str();
    }
  }
}

// ---------------------------------------------------------------------------
// Scenes.

// A clip-space vertex of a random kind: most inside, others across the near
// or far plane, the guard band, w = 0, or absurdly far.
inline glm::vec4 random_clip_vertex(std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::uniform_real_distribution<float> pos_w(0.3f, 3.0f);
  const int kind = std::uniform_int_distribution<int>(0, 99)(rng);
  const float w = pos_w(rng);
  if (kind < 45) return {1.2f * u(rng) * w, 1.2f * u(rng) * w, 1.2f * u(rng) * w, w};
  if (kind < 60) {
    // Guard band at |x/w| ~ 256 for a 256-pixel framebuffer.
    const float side = u(rng) < 0.0f ? -1.0f : 1.0f;
    const float g = side * (150.0f + 250.0f * (u(rng) + 1.0f));
    if (u(rng) < 0.0f) return {g * w, u(rng) * w, 0.5f * u(rng) * w, w};
    return {u(rng) * w, g * w, 0.5f * u(rng) * w, w};
  }
  if (kind < 75) return {u(rng), u(rng), u(rng), 0.7f * u(rng)};  // w around 0
  if (kind < 88) return {u(rng) * w, u(rng) * w, (1.0f + 2.0f * std::fabs(u(rng))) * u(rng) * w, w};
  if (kind < 94) return {1e6f * u(rng), 1e6f * u(rng), 1e3f * u(rng), w};
  if (kind < 97) return {u(rng), u(rng), 0.5f, 0.0f};  // exactly w = 0
  return {u(rng) * w, u(rng) * w, u(rng) * w, -w};     // behind the eye
}

inline glm::vec4 random_color(std::mt19937& rng) {
  std::uniform_real_distribution<float> c(-0.2f, 1.2f);  // clamped by the shader
  return {c(rng), c(rng), c(rng), c(rng)};
}

inline Draw random_draw(std::mt19937& rng, PrimitiveType primitive, size_t vertices, bool colors,
                        size_t indices) {
  Draw d;
  d.primitive = primitive;
  for (size_t i = 0; i < vertices; ++i) {
    d.positions.push_back(random_clip_vertex(rng));
    if (colors) d.colors.push_back(random_color(rng));
  }
  std::uniform_int_distribution<uint32_t> pick(0, static_cast<uint32_t>(vertices) - 1);
  // Indices concentrated on a small window moving through the vertices, so
  // the cache sees reuse at every distance.
  for (size_t i = 0; i < indices; ++i) {
    const uint32_t centre = static_cast<uint32_t>(i * vertices / indices);
    const uint32_t off = std::uniform_int_distribution<uint32_t>(0, 40)(rng);
    d.indices.push_back(
        std::uniform_int_distribution<int>(0, 9)(rng) == 0
            ? pick(rng)
            : std::min<uint32_t>(centre + off, static_cast<uint32_t>(vertices) - 1));
  }
  d.material.diffuse = {0.3f, 0.6f, 0.9f, 0.5f};
  return d;
}

inline Scene random_scene(uint32_t seed) {
  std::mt19937 rng(seed);
  Scene s;
  s.framebuffer.width = 256;
  s.framebuffer.height = 192;  // not square: x and y guard bands differ
  // Lists, strips and fans, indexed or not, with and without colours; the
  // long ones cross several batch boundaries (32 slots).
  s.draws.push_back(random_draw(rng, PrimitiveType::triangles, 900, true, 0));
  s.draws.push_back(random_draw(rng, PrimitiveType::triangle_strip, 131, true, 0));
  s.draws.push_back(random_draw(rng, PrimitiveType::triangle_fan, 77, false, 0));
  s.draws.push_back(random_draw(rng, PrimitiveType::triangles, 200, true, 601));
  s.draws.push_back(random_draw(rng, PrimitiveType::triangle_strip, 90, true, 150));
  s.draws.push_back(random_draw(rng, PrimitiveType::triangle_fan, 60, true, 100));
  // Tiny draws: below one triangle, exactly one, a partial last triangle.
  s.draws.push_back(random_draw(rng, PrimitiveType::triangle_strip, 2, true, 0));
  s.draws.push_back(random_draw(rng, PrimitiveType::triangle_fan, 3, false, 0));
  s.draws.push_back(random_draw(rng, PrimitiveType::triangles, 5, true, 0));
  return s;
}

// A lit, indexed sphere (shared vertices: the cache hits), with specular
// highlights, a directional and an attenuated point light, and a perspective
// camera whose near plane cuts it.
inline Scene lit_sphere_scene() {
  Scene s;
  s.framebuffer.width = 320;
  s.framebuffer.height = 240;
  s.global_ambient = {0.1f, 0.12f, 0.15f, 1.0f};
  Light sun;
  sun.type = LightType::directional;
  sun.vector = glm::normalize(glm::vec3(0.3f, 0.8f, 0.5f));
  sun.ambient = {0.05f, 0.05f, 0.05f, 1.0f};
  sun.diffuse = {0.8f, 0.75f, 0.7f, 1.0f};
  sun.specular = {0.9f, 0.9f, 0.9f, 1.0f};
  Light lamp;
  lamp.type = LightType::point;
  lamp.vector = {-2.5f, 1.5f, 0.5f};  // outside the sphere, towards the camera
  lamp.ambient = {0.1f, 0.05f, 0.02f, 1.0f};
  lamp.diffuse = {0.2f, 0.3f, 0.9f, 1.0f};
  lamp.specular = {0.5f, 0.5f, 1.0f, 1.0f};
  lamp.constant_attenuation = 0.3f;
  lamp.linear_attenuation = 0.0731f;
  lamp.quadratic_attenuation = 0.0177f;
  s.lights = {sun, lamp};

  Draw d;
  d.name = "sphere";
  const int rings = 24, sectors = 32;
  for (int r = 0; r <= rings; ++r) {
    const float phi = 3.14159265f * static_cast<float>(r) / rings;
    for (int q = 0; q <= sectors; ++q) {
      const float theta = 6.2831853f * static_cast<float>(q) / sectors;
      const glm::vec3 n(std::sin(phi) * std::cos(theta), std::cos(phi),
                        std::sin(phi) * std::sin(theta));
      d.positions.push_back(glm::vec4(1.5f * n, 1.0f));
      d.normals.push_back(n);
    }
  }
  for (int r = 0; r < rings; ++r) {
    for (int q = 0; q < sectors; ++q) {
      const uint32_t a = r * (sectors + 1) + q, b = a + sectors + 1;
      d.indices.insert(d.indices.end(), {a, b, a + 1, a + 1, b, b + 1});
    }
  }
  d.lighting = true;
  d.material.ambient = {0.3f, 0.2f, 0.2f, 1.0f};
  d.material.diffuse = {0.7f, 0.5f, 0.3f, 0.8f};
  d.material.specular = {0.6f, 0.6f, 0.6f, 1.0f};
  d.material.emission = {0.02f, 0.0f, 0.05f, 1.0f};
  d.material.shininess = 12.0f;
  d.model_view = glm::rotate(glm::translate(glm::mat4(1.0f), glm::vec3(0.3f, -0.2f, -2.2f)), 0.7f,
                             glm::vec3(0.2f, 1.0f, 0.1f));
  d.projection = glm::perspective(glm::radians(60.0f), 320.0f / 240.0f, 1.0f, 10.0f);
  d.mvp = d.projection * d.model_view;
  d.normal_matrix = glm::transpose(glm::inverse(glm::mat3(d.model_view)));
  s.draws.push_back(d);

  // The same sphere as a strip-less list, unlit with colours, far away: no
  // normals read, colours read.
  Draw c = d;
  c.lighting = false;
  c.normals.clear();
  for (size_t i = 0; i < c.positions.size(); ++i) {
    c.colors.push_back({0.5f + 0.5f * c.positions[i].x, 0.5f, 0.25f, 1.0f});
  }
  c.model_view = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, -8.5f));
  c.mvp = c.projection * c.model_view;
  s.draws.push_back(c);
  return s;
}

inline Scene spider_scene() {
  return load_scene(std::string(GPUSIM_SOURCE_DIR) + "/testbench/scenes/spider.json");
}

inline GpuConfig config_with(unsigned cache_entries, unsigned fifo_depth) {
  GpuConfig c;
  c.vertex_cache_entries = cache_entries;
  c.fifo_depth = fifo_depth;
  return c;
}

// The line strip's vertex i, inside the frustum: window x = 8 + i, y = 64 ± 16 on
// stages_clipper_test's 128 x 128 framebuffer.
inline glm::vec4 strip_vertex(size_t i) {
  return {(static_cast<float>(i) - 56.0f) / 64.0f, (i % 2 ? 0.25f : -0.25f), 0.0f, 1.0f};
}

// A counter-clockwise triangle in clip space, inside the frustum.
inline const std::vector<glm::vec4> kCcw = {
    {-0.5f, -0.5f, 0.0f, 1.0f}, {0.5f, -0.5f, 0.0f, 1.0f}, {0.0f, 0.5f, 0.0f, 1.0f}};

}  // namespace test
}  // namespace gpusim
