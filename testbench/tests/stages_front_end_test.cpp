// The geometry front end (command processor -> vertex fetch -> vertex shader
// -> clipper) against the golden model's rules: scenes are built here (or
// loaded), put into a Memory and a FrameState as a driver would, run through
// the four stages, and the ClippedPrimitive stream is compared with what
// golden::shade_vertex, assemble_triangles, clip_triangle and to_window give,
// bit for bit. Also: cache hit counts and memory traffic for known index
// patterns, exact timing of simple cases, and unchanged outputs under random
// FIFO stalls. One sc_start per TEST (ctest runs each in its own process).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <memory>
#include <random>
#include <sstream>
#include <string>
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
namespace {

using sc_core::sc_time;

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

LoadedFrame load_frame(const Scene& scene) {
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

struct Bench : sc_core::sc_module {
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
  std::vector<sc_time> times;  // when the sink read each result

  SC_HAS_PROCESS(Bench);
  Bench(sc_core::sc_module_name name, const GpuConfig& config, const LoadedFrame& frame)
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
    const sc_time cycle = config.cycle();
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

bool finite4(const glm::vec4& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w);
}

Expected expected_stream(const Scene& scene) {
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

uint32_t bits(float f) {
  uint32_t b;
  std::memcpy(&b, &f, sizeof b);
  return b;
}
bool same_bits(const glm::vec4& a, const glm::vec4& b) {
  return bits(a.x) == bits(b.x) && bits(a.y) == bits(b.y) && bits(a.z) == bits(b.z) &&
         bits(a.w) == bits(b.w);
}
// Varyings holding colour `c` in the layout every draw has today
// (varying_layout_for), and 0 in every other component.
bool holds_color(const Varyings& v, const glm::vec4& c) {
  const VaryingLayout layout = varying_layout_for(DrawState{});
  for (unsigned k = 0; k < kMaxVaryings; ++k) {
    const bool in_color = k >= layout.color && k < layout.color + kColorComponents;
    if (bits(v[k]) != bits(in_color ? c[k - layout.color] : 0.0f)) return false;
  }
  return true;
}

// Compares the work triangles of `got` (between the clear and end-of-frame
// tokens) with the expected ones; stops at the first few differences.
void expect_stream(const std::vector<ClippedPrimitive>& got, const Expected& want) {
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

void expect_clipper_stats(const Bench& b, const golden::Stats& s) {
  EXPECT_EQ(b.stat(b.clipper.stats(), "triangles_in"), s.triangles_in);
  EXPECT_EQ(b.stat(b.clipper.stats(), "triangles_invalid"), s.triangles_invalid);
  EXPECT_EQ(b.stat(b.clipper.stats(), "triangles_clipped_away"), s.triangles_clipped_away);
  EXPECT_EQ(b.stat(b.clipper.stats(), "triangles_clipped"), s.triangles_clipped);
  EXPECT_EQ(b.stat(b.clipper.stats(), "triangles_after_clip"), s.triangles_after_clip);
}

// ---------------------------------------------------------------------------
// Scenes.

// A clip-space vertex of a random kind: most inside, others across the near
// or far plane, the guard band, w = 0, or absurdly far.
glm::vec4 random_clip_vertex(std::mt19937& rng) {
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

glm::vec4 random_color(std::mt19937& rng) {
  std::uniform_real_distribution<float> c(-0.2f, 1.2f);  // clamped by the shader
  return {c(rng), c(rng), c(rng), c(rng)};
}

Draw random_draw(std::mt19937& rng, PrimitiveType primitive, size_t vertices, bool colors,
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

Scene random_scene(uint32_t seed) {
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

// Out-of-range indices and non-finite positions, in every primitive type.
Scene invalid_scene() {
  std::mt19937 rng(7);
  Scene s;
  s.framebuffer.width = 200;
  s.framebuffer.height = 100;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  for (PrimitiveType p :
       {PrimitiveType::triangles, PrimitiveType::triangle_strip, PrimitiveType::triangle_fan}) {
    Draw d = random_draw(rng, p, 40, true, 0);
    d.positions[3] = {nan, 0.0f, 0.0f, 1.0f};
    d.positions[10] = {0.0f, 0.0f, inf, 1.0f};
    d.positions[17] = {0.1f, 0.1f, 0.1f, -inf};
    d.colors[20] = {nan, nan, 2.0f, -1.0f};  // colours clamp: NaN -> 0; harmless
    for (uint32_t i = 0; i < 90; ++i) d.indices.push_back((i * 7 + i / 5) % 40);
    d.indices[5] = 40;            // one past the end
    d.indices[31] = 0xFFFFFFFFu;  // at a batch edge
    d.indices[32] = 1000;
    d.indices[60] = 3;  // NaN vertex through the cache too
    d.indices[61] = 3;
    s.draws.push_back(d);
  }
  // Non-indexed with NaN: every triangle using it is dropped.
  Draw d = random_draw(rng, PrimitiveType::triangle_strip, 20, false, 0);
  d.positions[9] = {0.0f, nan, 0.0f, 1.0f};
  s.draws.push_back(d);
  return s;
}

// A lit, indexed sphere (shared vertices: the cache hits), with specular
// highlights, a directional and an attenuated point light, and a perspective
// camera whose near plane cuts it.
Scene lit_sphere_scene() {
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

Scene spider_scene() {
  return load_scene(std::string(GPUSIM_SOURCE_DIR) + "/testbench/scenes/spider.json");
}

// Runs `scene` through the front end and checks it against the golden rules.
void run_and_compare(const Scene& scene, GpuConfig config, uint64_t stall_seed = 0) {
  const LoadedFrame frame = load_frame(scene);
  const Expected want = expected_stream(scene);
  Bench bench("bench", config, frame);
  if (stall_seed != 0) bench.inject_stalls(stall_seed, config);
  sc_core::sc_start();
  if (stall_seed != 0) {
    // The stalls happened, on every boundary.
    EXPECT_GT(bench.command_to_fetch.stats().injected_stalls, 0u);
    EXPECT_GT(bench.fetch_to_shader.stats().injected_stalls, 10u);
    EXPECT_GT(bench.shader_to_clipper.stats().injected_stalls, 10u);
    EXPECT_GT(bench.results.stats().injected_stalls, 100u);
  }
  expect_stream(bench.got, want);
  expect_clipper_stats(bench, want.stats);
  // The golden renderer's own counters agree with the expected stream.
  const golden::Stats g = golden::render(scene).stats;
  EXPECT_EQ(want.stats.triangles_in, g.triangles_in);
  EXPECT_EQ(want.stats.triangles_invalid, g.triangles_invalid);
  EXPECT_EQ(want.stats.triangles_clipped_away, g.triangles_clipped_away);
  EXPECT_EQ(want.stats.triangles_clipped, g.triangles_clipped);
  EXPECT_EQ(want.stats.triangles_after_clip, g.triangles_after_clip);
  // Hits read what misses wrote, one for one.
  EXPECT_EQ(bench.stat(bench.fetch.stats(), "cache_hits"),
            bench.stat(bench.clipper.stats(), "cache_reads"));
  EXPECT_EQ(bench.stat(bench.fetch.stats(), "vertices_fetched"),
            bench.stat(bench.shader.stats(), "vertices_shaded"));
}

GpuConfig config_with(unsigned cache_entries, unsigned fifo_depth) {
  GpuConfig c;
  c.vertex_cache_entries = cache_entries;
  c.fifo_depth = fifo_depth;
  return c;
}

// ---------------------------------------------------------------------------
// Golden equivalence.

TEST(FrontEnd, RandomListsStripsFansMatchGolden) {
  const Scene scene = random_scene(1);
  // The scene must exercise what it claims to.
  const Expected e = expected_stream(scene);
  EXPECT_GT(e.stats.triangles_clipped, 50u);
  EXPECT_GT(e.stats.triangles_clipped_away, 30u);
  EXPECT_GT(e.stats.triangles_after_clip,
            e.stats.triangles_in - e.stats.triangles_invalid - e.stats.triangles_clipped_away);
  run_and_compare(scene, GpuConfig{});
}

// Every cache size gives the same stream (and the mirror holds): none, one
// entry (hits only on immediate repeats), odd, default, larger than a draw.
class FrontEndCacheSizes : public ::testing::TestWithParam<unsigned> {};
TEST_P(FrontEndCacheSizes, RandomSceneMatchesGolden) {
  run_and_compare(random_scene(2), config_with(GetParam(), 2));
}
INSTANTIATE_TEST_SUITE_P(Entries, FrontEndCacheSizes, ::testing::Values(0u, 1u, 7u, 32u, 4096u));

TEST(FrontEnd, DepthOneFifosMatchGolden) {
  run_and_compare(random_scene(3), config_with(32, 1));
}

TEST(FrontEnd, InvalidIndicesAndNonFinitePositionsAreDropped) {
  const Scene scene = invalid_scene();
  const Expected e = expected_stream(scene);
  EXPECT_GT(e.stats.triangles_invalid, 20u);
  run_and_compare(scene, config_with(8, 4));
}

TEST(FrontEnd, LitIndexedSphereMatchesGolden) {
  const Scene scene = lit_sphere_scene();
  const Expected e = expected_stream(scene);
  EXPECT_GT(e.stats.triangles_clipped, 0u);  // the near plane cuts the sphere
  run_and_compare(scene, GpuConfig{});
}

TEST(FrontEnd, SpiderMeshMatchesGolden) {
  const Scene scene = spider_scene();
  ASSERT_TRUE(scene.draws.at(0).lighting);
  run_and_compare(scene, GpuConfig{});
}

TEST(FrontEnd, RandomStallsChangeNoOutput) {
  const Scene scene = random_scene(4);
  const GpuConfig config = config_with(16, 2);
  run_and_compare(scene, config, /*stall_seed=*/99);
}

// The shader alone against golden::shade_vertex for every vertex of the
// spider and the sphere: with the cache disabled, the fetched vertices of a
// batch are its valid slots in order.
struct ShaderBench : sc_core::sc_module {
  Memory memory;
  Fifo<Command> commands;
  VertexFetch fetch;
  Fifo<VertexBatch> fetch_to_shader;
  VertexShader shader;
  Fifo<ShadedBatch> results;
  const LoadedFrame& frame;
  std::vector<ShadedBatch> got;

  SC_HAS_PROCESS(ShaderBench);
  ShaderBench(sc_core::sc_module_name name, const GpuConfig& config, const LoadedFrame& f)
      : sc_core::sc_module(name),
        memory("memory", f.image.size(), 20, 32, config.cycle()),
        commands("commands", 4),
        fetch("vertex_fetch", config, f.state),
        fetch_to_shader("fetch_to_shader", 4),
        shader("vertex_shader", config, f.state),
        results("results", 4),
        frame(f) {
    memory.debug_write(0, f.image.data(), f.image.size());
    fetch.in(commands);
    fetch.out(fetch_to_shader);
    fetch.mem.bind(memory);
    shader.in(fetch_to_shader);
    shader.out(results);
    SC_THREAD(source);
    SC_THREAD(sink);
  }
  void source() {
    for (uint32_t i = 0; i < frame.state.draws.size(); ++i) commands.write({PacketKind::work, i});
  }
  void sink() {
    for (;;) got.push_back(results.read());
  }
};

TEST(VertexShader, EveryVertexMatchesGoldenShadeVertex) {
  Scene scene = spider_scene();
  const Scene sphere = lit_sphere_scene();
  scene.draws.insert(scene.draws.end(), sphere.draws.begin(), sphere.draws.end());
  scene.lights.insert(scene.lights.end(), sphere.lights.begin(), sphere.lights.end());
  const Scene random = random_scene(5);
  scene.draws.push_back(random.draws[0]);  // unlit, coloured
  scene.draws.push_back(random.draws[2]);  // unlit, material colour
  const LoadedFrame frame = load_frame(scene);
  const GpuConfig config = config_with(0, 4);
  ShaderBench bench("bench", config, frame);
  sc_core::sc_start();

  size_t checked = 0, lit = 0;
  int failures = 0;
  for (const ShadedBatch& b : bench.got) {
    ASSERT_EQ(b.kind, PacketKind::work);
    const Draw& draw = scene.draws.at(b.draw_id);
    for (uint32_t i = 0; i < b.slot_count; ++i) {
      const VertexSlot& slot = b.slots[i];
      const uint32_t slot_number = b.first_slot + i;
      const uint32_t index = draw.indices.empty() ? slot_number : draw.indices[slot_number];
      ASSERT_EQ(slot.kind, SlotKind::fetched);  // no cache, all in range
      const golden::ShadedVertex want = golden::shade_vertex(scene, draw, index);
      const ShadedVertex& v = b.vertices[slot.vertex];
      if (!(same_bits(v.clip, want.clip) && holds_color(v.varyings, want.color)) &&
          failures++ < 5) {
        ADD_FAILURE() << "draw " << b.draw_id << " slot " << slot_number << " vertex " << index;
      }
      ++checked;
      if (draw.lighting) ++lit;
    }
  }
  size_t slots = 0;
  for (const Draw& d : scene.draws) slots += d.vertex_count();
  EXPECT_EQ(checked, slots);
  EXPECT_GT(lit, 5000u);
}

// ---------------------------------------------------------------------------
// The vertex cache: hits for a known pattern, FIFO replacement, flushing
// between draws, memory traffic.

TEST(VertexFetch, CacheHitsFollowFifoReplacement) {
  // 4 entries, FIFO replacement, indices in one batch:
  //   0 1 2 | 2 1 3 | 0 4 5 | 1 2 3
  //   0 m(e0) 1 m(e1) 2 m(e2) | 2 hit, 1 hit, 3 m(e3) | 0 hit (LRU would
  //   refresh it; FIFO does not), 4 m evicts 0 (e0), 5 m evicts 1 (e1) |
  //   1 m evicts 2 (e2), 2 m evicts 3 (e3), 3 m evicts 4 (e0).
  // Hits 3, misses 9. The same draw twice: the cache is flushed at the
  // second draw, which counts the same again.
  Scene scene;
  scene.framebuffer.width = 64;
  scene.framebuffer.height = 64;
  Draw d;
  for (int i = 0; i < 6; ++i) {
    d.positions.push_back({0.1f * i, 0.05f * i * i - 0.5f, 0.0f, 1.0f});
  }
  d.indices = {0, 1, 2, 2, 1, 3, 0, 4, 5, 1, 2, 3};
  scene.draws = {d, d};
  const LoadedFrame frame = load_frame(scene);
  const GpuConfig config = config_with(4, 4);
  Bench bench("bench", config, frame);
  sc_core::sc_start();
  expect_stream(bench.got, expected_stream(scene));
  const StatGroup& f = bench.fetch.stats();
  EXPECT_EQ(bench.stat(f, "slots"), 24u);
  EXPECT_EQ(bench.stat(f, "cache_lookups"), 24u);
  EXPECT_EQ(bench.stat(f, "cache_hits"), 6u);
  EXPECT_EQ(bench.stat(f, "cache_misses"), 18u);
  EXPECT_DOUBLE_EQ(f.to_json().at("cache_hit_rate").get<double>(), 0.25);
  // Per draw: 48 bytes of indices in one request; misses in fetch order
  // 0 1 2 3 4 5 1 2 3 are two bursts of positions (16 bytes each vertex).
  EXPECT_EQ(bench.stat(f, "memory_requests"), 2u * 3u);
  EXPECT_EQ(bench.stat(f, "bytes_read"), 2u * (48u + 9u * 16u));
  EXPECT_EQ(bench.stat(bench.clipper.stats(), "cache_writes"), 18u);
  EXPECT_EQ(bench.stat(bench.clipper.stats(), "cache_reads"), 6u);
  // The memory saw the same traffic.
  const nlohmann::json m = bench.memory.stat_group().to_json().at("clients").at("vertex_fetch");
  EXPECT_EQ(m.at("bytes_read").get<uint64_t>(), 2u * (48u + 9u * 16u));
  EXPECT_EQ(m.at("reads").get<uint64_t>(), 6u);
}

TEST(VertexFetch, DisabledCacheAndNonIndexedDrawsFetchEverySlot) {
  // Lit with normals and colours: 16 + 12 + 16 bytes per fetched vertex.
  Scene scene;
  Draw d;
  for (int i = 0; i < 10; ++i) {
    d.positions.push_back({0.1f * i, 0.2f, 0.0f, 1.0f});
    d.normals.push_back({0.0f, 0.0f, 1.0f});
    d.colors.push_back({1.0f, 0.5f, 0.25f, 1.0f});
  }
  d.lighting = true;
  d.indices = {0, 1, 2, 2, 1, 3, 7, 8, 9};  // a burst 0-2, then 2, 1, 3, a burst 7-9
  Draw flat = d;
  flat.indices.clear();   // 10 slots, one burst per attribute
  flat.lighting = false;  // normals not read
  scene.draws = {d, flat};
  const LoadedFrame frame = load_frame(scene);
  const GpuConfig config = config_with(0, 4);
  Bench bench("bench", config, frame);
  sc_core::sc_start();
  expect_stream(bench.got, expected_stream(scene));
  const StatGroup& f = bench.fetch.stats();
  EXPECT_EQ(bench.stat(f, "cache_lookups"), 9u);
  EXPECT_EQ(bench.stat(f, "cache_hits"), 0u);
  EXPECT_EQ(bench.stat(f, "vertices_fetched"), 19u);
  // Indexed: 1 index read + the bursts of consecutive indices in fetch order
  // {0 1 2} {2} {1} {3} {7 8 9}, x 3 attributes. Non-indexed: one burst of
  // positions and one of colours.
  EXPECT_EQ(bench.stat(f, "memory_requests"), 1u + 5u * 3u + 2u);
  EXPECT_EQ(bench.stat(f, "bytes_read"), 9u * 4u + 9u * 44u + 10u * 32u);
  EXPECT_EQ(bench.stat(bench.shader.stats(), "vertices_lit"), 9u);
}

// ---------------------------------------------------------------------------
// Points, lines and polygon mode, against expectations derived here from the
// spec (sections 3, 4b, 4c, 4d): draws in clip space (identity matrices) on a
// 128 x 128 framebuffer, where x_w = (x / w + 1) * 64, so vertices at
// multiples of 1/64 map to exact window coordinates.

constexpr int kSide = 128;

// Vertex i's colour: distinct and exact, to tell provoking vertices apart.
glm::vec4 color_of(size_t i) {
  return {static_cast<float>(i) / 64.0f, 0.5f, 0.25f, 1.0f};
}

Draw clip_space_draw(PrimitiveType primitive, const std::vector<glm::vec4>& positions) {
  Draw d;
  d.primitive = primitive;
  d.positions = positions;
  for (size_t i = 0; i < positions.size(); ++i) d.colors.push_back(color_of(i));
  return d;
}

Scene clip_space_scene(std::vector<Draw> draws) {
  Scene s;
  s.framebuffer.width = kSide;
  s.framebuffer.height = kSide;
  s.draws = std::move(draws);
  return s;
}

// Runs the front end on `scene`; returns the work primitives it wrote and
// the clipper's counters.
struct FrontEndRun {
  std::vector<ClippedPrimitive> prims;
  nlohmann::json clipper;
};
FrontEndRun run_front_end(const Scene& scene, const GpuConfig& config = GpuConfig{}) {
  const LoadedFrame frame = load_frame(scene);
  Bench bench("bench", config, frame);
  sc_core::sc_start();
  FrontEndRun r;
  for (const ClippedPrimitive& p : bench.got) {
    if (p.kind == PacketKind::work) r.prims.push_back(p);
  }
  r.clipper = bench.clipper.stats().to_json();
  return r;
}

// The line strip's vertex i, inside the frustum: window x = 8 + i, y = 64 ± 16.
glm::vec4 strip_vertex(size_t i) {
  return {(static_cast<float>(i) - 56.0f) / 64.0f, (i % 2 ? 0.25f : -0.25f), 0.0f, 1.0f};
}

TEST(FrontEndLines, StripOfNVerticesGivesNMinusOneLines) {
  // 37 slots: the strip crosses a batch boundary (32 slots). A triangle
  // list of 2 triangles before it: its lines are numbered from 2.
  std::vector<glm::vec4> tri(6, glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
  std::vector<glm::vec4> strip;
  for (size_t i = 0; i < 37; ++i) strip.push_back(strip_vertex(i));
  const FrontEndRun r =
      run_front_end(clip_space_scene({clip_space_draw(PrimitiveType::triangles, tri),
                                      clip_space_draw(PrimitiveType::line_strip, strip)}));
  // The two triangles are degenerate but the clipper passes them on.
  ASSERT_EQ(r.prims.size(), 2u + 36u);
  for (size_t i = 0; i < 36; ++i) {
    const ClippedPrimitive& l = r.prims[2 + i];
    SCOPED_TRACE("line " + std::to_string(i));
    EXPECT_EQ(l.primitive_kind, PrimitiveKind::line);
    EXPECT_EQ(l.vertex_count, 2);
    EXPECT_EQ(l.draw_id, 1u);
    EXPECT_EQ(l.primitive_id, static_cast<int64_t>(2 + i));
    EXPECT_EQ(l.draw_first, i == 0);  // later lines share their first vertex
    EXPECT_TRUE(l.draw_last);
    EXPECT_EQ(l.v[0].x, 8.0f + i);
    EXPECT_EQ(l.v[1].x, 9.0f + i);
    EXPECT_EQ(l.v[0].y, i % 2 ? 80.0f : 48.0f);
    EXPECT_EQ(l.v[1].inv_w, 1.0f);
    EXPECT_TRUE(holds_color(l.v[1].varyings_over_w, color_of(i + 1)));
    EXPECT_TRUE(holds_color(l.flat_varyings, color_of(i + 1)));  // the last vertex
  }
  EXPECT_EQ(r.clipper.at("lines_in"), 36u);
  EXPECT_EQ(r.clipper.at("lines_out"), 36u);
  EXPECT_EQ(r.clipper.at("lines_clipped"), 0u);
  EXPECT_EQ(r.clipper.at("triangles_in"), 2u);
}

TEST(FrontEndLines, ListsAndLoops) {
  // lines of 5 slots: 2 lines, the partial last one ignored, both ends drawn.
  // line_loop of 33 slots (across a batch boundary): 33 lines, the closing
  // one (32, 0) with both flags clear and vertex 0's colour. Loops of 1 and
  // 2 slots: none, and (0, 1), (1, 0).
  std::vector<glm::vec4> v;
  for (size_t i = 0; i < 33; ++i) v.push_back(strip_vertex(i));
  const std::vector<glm::vec4> five(v.begin(), v.begin() + 5);
  const std::vector<glm::vec4> one(v.begin(), v.begin() + 1);
  const std::vector<glm::vec4> two(v.begin(), v.begin() + 2);
  const FrontEndRun r = run_front_end(clip_space_scene(
      {clip_space_draw(PrimitiveType::lines, five), clip_space_draw(PrimitiveType::line_loop, v),
       clip_space_draw(PrimitiveType::line_loop, one),
       clip_space_draw(PrimitiveType::line_loop, two)}));
  ASSERT_EQ(r.prims.size(), 2u + 33u + 0u + 2u);
  for (size_t i = 0; i < 2; ++i) {
    const ClippedPrimitive& l = r.prims[i];
    EXPECT_EQ(l.primitive_id, static_cast<int64_t>(i));
    EXPECT_EQ(l.v[0].x, 8.0f + 2 * i);
    EXPECT_EQ(l.v[1].x, 9.0f + 2 * i);
    EXPECT_TRUE(l.draw_first && l.draw_last);
    EXPECT_TRUE(holds_color(l.flat_varyings, color_of(2 * i + 1)));
  }
  for (size_t i = 0; i < 33; ++i) {
    const ClippedPrimitive& l = r.prims[2 + i];
    SCOPED_TRACE("loop line " + std::to_string(i));
    EXPECT_EQ(l.draw_id, 1u);
    EXPECT_EQ(l.primitive_id, static_cast<int64_t>(2 + i));
    const size_t a = i, b = (i + 1) % 33;
    EXPECT_EQ(l.v[0].x, 8.0f + a);
    EXPECT_EQ(l.v[1].x, 8.0f + b);
    EXPECT_EQ(l.draw_first, i == 0);
    EXPECT_EQ(l.draw_last, i != 32);
    EXPECT_TRUE(holds_color(l.flat_varyings, color_of(b)));
  }
  const ClippedPrimitive& p = r.prims[35];
  const ClippedPrimitive& q = r.prims[36];
  EXPECT_EQ(p.draw_id, 3u);
  EXPECT_EQ(p.primitive_id, 2 + 33 + 0);
  EXPECT_EQ(q.primitive_id, 2 + 33 + 1);
  EXPECT_TRUE(p.draw_first && p.draw_last);
  EXPECT_TRUE(!q.draw_first && !q.draw_last);
  EXPECT_EQ(q.v[0].x, 9.0f);
  EXPECT_EQ(q.v[1].x, 8.0f);
  EXPECT_TRUE(holds_color(q.flat_varyings, color_of(0)));
  EXPECT_EQ(r.clipper.at("lines_in"), 37u);
}

TEST(FrontEndLines, IndexedLinesWithAnInvalidIndexAreDropped) {
  // Indices 0 1 | 1 9 | 2 3: the second line's vertex 9 does not exist. A
  // loop over 0 1 9 2: lines (0 1), (1 9) and (9 2) invalid, (2 0) closes.
  std::vector<glm::vec4> v;
  for (size_t i = 0; i < 4; ++i) v.push_back(strip_vertex(i));
  Draw lines = clip_space_draw(PrimitiveType::lines, v);
  lines.indices = {0, 1, 1, 9, 2, 3};
  Draw loop = clip_space_draw(PrimitiveType::line_loop, v);
  loop.indices = {0, 1, 9, 2};
  const FrontEndRun r = run_front_end(clip_space_scene({lines, loop}));
  ASSERT_EQ(r.prims.size(), 4u);
  EXPECT_EQ(r.prims[0].primitive_id, 0);
  EXPECT_EQ(r.prims[1].primitive_id, 2);
  EXPECT_EQ(r.prims[2].primitive_id, 3);  // the loop's first line
  EXPECT_EQ(r.prims[3].primitive_id, 6);  // its closing line (2, 0)
  EXPECT_EQ(r.prims[3].v[0].x, 10.0f);
  EXPECT_EQ(r.prims[3].v[1].x, 8.0f);
  EXPECT_EQ(r.clipper.at("lines_in"), 7u);
  EXPECT_EQ(r.clipper.at("lines_invalid"), 3u);
}

TEST(FrontEndLines, LineCrossingTheNearPlaneIsCutOnIt) {
  // Line 0: a = (0.5, 0.25, -2, 1) has z + w = -1, b = (-0.5, 0, 0, 1) has
  // z + w = 1: equal distances, so the cut starts from the inside endpoint
  // b, t = 1 / (1 - -1) = 0.5 exactly, and the new a is the midpoint
  // (0, 0.125, -1, 1), colour midway: window (64, 72, z 0).
  // Line 1: a = (0.5, 0, -3, 1) (z + w = -2), b = (0, 0, 0.5, 1) (1.5): the
  // cut starts from b, nearer: t = 1.5 / 3.5 = 3/7, the plane z = -w at
  // x = 3/14 (the analytic crossing, to float rounding).
  Draw d = clip_space_draw(PrimitiveType::lines, {{0.5f, 0.25f, -2.0f, 1.0f},
                                                  {-0.5f, 0.0f, 0.0f, 1.0f},
                                                  {0.5f, 0.0f, -3.0f, 1.0f},
                                                  {0.0f, 0.0f, 0.5f, 1.0f}});
  const FrontEndRun r = run_front_end(clip_space_scene({d}));
  ASSERT_EQ(r.prims.size(), 2u);
  const ClippedPrimitive& l = r.prims[0];
  EXPECT_EQ(l.v[0].x, 64.0f);
  EXPECT_EQ(l.v[0].y, 72.0f);
  EXPECT_EQ(l.v[0].z, 0.0f);
  EXPECT_EQ(l.v[0].inv_w, 1.0f);
  EXPECT_TRUE(holds_color(l.v[0].varyings_over_w, 0.5f * (color_of(0) + color_of(1))));
  EXPECT_EQ(l.v[1].x, 32.0f);  // b untouched
  EXPECT_EQ(l.v[1].z, 0.5f);
  EXPECT_TRUE(holds_color(l.flat_varyings, color_of(1)));
  EXPECT_TRUE(l.draw_first && l.draw_last);  // clipping keeps the flags
  const ClippedPrimitive& m = r.prims[1];
  EXPECT_NEAR(m.v[0].z, 0.0f, 1e-6f);  // on the near plane: z_w = 0
  EXPECT_NEAR(m.v[0].x, (3.0f / 14.0f + 1.0f) * 64.0f, 1e-4f);
  EXPECT_EQ(m.v[1].x, 64.0f);
  EXPECT_EQ(m.v[1].z, 0.75f);
  EXPECT_EQ(r.clipper.at("lines_clipped"), 2u);
  EXPECT_EQ(r.clipper.at("lines_clipped_away"), 0u);
}

TEST(FrontEndLines, LinesWithNothingInsideAreClippedAway) {
  // Both ends behind the eye (w < 0): the outcodes share plane 0. Then a
  // line from outside the left guard band to outside the bottom one, the
  // outcodes disjoint: for 128 pixels the band is x >= -513 w, y >= -513 w;
  // the line x + y = -1100 passes the corner (-513, -513) at y = -587 after
  // the left cut, so the bottom plane finds both ends outside.
  Draw d = clip_space_draw(PrimitiveType::lines, {{0.0f, 0.0f, 0.0f, -1.0f},
                                                  {0.5f, 0.2f, 0.1f, -2.0f},
                                                  {-1100.0f, 0.0f, 0.0f, 1.0f},
                                                  {0.0f, -1100.0f, 0.0f, 1.0f}});
  const FrontEndRun r = run_front_end(clip_space_scene({d}));
  EXPECT_EQ(r.prims.size(), 0u);
  EXPECT_EQ(r.clipper.at("lines_in"), 2u);
  EXPECT_EQ(r.clipper.at("lines_clipped_away"), 2u);
  EXPECT_EQ(r.clipper.at("lines_clipped"), 0u);
}

TEST(FrontEndPoints, OutsideTheFrustumDroppedOnTheEdgeKept) {
  // Kept: inside; x = w (the right edge); z = -w (the near plane); y = -w.
  // Dropped: x > w (inside the guard band, but a point is not clipped
  // there), w < 0, z > w.
  Draw d = clip_space_draw(PrimitiveType::points, {{0.25f, 0.5f, 0.0f, 1.0f},
                                                   {2.0f, 0.0f, 0.0f, 2.0f},
                                                   {0.0f, 0.0f, -1.0f, 1.0f},
                                                   {0.0f, -1.0f, 0.0f, 1.0f},
                                                   {1.0f + 1.0f / 64.0f, 0.0f, 0.0f, 1.0f},
                                                   {0.0f, 0.0f, 0.0f, -1.0f},
                                                   {0.0f, 0.0f, 1.5f, 1.0f}});
  const FrontEndRun r = run_front_end(clip_space_scene({d}));
  ASSERT_EQ(r.prims.size(), 4u);
  const int64_t ids[4] = {0, 1, 2, 3};
  const float xs[4] = {80.0f, 128.0f, 64.0f, 64.0f};
  const float ys[4] = {96.0f, 64.0f, 64.0f, 0.0f};
  for (size_t i = 0; i < 4; ++i) {
    const ClippedPrimitive& p = r.prims[i];
    EXPECT_EQ(p.primitive_kind, PrimitiveKind::point);
    EXPECT_EQ(p.vertex_count, 1);
    EXPECT_EQ(p.primitive_id, ids[i]);
    EXPECT_EQ(p.v[0].x, xs[i]);
    EXPECT_EQ(p.v[0].y, ys[i]);
    EXPECT_TRUE(holds_color(p.flat_varyings, color_of(i)));
  }
  EXPECT_EQ(r.prims[1].v[0].inv_w, 0.5f);
  EXPECT_EQ(r.prims[2].v[0].z, 0.0f);
  EXPECT_EQ(r.clipper.at("points_in"), 7u);
  EXPECT_EQ(r.clipper.at("points_clipped_away"), 3u);
  EXPECT_EQ(r.clipper.at("points_out"), 4u);
}

// One triangle per draw in polygon mode `mode`, cull mode `cull`.
Draw unfilled(PolygonMode mode, CullMode cull, const std::vector<glm::vec4>& v) {
  Draw d = clip_space_draw(PrimitiveType::triangles, v);
  d.state.polygon_mode = mode;
  d.state.cull = cull;
  return d;
}

const std::vector<glm::vec4> kCcw = {
    {-0.5f, -0.5f, 0.0f, 1.0f}, {0.5f, -0.5f, 0.0f, 1.0f}, {0.0f, 0.5f, 0.0f, 1.0f}};
const std::vector<glm::vec4> kCw = {kCcw[0], kCcw[2], kCcw[1]};

TEST(FrontEndPolygonMode, LineModeDrawsTheEdgesOfSurvivingTriangles) {
  // CCW (window (32, 32), (96, 32), (64, 96)), cull back: 3 lines (v0 v1),
  // (v1 v2), (v2 v0), each with its first end only, the triangle's id and
  // its provoking colour (v2). The same triangle clockwise with cull back: culled.
  // A collinear one: degenerate. The clockwise one without culling: 3 lines.
  const FrontEndRun r = run_front_end(clip_space_scene(
      {unfilled(PolygonMode::line, CullMode::back, kCcw),
       unfilled(PolygonMode::line, CullMode::back, kCw),
       unfilled(PolygonMode::line, CullMode::none, {kCcw[0], kCcw[1], {1.5f, -0.5f, 0.0f, 1.0f}}),
       unfilled(PolygonMode::line, CullMode::none, kCw)}));
  ASSERT_EQ(r.prims.size(), 6u);
  const float x[3] = {32.0f, 96.0f, 64.0f}, y[3] = {32.0f, 32.0f, 96.0f};
  for (size_t i = 0; i < 3; ++i) {
    const ClippedPrimitive& l = r.prims[i];
    EXPECT_EQ(l.primitive_kind, PrimitiveKind::line);
    EXPECT_EQ(l.vertex_count, 2);
    EXPECT_EQ(l.primitive_id, 0);
    EXPECT_TRUE(l.draw_first);
    EXPECT_FALSE(l.draw_last);
    EXPECT_EQ(l.v[0].x, x[i]);
    EXPECT_EQ(l.v[0].y, y[i]);
    EXPECT_EQ(l.v[1].x, x[(i + 1) % 3]);
    EXPECT_EQ(l.v[1].y, y[(i + 1) % 3]);
    EXPECT_TRUE(holds_color(l.v[0].varyings_over_w, color_of(i)));
    EXPECT_TRUE(holds_color(l.flat_varyings, color_of(2)));
  }
  // The clockwise one: its own vertex order, (v0 v1) = (32, 32) -> (64, 96).
  EXPECT_EQ(r.prims[3].primitive_id, 3);
  EXPECT_EQ(r.prims[3].v[1].x, 64.0f);
  EXPECT_EQ(r.clipper.at("triangles_in"), 4u);
  EXPECT_EQ(r.clipper.at("triangles_unfilled"), 2u);
  EXPECT_EQ(r.clipper.at("triangles_culled"), 1u);
  EXPECT_EQ(r.clipper.at("triangles_degenerate"), 1u);
  EXPECT_EQ(r.clipper.at("triangles_after_clip"), 0u);
  EXPECT_EQ(r.clipper.at("unfilled_lines"), 6u);
  EXPECT_EQ(r.clipper.at("lines_in"), 0u);  // not assembled lines
}

TEST(FrontEndPolygonMode, TheClippedEdgeIsNotDrawn) {
  // v2 behind the near plane (z + w = -2): the polygon is v0, v1, the cut c1
  // on (v1 v2) where the edge leaves (its flag clear: the edge from it runs
  // along the plane), the cut c2 on (v2 v0) where it enters (v2's flag,
  // set). Line mode draws (v0 v1), (v1 c1), (c2 v0); point mode v0, v1, c2.
  // Each cut starts from the inside endpoint (distance 1 against 2), t =
  // 1/3: c1 = (1/3, -1/6), c2 = (-1/3, -1/6), window (85.33, 53.33) and
  // (42.67, 53.33), on the near plane (z_w = 0).
  const std::vector<glm::vec4> v = {kCcw[0], kCcw[1], {0.0f, 0.5f, -3.0f, 1.0f}};
  const FrontEndRun r =
      run_front_end(clip_space_scene({unfilled(PolygonMode::line, CullMode::back, v),
                                      unfilled(PolygonMode::point, CullMode::back, v)}));
  ASSERT_EQ(r.prims.size(), 6u);
  const float third = 64.0f / 3.0f;
  const ClippedPrimitive& a = r.prims[0];
  const ClippedPrimitive& b = r.prims[1];
  const ClippedPrimitive& c = r.prims[2];
  EXPECT_EQ(a.v[0].x, 32.0f);
  EXPECT_EQ(a.v[1].x, 96.0f);
  EXPECT_EQ(b.v[0].x, 96.0f);
  EXPECT_NEAR(b.v[1].x, 64.0f + third, 1e-4f);
  EXPECT_NEAR(b.v[1].y, 64.0f - third / 2, 1e-4f);
  EXPECT_NEAR(b.v[1].z, 0.0f, 1e-6f);
  EXPECT_NEAR(c.v[0].x, 64.0f - third, 1e-4f);
  EXPECT_NEAR(c.v[0].z, 0.0f, 1e-6f);
  EXPECT_EQ(c.v[1].x, 32.0f);
  for (const ClippedPrimitive* l : {&a, &b, &c}) {
    EXPECT_EQ(l->primitive_kind, PrimitiveKind::line);
    EXPECT_TRUE(holds_color(l->flat_varyings, color_of(2)));  // v2, though clipped off
  }
  for (size_t i = 3; i < 6; ++i) EXPECT_EQ(r.prims[i].primitive_kind, PrimitiveKind::point);
  EXPECT_EQ(r.prims[3].v[0].x, 32.0f);
  EXPECT_EQ(r.prims[4].v[0].x, 96.0f);
  EXPECT_NEAR(r.prims[5].v[0].x, 64.0f - third, 1e-4f);
  EXPECT_EQ(r.prims[5].primitive_id, 1);
  EXPECT_EQ(r.clipper.at("triangles_clipped"), 2u);
  EXPECT_EQ(r.clipper.at("triangles_unfilled"), 2u);
  EXPECT_EQ(r.clipper.at("unfilled_lines"), 3u);
  EXPECT_EQ(r.clipper.at("unfilled_points"), 3u);
  EXPECT_EQ(r.clipper.at("points_out"), 3u);
  EXPECT_EQ(r.clipper.at("points_in"), 0u);
}

TEST(FrontEndPolygonMode, ATriangleEnclosingTheGuardBandHasNoEdgeLeft) {
  // The guard band of 128 pixels is -513 w <= x, y <= 511 w: this triangle
  // contains it, so the clipped polygon is the band's square, every edge
  // along a plane, and line mode draws nothing, though the triangle is
  // unfilled (not culled or degenerate).
  const FrontEndRun r = run_front_end(clip_space_scene({unfilled(PolygonMode::line, CullMode::back,
                                                                 {{-5000.0f, -5000.0f, 0.0f, 1.0f},
                                                                  {5000.0f, -5000.0f, 0.0f, 1.0f},
                                                                  {0.0f, 5000.0f, 0.0f, 1.0f}})}));
  EXPECT_EQ(r.prims.size(), 0u);
  EXPECT_EQ(r.clipper.at("triangles_unfilled"), 1u);
  EXPECT_EQ(r.clipper.at("triangles_clipped"), 1u);
}

TEST(FrontEndPolygonMode, AVertexOnAPlaneIsDrawnTwiceInPointMode) {
  // Section 4d taken literally: v2 lies on the near plane (z + w = 0), v1
  // behind it. The edge (v1 v2) enters the inside at v2 itself: the cut
  // starts from v2 (distance 0), t = 0, and the new vertex, equal to v2,
  // takes v1's flag (set); v2 keeps its own. Polygon v0, c1 (leaving, clear),
  // c' = v2, v2: the points v0, v2, v2; the lines (v0 c1), (v2 v2) of zero
  // length, (v2 v0).
  const std::vector<glm::vec4> v = {kCcw[0], {0.5f, -0.5f, -3.0f, 1.0f}, {0.0f, 0.5f, -1.0f, 1.0f}};
  const FrontEndRun r =
      run_front_end(clip_space_scene({unfilled(PolygonMode::point, CullMode::none, v),
                                      unfilled(PolygonMode::line, CullMode::none, v)}));
  ASSERT_EQ(r.prims.size(), 6u);
  EXPECT_EQ(r.prims[0].v[0].x, 32.0f);
  for (size_t i : {1, 2}) {
    EXPECT_EQ(r.prims[i].v[0].x, 64.0f);
    EXPECT_EQ(r.prims[i].v[0].y, 96.0f);
    EXPECT_EQ(r.prims[i].v[0].z, 0.0f);
  }
  EXPECT_EQ(r.prims[4].v[0], r.prims[4].v[1]);
  EXPECT_EQ(r.prims[5].v[1].x, 32.0f);
}

TEST(FrontEndPolygonMode, PointModeDrawsTheVertices) {
  // A point shows its flat varyings (section 9): with Gouraud shading its
  // own vertex's colour, with flat shading the triangle's provoking one.
  Draw flat = unfilled(PolygonMode::point, CullMode::front, kCw);
  flat.state.shading = Shading::flat;
  const FrontEndRun r =
      run_front_end(clip_space_scene({unfilled(PolygonMode::point, CullMode::front, kCw), flat}));
  ASSERT_EQ(r.prims.size(), 6u);
  const float x[3] = {32.0f, 64.0f, 96.0f};
  for (size_t i = 0; i < 6; ++i) {
    EXPECT_EQ(r.prims[i].primitive_kind, PrimitiveKind::point);
    EXPECT_EQ(r.prims[i].v[0].x, x[i % 3]);
    EXPECT_TRUE(holds_color(r.prims[i].flat_varyings, color_of(i < 3 ? i : 2)));
  }
}

// Random lines, strips, loops and points (vertices of every kind that
// random_clip_vertex makes: near and far, guard band, w around 0, behind the
// eye, huge) against the rules of sections 3, 4b and 4c written out here
// from the spec's text, on golden::clip_distance and golden::to_window.

struct ExpectedLinePoint {
  uint32_t draw_id = 0;
  int64_t primitive_id = 0;
  std::vector<golden::ShadedVertex> v;  // clipped, 1 or 2
  glm::vec4 flat_color{0.0f};
  bool first = true, last = true;
};

struct ExpectedLinesPoints {
  std::vector<ExpectedLinePoint> prims;
  uint64_t lines_in = 0, lines_invalid = 0, lines_away = 0, lines_clipped = 0;
  uint64_t points_in = 0, points_invalid = 0, points_away = 0;
};

// Section 4b: false when nothing is left; `clipped` when step 2 ran.
bool spec_clip_line(golden::ShadedVertex& a, golden::ShadedVertex& b, const golden::GuardBand& gb,
                    bool& clipped) {
  clipped = false;
  bool accept = true;
  for (int p = 0; p < golden::kClipPlaneCount; ++p) {
    const float da = golden::clip_distance(p, a.clip, gb),
                db = golden::clip_distance(p, b.clip, gb);
    if (da < 0.0f && db < 0.0f) return false;
    accept = accept && da >= 0.0f && db >= 0.0f;
  }
  if (accept) return true;
  for (int p = 0; p < golden::kClipPlaneCount; ++p) {
    const float da = golden::clip_distance(p, a.clip, gb),
                db = golden::clip_distance(p, b.clip, gb);
    if (da >= 0.0f && db >= 0.0f) continue;
    if (da < 0.0f && db < 0.0f) return false;
    golden::ShadedVertex& out = da < 0.0f ? a : b;
    const golden::ShadedVertex in = da < 0.0f ? b : a;
    const float d_out = da < 0.0f ? da : db, d_in = da < 0.0f ? db : da;
    // From the endpoint nearer the plane, the inside one on a tie.
    const bool from_in = std::fabs(d_in) <= std::fabs(d_out);
    const golden::ShadedVertex& s = from_in ? in : out;
    const golden::ShadedVertex& e = from_in ? out : in;
    const float ds = from_in ? d_in : d_out, de = from_in ? d_out : d_in;
    const float t = ds / (ds - de);
    golden::ShadedVertex v;
    for (int k = 0; k < 4; ++k) {
      v.clip[k] = s.clip[k] + t * (e.clip[k] - s.clip[k]);
      v.color[k] = s.color[k] + t * (e.color[k] - s.color[k]);
    }
    if (p == 0 && v.clip.w < golden::kMinClipW) v.clip.w = golden::kMinClipW;
    out = v;
  }
  clipped = true;
  return true;
}

ExpectedLinesPoints expected_lines_points(const Scene& scene) {
  ExpectedLinesPoints e;
  const golden::GuardBand gb =
      golden::guard_band_for(scene.framebuffer.width, scene.framebuffer.height);
  int64_t id = 0;
  for (uint32_t d = 0; d < scene.draws.size(); ++d) {
    const Draw& draw = scene.draws[d];
    const uint32_t n = static_cast<uint32_t>(draw.vertex_count());
    // Slot -> vertex, or nothing when invalid (index or non-finite clip).
    const auto vertex = [&](uint32_t slot, golden::ShadedVertex& out) {
      const uint32_t vi = draw.indices.empty() ? slot : draw.indices[slot];
      if (vi >= draw.positions.size()) return false;
      out = golden::shade_vertex(scene, draw, vi);
      return finite4(out.clip);
    };
    if (draw.primitive == PrimitiveType::points) {
      for (uint32_t i = 0; i < n; ++i, ++id) {
        ++e.points_in;
        golden::ShadedVertex v;
        if (!vertex(i, v)) {
          ++e.points_invalid;
          continue;
        }
        const glm::vec4& c = v.clip;
        if (!(c.w - golden::kMinClipW >= 0.0f && c.x + c.w >= 0.0f && c.w - c.x >= 0.0f &&
              c.y + c.w >= 0.0f && c.w - c.y >= 0.0f && c.z + c.w >= 0.0f && c.w - c.z >= 0.0f)) {
          ++e.points_away;
          continue;
        }
        e.prims.push_back({d, id, {v}, v.color, true, true});
      }
      continue;
    }
    // Section 3's table.
    std::vector<std::array<uint32_t, 2>> lines;
    std::vector<std::pair<bool, bool>> flags;
    if (draw.primitive == PrimitiveType::lines) {
      for (uint32_t i = 0; 2 * i + 1 < n; ++i) {
        lines.push_back({2 * i, 2 * i + 1});
        flags.push_back({true, true});
      }
    } else {
      for (uint32_t i = 0; i + 1 < n; ++i) {
        lines.push_back({i, i + 1});
        flags.push_back({i == 0, true});
      }
      if (draw.primitive == PrimitiveType::line_loop && n >= 2) {
        lines.push_back({n - 1, 0});
        flags.push_back({false, false});
      }
    }
    for (size_t i = 0; i < lines.size(); ++i, ++id) {
      ++e.lines_in;
      golden::ShadedVertex a, b;
      if (!vertex(lines[i][0], a) || !vertex(lines[i][1], b)) {
        ++e.lines_invalid;
        continue;
      }
      const glm::vec4 flat = b.color;
      bool clipped = false;
      if (!spec_clip_line(a, b, gb, clipped)) {
        ++e.lines_away;
        continue;
      }
      if (clipped) ++e.lines_clipped;
      e.prims.push_back({d, id, {a, b}, flat, flags[i].first, flags[i].second});
    }
  }
  return e;
}

TEST(FrontEndLines, RandomLinesAndPointsFollowTheSpec) {
  std::mt19937 rng(11);
  Scene s;
  s.framebuffer.width = 256;
  s.framebuffer.height = 192;
  s.draws.push_back(random_draw(rng, PrimitiveType::lines, 400, true, 0));
  s.draws.push_back(random_draw(rng, PrimitiveType::line_strip, 131, true, 0));
  s.draws.push_back(random_draw(rng, PrimitiveType::line_loop, 97, false, 0));
  s.draws.push_back(random_draw(rng, PrimitiveType::points, 300, true, 0));
  Draw indexed = random_draw(rng, PrimitiveType::line_loop, 60, true, 150);
  indexed.indices[7] = 60;      // out of range
  indexed.indices[149] = 1000;  // the loop's last slot: its last two lines invalid
  s.draws.push_back(indexed);
  Draw points = random_draw(rng, PrimitiveType::points, 50, true, 90);
  points.indices[40] = 77;
  s.draws.push_back(points);
  s.draws.push_back(random_draw(rng, PrimitiveType::line_strip, 33, true, 0));
  s.draws.push_back(random_draw(rng, PrimitiveType::line_loop, 2, true, 0));
  const ExpectedLinesPoints want = expected_lines_points(s);
  EXPECT_GT(want.lines_clipped, 50u);
  EXPECT_GT(want.lines_away, 50u);
  EXPECT_GT(want.points_away, 50u);
  EXPECT_GT(want.lines_invalid, 3u);

  const FrontEndRun r = run_front_end(s, config_with(16, 2));
  ASSERT_EQ(r.prims.size(), want.prims.size());
  const float half_w = 0.5f * s.framebuffer.width, half_h = 0.5f * s.framebuffer.height;
  int failures = 0;
  for (size_t i = 0; i < want.prims.size() && failures < 5; ++i) {
    const ClippedPrimitive& g = r.prims[i];
    const ExpectedLinePoint& w = want.prims[i];
    bool ok = g.draw_id == w.draw_id && g.primitive_id == w.primitive_id &&
              g.vertex_count == w.v.size() &&
              g.primitive_kind == (w.v.size() == 1 ? PrimitiveKind::point : PrimitiveKind::line) &&
              holds_color(g.flat_varyings, w.flat_color);
    if (w.v.size() == 2) ok = ok && g.draw_first == w.first && g.draw_last == w.last;
    for (size_t k = 0; k < w.v.size(); ++k) {
      const golden::WindowVertex wv =
          golden::to_window(w.v[k], s.framebuffer.width, s.framebuffer.height);
      const float x = (w.v[k].clip.x * wv.inv_w + 1.0f) * half_w;
      const float y = (w.v[k].clip.y * wv.inv_w + 1.0f) * half_h;
      ok = ok && bits(g.v[k].x) == bits(x) && bits(g.v[k].y) == bits(y) &&
           bits(g.v[k].z) == bits(wv.z) && bits(g.v[k].inv_w) == bits(wv.inv_w) &&
           holds_color(g.v[k].varyings_over_w, wv.color_over_w);
    }
    if (!ok) {
      ++failures;
      ADD_FAILURE() << "primitive " << i << " (prim " << w.primitive_id << "): " << g;
    }
  }
  EXPECT_EQ(r.clipper.at("lines_in"), want.lines_in);
  EXPECT_EQ(r.clipper.at("lines_invalid"), want.lines_invalid);
  EXPECT_EQ(r.clipper.at("lines_clipped_away"), want.lines_away);
  EXPECT_EQ(r.clipper.at("lines_clipped"), want.lines_clipped);
  EXPECT_EQ(r.clipper.at("points_in"), want.points_in);
  EXPECT_EQ(r.clipper.at("points_invalid"), want.points_invalid);
  EXPECT_EQ(r.clipper.at("points_clipped_away"), want.points_away);
}

// ---------------------------------------------------------------------------
// Timing, the documented defaults: command processor ii 1 / latency 2, vertex fetch 1 / 2,
// vertex shader 4 / 24, clipper 2 / 8; memory latency 20, 32 bytes/cycle;
// 1 GHz. These benches send only the draw and end_of_frame, both written by
// the source at time 0; the lists are the cycles at which the sink reads each
// result.

// The costs the comments below assume, pinned so that a change of the
// defaults does not silently change what these tests check.
GpuConfig timing_config() {
  GpuConfig c;
  c.clock_mhz = 1000.0;
  c.stages["command_processor"] = {1, 2};
  c.stages["vertex_fetch"] = {1, 2};
  c.stages["vertex_shader"] = {4, 24};
  c.stages["clipper"] = {2, 8};
  c.memory = {20, 32};
  c.fifo_depth = 16;
  c.vertex_cache_entries = 32;
  return c;
}

void run_timing(const Scene& scene, const std::vector<double>& want,
                const GpuConfig& config = timing_config()) {
  const LoadedFrame frame = load_frame(scene);
  Bench bench("bench", config, frame);
  bench.script = {{PacketKind::work, 0}, {PacketKind::end_of_frame, 0}};
  sc_core::sc_start();
  std::vector<double> cycles;
  for (const sc_time& t : bench.times) cycles.push_back(t / config.cycle());
  EXPECT_EQ(cycles, want);
}

TEST(FrontEndTiming, OneTriangle) {
  // command processor: draw at 0, busy 1, readable at 3; end of frame
  //   read at 1, readable at 4.
  // fetch: draw at 3; 3 positions in one 48-byte burst: bus 2 cycles + 20
  //   = 22 of memory time; busy 3 x 1 -> 6; readable at 3 + max(3, 22) + 2
  //   = 27. End of frame: 6 -> 7, readable 9 (behind the batch).
  // shader: batch at 27, 3 vertices x 4 = 12 -> 39, readable 63; end of
  //   frame 39 -> 43, readable 67.
  // clipper: batch at 63, 1 triangle x 2 -> 65, readable 73; end of frame
  //   67 -> 69, readable 77.
  Scene scene;
  Draw d;
  d.positions = {{-0.5f, -0.5f, 0.0f, 1.0f}, {0.5f, -0.5f, 0.0f, 1.0f}, {0.0f, 0.5f, 0.0f, 1.0f}};
  scene.draws = {d};
  run_timing(scene, {73, 77});
}

TEST(FrontEndTiming, IndexedWithColorsAndCacheHits) {
  // fetch: draw at 3; 6 indices (24 B) bus [3, 4), back at 4 + 20 = 24;
  //   misses 0 1 2 3 (2 and 1 hit) are one burst: positions 64 B bus
  //   [24, 26), colours 64 B bus [26, 28), done at 28 + 20 = 48: memory time
  //   45; busy 6 x 1 -> 9; readable at 3 + max(6, 45) + 2 = 50. End of
  //   frame 9 -> 10.
  // shader: batch at 50, 4 new vertices x 4 = 16 -> 66, readable 90; end
  //   of frame 66 -> 70, readable 94.
  // clipper: batch at 90, 2 triangles x 2 = 4 -> 94, both readable 102;
  //   end of frame 94 -> 96, readable 104.
  Scene scene;
  Draw d;
  d.positions = {{-0.5f, -0.5f, 0.0f, 1.0f},
                 {0.5f, -0.5f, 0.0f, 1.0f},
                 {0.0f, 0.5f, 0.0f, 1.0f},
                 {0.9f, 0.5f, 0.0f, 1.0f}};
  d.colors.assign(4, glm::vec4(0.25f, 0.5f, 0.75f, 1.0f));
  d.indices = {0, 1, 2, 2, 1, 3};
  scene.draws = {d};
  run_timing(scene, {102, 102, 104});
}

TEST(FrontEndTiming, ClippedTrianglePaysPerOutputTriangle) {
  // One triangle with one vertex behind the near plane: a quad, 2 triangles.
  // fetch as in OneTriangle: batch readable 27, shader readable 63.
  // clipper: (1 + 1 extra) x 2 = 4 -> 67, both readable 75; end of frame
  //   (readable 67) read at 67 -> 69, readable 77.
  Scene scene;
  Draw d;
  d.positions = {{-0.5f, -0.5f, 0.0f, 1.0f}, {0.5f, -0.5f, 0.0f, 1.0f}, {0.0f, 0.5f, -3.0f, 1.0f}};
  scene.draws = {d};
  const Expected e = expected_stream(scene);
  ASSERT_EQ(e.triangles.size(), 2u);
  run_timing(scene, {75, 75, 77});
}

TEST(FrontEndTiming, StageCostsFromConfig) {
  // Same triangle as OneTriangle with other costs and a slow, narrow memory:
  // cp ii 3 lat 1: draw readable 4, end of frame 3 -> 6, readable 7.
  // fetch ii 2 lat 5: draw at 4; 48 B at 8 B/cycle = 6 bus cycles + 50 =
  //   56 of memory time; busy 3 x 2 -> 10; readable 4 + max(6, 56) + 5 =
  //   65; end of frame 10 -> 12, readable 17.
  // shader ii 1 lat 3: 65 -> 68, readable 71; end of frame 68 -> 69,
  //   readable 72.
  // clipper ii 5 lat 0: 71 -> 76, readable 76; end of frame 76 -> 81.
  GpuConfig config = timing_config();
  config.stages["command_processor"] = {3, 1};
  config.stages["vertex_fetch"] = {2, 5};
  config.stages["vertex_shader"] = {1, 3};
  config.stages["clipper"] = {5, 0};
  config.memory = {50, 8};
  Scene scene;
  Draw d;
  d.positions = {{-0.5f, -0.5f, 0.0f, 1.0f}, {0.5f, -0.5f, 0.0f, 1.0f}, {0.0f, 0.5f, 0.0f, 1.0f}};
  scene.draws = {d};
  run_timing(scene, {76, 81}, config);
}

TEST(FrontEndTiming, LineStripPaysPerLine) {
  // fetch: 4 positions, one 64-byte burst: bus 2 + 20 = 22 of memory time;
  //   busy 4; readable 3 + 22 + 2 = 27; end of frame readable 10.
  // shader: 4 vertices x 4 = 16 -> 43, readable 67; end of frame 43 -> 47,
  //   readable 71.
  // clipper: 3 lines x 2 = 6 -> 73, readable 81; end of frame 73 -> 75,
  //   readable 83.
  Scene scene;
  Draw d;
  d.primitive = PrimitiveType::line_strip;
  for (size_t i = 0; i < 4; ++i) d.positions.push_back(strip_vertex(i));
  scene.draws = {d};
  run_timing(scene, {81, 81, 81, 83});
}

TEST(FrontEndTiming, PolygonModePaysPerEmittedLine) {
  // As OneTriangle to the clipper (batch at 63); the triangle drawn as 3
  // lines costs 1 + 2 extra: 3 x 2 = 6 -> 69, readable 77; end of frame
  // (readable 67) at 69 -> 71, readable 79. Culled, it costs its one: 63 ->
  // 65, and the end of frame 67 -> 69, readable 77.
  Scene scene;
  Draw d;
  d.positions = kCcw;
  d.state.polygon_mode = PolygonMode::line;
  scene.draws = {d};
  run_timing(scene, {77, 77, 77, 79});
}

TEST(FrontEndTiming, CulledPolygonModeTrianglePaysOne) {
  Scene scene;
  Draw d;
  d.positions = kCcw;
  d.state.polygon_mode = PolygonMode::line;
  d.state.cull = CullMode::front;
  scene.draws = {d};
  run_timing(scene, {77});
}

}  // namespace
}  // namespace gpusim
