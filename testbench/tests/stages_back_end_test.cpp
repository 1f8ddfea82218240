// The back end of a raster unit: DepthTest -> Interpolator -> Rop, with
// their tile caches, on a memory shared by every unit.
//
// Frames: the test plays front end (testbench/tests/back_end_input.h). It
// sets triangles up and cuts them into per-unit stamp batches with the
// golden model's own functions (clip, to_window, edge_function, the fill
// rule), runs several units' back ends and compares the colour and depth
// buffers it then finds in memory, bit for bit, with golden::render() of the
// same scene, together with the last writer of every pixel and the fragment
// counts. Scenes cover every depth format and compare function, depth writes
// and tests off, polygon offset, every blend factor and equation, colour
// masks, both colour formats, flat and Gouraud, clear values, and
// configurations from 1 to 16 units, tiles 8 to 64, stamps 1x1 to 8x8, FIFOs
// of depth 1 to 16, 1 to 1024 cache entries, with and without random FIFO
// stalls.
//
// The tile caches of the depth test and the ROP are counted by hand for an
// LRU pattern in the chain. The timing tests run each of the depth test,
// the interpolator and the ROP alone against the cost model, several stages
// side by side in one TEST; the interpolator's colours are tested alone in
// stages_interpolator_test.cpp. One sc_start per TEST (ctest runs each in
// its own process); a TEST may hold many independent benches.
#define SC_INCLUDE_DYNAMIC_PROCESSES
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <iterator>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "hw/draw_state.h"
#include "hw/fifo.h"
#include "hw/gpu_config.h"
#include "hw/memory.h"
#include "hw/packets.h"
#include "hw/pixel_formats.h"
#include "stages/depth_test.h"
#include "stages/interpolator.h"
#include "stages/rop.h"
#include "testbench/golden/golden_model.h"
#include "testbench/tests/back_end_input.h"

namespace gpusim {
namespace {

using namespace test;
using sc_core::sc_time;

constexpr uint8_t kFill = 0xA5;  // memory content before the frame

// ---------------------------------------------------------------------------
// Scenes only these tests use.

RenderState random_state(Rng& rng) {
  RenderState st;
  st.cull = static_cast<CullMode>(rng.below(3));
  st.front_face = static_cast<FrontFace>(rng.below(2));
  st.depth_test = rng.chance(0.8);
  st.depth_func = static_cast<CompareFunc>(rng.below(8));
  st.depth_write = rng.chance(0.7);
  if (rng.chance(0.3)) {
    st.offset_factor = rng.uniform(-2.0f, 2.0f);
    st.offset_units = rng.uniform(-8.0f, 8.0f);
  }
  st.blend = rng.chance(0.5);
  st.blend_src = static_cast<BlendFactor>(rng.below(11));
  st.blend_dst = static_cast<BlendFactor>(rng.below(11));
  st.blend_equation = static_cast<BlendEquation>(rng.below(3));
  for (bool& m : st.color_mask) m = rng.chance(0.85);
  st.shading = static_cast<Shading>(rng.below(2));
  return st;
}

// A bit of everything: random states, repeated geometry.
Scene mixed_scene(uint32_t seed, int w, int h, ColorFormat cf, DepthFormat df) {
  Rng rng(seed);
  Scene s = make_scene(w, h, cf, df);
  std::vector<glm::vec4> history;
  RenderState first;
  first.depth_func = CompareFunc::lequal;
  add_random_draw(s, rng, 12, first, 0.0, &history);
  for (int d = 0; d < 24; ++d) add_random_draw(s, rng, 5, random_state(rng), 0.3, &history);
  return s;
}

// ---------------------------------------------------------------------------
// The bench: per unit a source -> DepthTest -> Interpolator -> Rop, one memory.

uint64_t memory_size(const FrameState& f) {
  const FramebufferDesc& fb = f.framebuffer;
  const uint64_t pixels = static_cast<uint64_t>(fb.width) * fb.height;
  return f.depth_address + pixels * depth_bytes_per_pixel(fb.depth_format) + kGuard;
}

class BackEnd : public sc_core::sc_module {
 public:
  // `config` and `frame` must outlive the bench; tokens[u] feeds unit u.
  BackEnd(sc_core::sc_module_name name, const GpuConfig& config, const FrameState& frame,
          UnitTokens tokens, bool stalls = false, uint64_t seed = 1)
      : sc_core::sc_module(name),
        m_config(config),
        m_frame(frame),
        m_tokens(std::move(tokens)),
        memory("memory", memory_size(frame), config.memory.latency, config.memory.bytes_per_cycle,
               config.cycle()) {
    std::memset(memory.data(0, memory.size()), kFill, memory.size());
    last_writer.assign(static_cast<size_t>(frame.framebuffer.width) * frame.framebuffer.height, -1);
    for (unsigned u = 0; u < config.units; ++u) {
      const std::string n = std::to_string(u);
      Unit unit;
      unit.in = std::make_unique<Fifo<StampBatch>>(("in_" + n).c_str(), config.fifo_depth);
      unit.depth = std::make_unique<DepthTest>(("depth_test_" + n).c_str(), config, frame, u);
      unit.visible =
          std::make_unique<Fifo<StampBatch>>(("visible_" + n).c_str(), config.fifo_depth);
      unit.interpolator =
          std::make_unique<Interpolator>(("interpolator_" + n).c_str(), config, frame, u);
      unit.shaded =
          std::make_unique<Fifo<ShadedStampBatch>>(("shaded_" + n).c_str(), config.fifo_depth);
      unit.rop = std::make_unique<Rop>(("rop_" + n).c_str(), config, frame, u);
      unit.depth->in(*unit.in);
      unit.depth->out(*unit.visible);
      unit.depth->mem.bind(memory);
      unit.interpolator->in(*unit.visible);
      unit.interpolator->out(*unit.shaded);
      unit.rop->in(*unit.shaded);
      unit.rop->mem.bind(memory);
      unit.rop->set_last_writer(&last_writer);
      if (stalls) {
        const uint64_t s = seed * 1000 + 3 * u;
        unit.in->set_stalls(RandomStalls(unit.in->basename(), s, 0.3, 7, config.cycle()));
        unit.visible->set_stalls(
            RandomStalls(unit.visible->basename(), s + 1, 0.3, 7, config.cycle()));
        unit.shaded->set_stalls(
            RandomStalls(unit.shaded->basename(), s + 2, 0.3, 7, config.cycle()));
      }
      units.push_back(std::move(unit));
      sc_core::sc_spawn(
          [this, u] {
            for (const StampBatch& b : m_tokens[u]) units[u].in->write(b);
          },
          ("source_" + n).c_str());
    }
  }

  struct Unit {
    std::unique_ptr<Fifo<StampBatch>> in;
    std::unique_ptr<DepthTest> depth;
    std::unique_ptr<Fifo<StampBatch>> visible;
    std::unique_ptr<Interpolator> interpolator;
    std::unique_ptr<Fifo<ShadedStampBatch>> shaded;
    std::unique_ptr<Rop> rop;
  };

  uint64_t counter(const char* stage, const char* name) const {
    uint64_t sum = 0;
    for (const Unit& u : units) {
      const StatGroup& g = std::string(stage) == "depth_test"     ? u.depth->stats()
                           : std::string(stage) == "interpolator" ? u.interpolator->stats()
                                                                  : u.rop->stats();
      sum += g.to_json().at(name).get<uint64_t>();
    }
    return sum;
  }

  // The buffers as the golden model stores them, read through the backdoor.
  Framebuffer framebuffer() const {
    const FramebufferDesc& d = m_frame.framebuffer;
    Framebuffer fb(d.width, d.height, d.color_format, d.depth_format);
    const unsigned cb = color_bytes_per_pixel(d.color_format);
    const unsigned db = depth_bytes_per_pixel(d.depth_format);
    for (size_t p = 0; p < fb.depth.size(); ++p) {
      uint8_t c[8], z[4] = {0, 0, 0, 0};
      memory.debug_read(m_frame.color_address + p * cb, c, cb);
      memory.debug_read(m_frame.depth_address + p * db, z, db);
      for (int k = 0; k < 4; ++k) {
        fb.color[p * 4 + k] =
            cb == 4 ? c[k] : static_cast<ColorChannel>(c[2 * k] | c[2 * k + 1] << 8);
      }
      fb.depth[p] = DepthValue{z[0]} | DepthValue{z[1]} << 8 | DepthValue{z[2]} << 16 |
                    DepthValue{z[3]} << 24;
    }
    return fb;
  }

  // Bytes outside both buffers still hold the fill pattern.
  bool guards_intact() const {
    const FramebufferDesc& d = m_frame.framebuffer;
    const uint64_t pixels = static_cast<uint64_t>(d.width) * d.height;
    const uint64_t color_end =
        m_frame.color_address + pixels * color_bytes_per_pixel(d.color_format);
    const uint64_t depth_end =
        m_frame.depth_address + pixels * depth_bytes_per_pixel(d.depth_format);
    for (uint64_t a = 0; a < memory.size(); ++a) {
      const bool inside = (a >= m_frame.color_address && a < color_end) ||
                          (a >= m_frame.depth_address && a < depth_end);
      uint8_t b;
      memory.debug_read(a, &b, 1);
      if (!inside && b != kFill) return false;
    }
    return true;
  }

  bool all_frames_done() const {
    for (const Unit& u : units) {
      if (!u.rop->frame_done()) return false;
    }
    return true;
  }

  const GpuConfig& m_config;
  const FrameState& m_frame;
  UnitTokens m_tokens;
  Memory memory;
  std::vector<Unit> units;
  std::vector<int64_t> last_writer;
};

// Where two framebuffers first differ, for a readable failure.
std::string first_difference(const Framebuffer& got, const Framebuffer& want) {
  for (int y = 0; y < want.height; ++y) {
    for (int x = 0; x < want.width; ++x) {
      const size_t p = want.pixel_index(x, y);
      if (got.depth[p] != want.depth[p]) {
        return "depth at (" + std::to_string(x) + ", " + std::to_string(y) + "): got " +
               std::to_string(got.depth[p]) + ", want " + std::to_string(want.depth[p]);
      }
      for (int k = 0; k < 4; ++k) {
        if (got.color[p * 4 + k] != want.color[p * 4 + k]) {
          return "colour channel " + std::to_string(k) + " at (" + std::to_string(x) + ", " +
                 std::to_string(y) + "): got " + std::to_string(got.color[p * 4 + k]) + ", want " +
                 std::to_string(want.color[p * 4 + k]);
        }
      }
    }
  }
  return "none";
}

// A scene, its frame registers, the bench and the golden result, to check
// after sc_start.
struct Case {
  std::string label;
  Scene scene;
  GpuConfig config = GpuConfig::baseline();
  FrameState frame;
  std::unique_ptr<BackEnd> bench;
  golden::Result expected;

  Case(const std::string& name, Scene s, const GpuConfig& c, bool stalls = false, uint64_t seed = 1)
      : label(name), scene(std::move(s)), config(c), frame(frame_state(scene)) {
    bench = std::make_unique<BackEnd>(name.c_str(), config, frame, front_end(scene, config), stalls,
                                      seed);
    expected = golden::render(scene);
  }

  void check() const {
    SCOPED_TRACE(label);
    EXPECT_TRUE(bench->all_frames_done());
    const Framebuffer got = bench->framebuffer();
    EXPECT_TRUE(got == expected.framebuffer)
        << "first difference: " << first_difference(got, expected.framebuffer);
    EXPECT_TRUE(bench->last_writer == expected.last_writer);
    EXPECT_TRUE(bench->guards_intact());
    const golden::Stats& s = expected.stats;
    EXPECT_EQ(bench->counter("depth_test", "fragments_in"), s.fragments_generated);
    EXPECT_EQ(bench->counter("depth_test", "fragments_passed"), s.fragments_passed_depth);
    EXPECT_EQ(bench->counter("interpolator", "fragments"), s.fragments_passed_depth);
    EXPECT_EQ(bench->counter("rop", "fragments_written"), s.fragments_written);
    // Every lookup is a hit, a miss or a fill from the clear value.
    for (const char* stage : {"depth_test", "rop"}) {
      EXPECT_LE(bench->counter(stage, "cache_hits") + bench->counter(stage, "cache_misses") +
                    bench->counter(stage, "cache_clear_fills"),
                bench->counter(stage, "stamps"));
    }
  }
};

// ---------------------------------------------------------------------------
// Frames against the golden model.

TEST(BackEnd, EveryDepthFormatAndFunction) {
  std::vector<std::unique_ptr<Case>> cases;
  const GpuConfig configs[] = {config(1, 16, 4, 4, 16, 4), config(3, 8, 2, 2, 2, 2),
                               config(4, 16, 4, 4, 16, 1), config(16, 8, 8, 8, 1, 3)};
  int n = 0;
  for (DepthFormat df : {DepthFormat::unorm16, DepthFormat::unorm24, DepthFormat::float32}) {
    for (int f = 0; f < 8; ++f) {
      const auto func = static_cast<CompareFunc>(f);
      // write on, write off, test off
      for (int variant = 0; variant < 3; ++variant) {
        Rng rng(100 + n);
        Scene s = make_scene(61, 47, ColorFormat::rgba8, df);
        s.framebuffer.clear_depth = variant == 1 ? 0.5f : 0.75f;
        std::vector<glm::vec4> history;
        RenderState base;
        base.depth_func = CompareFunc::lequal;
        add_random_draw(s, rng, 20, base, 0.0, &history);
        RenderState st;
        st.depth_func = func;
        st.depth_write = variant != 1;
        st.depth_test = variant != 2;
        add_random_draw(s, rng, 30, st, 0.4, &history);
        add_random_draw(s, rng, 10, base, 0.3, &history);
        const std::string label = std::string("d_") + std::string(to_string(df)) + "_" +
                                  std::string(to_string(func)) + "_" + std::to_string(variant);
        cases.push_back(std::make_unique<Case>(label, std::move(s), configs[n % 4]));
        ++n;
      }
    }
  }
  sc_core::sc_start();
  for (const auto& c : cases) c->check();
  // Not vacuous: the scenes pass and fail depth tests and write depth.
  uint64_t passed = 0, generated = 0;
  for (const auto& c : cases) {
    passed += c->expected.stats.fragments_passed_depth;
    generated += c->expected.stats.fragments_generated;
  }
  EXPECT_GT(passed, generated / 4);
  EXPECT_LT(passed, generated);
}

TEST(BackEnd, PolygonOffset) {
  std::vector<std::unique_ptr<Case>> cases;
  int n = 0;
  for (DepthFormat df : {DepthFormat::unorm16, DepthFormat::unorm24, DepthFormat::float32}) {
    for (const auto& offset :
         {std::array<float, 2>{1.5f, 2.0f}, std::array<float, 2>{-1.0f, -4.0f},
          std::array<float, 2>{0.0f, 3.0f}, std::array<float, 2>{4.0f, 0.0f}}) {
      Rng rng(200 + n);
      Scene s = make_scene(50, 50, ColorFormat::rgba8, df);
      std::vector<glm::vec4> history;
      RenderState base;
      add_random_draw(s, rng, 15, base, 0.0, &history);
      // The same geometry again, offset, so the result hinges on the offset.
      RenderState st;
      st.depth_func = offset[0] + offset[1] > 0 ? CompareFunc::greater : CompareFunc::less;
      st.offset_factor = offset[0];
      st.offset_units = offset[1];
      add_random_draw(s, rng, 15, st, 1.0, &history);
      cases.push_back(std::make_unique<Case>("offset_" + std::to_string(n), std::move(s),
                                             config(2 + n % 3, 16, 4, 4, 4, 2)));
      ++n;
    }
  }
  sc_core::sc_start();
  for (const auto& c : cases) c->check();
}

TEST(BackEnd, EveryBlendFactorAndEquation) {
  std::vector<std::unique_ptr<Case>> cases;
  for (ColorFormat cf : {ColorFormat::rgba8, ColorFormat::rgba16f}) {
    Rng rng(cf == ColorFormat::rgba8 ? 300 : 301);
    Scene s = make_scene(40, 36, cf, DepthFormat::unorm24);
    for (int e = 0; e < 3; ++e) {
      for (int src = 0; src < 11; ++src) {
        for (int dst = 0; dst < 11; ++dst) {
          RenderState st;
          st.depth_test = false;  // every layer blends over the previous ones
          st.blend = true;
          st.blend_src = static_cast<BlendFactor>(src);
          st.blend_dst = static_cast<BlendFactor>(dst);
          st.blend_equation = static_cast<BlendEquation>(e);
          add_random_draw(s, rng, 2, st, 0.0, nullptr);
          if (rng.chance(0.1)) {
            RenderState opaque;
            opaque.depth_test = false;
            add_random_draw(s, rng, 1, opaque, 0.0, nullptr);
          }
        }
      }
    }
    cases.push_back(std::make_unique<Case>(std::string("blend_") + std::string(to_string(cf)),
                                           std::move(s), config(3, 8, 4, 4, 16, 4)));
  }
  sc_core::sc_start();
  for (const auto& c : cases) c->check();
}

TEST(BackEnd, ColorMasksShadingAndClearValues) {
  std::vector<std::unique_ptr<Case>> cases;
  int n = 0;
  for (ColorFormat cf : {ColorFormat::rgba8, ColorFormat::rgba16f}) {
    for (const glm::vec4& clear : {glm::vec4(0.0f), glm::vec4(1.0f, 0.2f, 0.6f, 0.8f)}) {
      Rng rng(400 + n);
      Scene s = make_scene(45, 52, cf, DepthFormat::unorm24);
      s.framebuffer.clear_color = clear;
      s.framebuffer.clear_depth = n % 2 ? 1.0f : 0.3f;
      std::vector<glm::vec4> history;
      for (int m = 0; m < 16; ++m) {
        for (int shading = 0; shading < 2; ++shading) {
          RenderState st;
          for (int k = 0; k < 4; ++k) st.color_mask[k] = (m >> k) & 1;
          st.shading = static_cast<Shading>(shading);
          st.blend = m % 3 == 0;
          st.blend_src = BlendFactor::src_alpha;
          st.blend_dst = BlendFactor::one_minus_src_alpha;
          st.depth_func = CompareFunc::lequal;
          add_random_draw(s, rng, 3, st, 0.2, &history);
        }
      }
      cases.push_back(std::make_unique<Case>("mask_" + std::to_string(n), std::move(s),
                                             config(2, 16, 2, 4, 2, 3)));
      ++n;
    }
  }
  sc_core::sc_start();
  for (const auto& c : cases) c->check();
}

// Configurations across the whole range, each with and without random stalls
// on every FIFO: the results must all equal the golden model's.
TEST(BackEnd, ConfigurationsWithAndWithoutRandomStalls) {
  struct Setup {
    GpuConfig config = GpuConfig::baseline();
    int w, h;
    ColorFormat cf;
    DepthFormat df;
  };
  const Setup setups[] = {
      {config(1, 16, 4, 4, 16, 4), 64, 64, ColorFormat::rgba8, DepthFormat::unorm24},
      {config(3, 8, 2, 2, 1, 1), 70, 45, ColorFormat::rgba16f, DepthFormat::unorm16},
      {config(16, 8, 8, 8, 2, 2), 100, 37, ColorFormat::rgba8, DepthFormat::float32},
      {config(5, 64, 8, 2, 16, 64), 130, 90, ColorFormat::rgba16f, DepthFormat::float32},
      {config(2, 16, 1, 1, 1, 3), 33, 65, ColorFormat::rgba8, DepthFormat::unorm24},
      {config(7, 32, 4, 8, 2, 1024), 96, 80, ColorFormat::rgba16f, DepthFormat::unorm24},
  };
  std::vector<std::unique_ptr<Case>> cases;
  for (size_t i = 0; i < std::size(setups); ++i) {
    const Setup& st = setups[i];
    for (bool stalls : {false, true}) {
      cases.push_back(std::make_unique<Case>(
          "config_" + std::to_string(i) + (stalls ? "_stalls" : ""),
          mixed_scene(500 + static_cast<uint32_t>(i), st.w, st.h, st.cf, st.df), st.config, stalls,
          i + 1));
    }
  }
  sc_core::sc_start();
  for (const auto& c : cases) c->check();
  // The stalls happened, and changed the timing of the run, not its result.
  for (size_t i = 0; i + 1 < cases.size(); i += 2) {
    const BackEnd& plain = *cases[i]->bench;
    const BackEnd& stalled = *cases[i + 1]->bench;
    EXPECT_EQ(plain.units[0].in->stats().injected_stalls, 0u);
    EXPECT_GT(stalled.units[0].in->stats().injected_stalls, 0u);
    EXPECT_EQ(plain.counter("rop", "fragments_written"),
              stalled.counter("rop", "fragments_written"));
  }
}

// ---------------------------------------------------------------------------
// Tile caches, counted by hand. One unit, a 64x64 framebuffer of 16x16 tiles
// (4 x 4 tiles), 2 cache entries, one full 4x4 stamp per batch, visiting
// tiles A = (0, 0), B = (1, 0), C = (2, 0) in the order A A B A C B, with
// depth func always and depth writes on, so every access dirties its tile.
// LRU with 2 entries:
//   A miss [A] | A hit | B miss [A B] | A hit | C miss, evicts B (dirty) |
//   B miss, evicts A (dirty, last used before C)
// Without a clear: 2 hits, 4 misses, 2 write-backs, then end_of_frame writes
// back C and B: 4 write-backs. A tile is 16 rows x 16 pixels x 4 bytes = 1 KiB.
// After a fast clear: A, B, C are filled from the clear value (no read); only
// the second B is read (it was written back): 2 hits, 1 miss, 3 clear fills;
// write-backs: B and A on eviction, C and B at end_of_frame, and the 13 tiles
// never touched, 17 in all.

UnitTokens stamp_pattern(const std::shared_ptr<RasterPrimitive>& t, const GpuConfig& cfg,
                         const FramebufferDesc& fb, const std::vector<std::array<int, 2>>& origins,
                         bool clear) {
  UnitTokens tokens(1);
  if (clear) tokens[0].push_back(StampBatch{PacketKind::clear, nullptr, {}, {}});
  for (const auto& o : origins) {
    StampBatch b;
    b.primitive = t;
    b.stamps.push_back(make_stamp(*t, o[0], o[1], cfg, fb));
    tokens[0].push_back(b);
  }
  tokens[0].push_back(StampBatch{PacketKind::end_of_frame, nullptr, {}, {}});
  return tokens;
}

TEST(TileCache, HitsMissesAndTrafficOfAnLruPattern) {
  const GpuConfig cfg = config(1, 16, 4, 4, 16, 2);
  Scene scene = make_scene(64, 64, ColorFormat::rgba8, DepthFormat::unorm24);
  scene.draws.push_back(Draw{});
  scene.draws[0].state.depth_func = CompareFunc::always;
  const FrameState frame = frame_state(scene);
  const auto tri = full_screen_triangle(frame.framebuffer, 0.5f);
  // A at (0, 0), B at (16, 0), C at (32, 0); the second A and B use other stamps.
  const std::vector<std::array<int, 2>> origins = {{0, 0}, {4, 0},  {16, 0},
                                                   {0, 8}, {32, 0}, {20, 12}};
  BackEnd plain("plain", cfg, frame, stamp_pattern(tri, cfg, frame.framebuffer, origins, false));
  BackEnd cleared("cleared", cfg, frame, stamp_pattern(tri, cfg, frame.framebuffer, origins, true));
  sc_core::sc_start();

  for (const char* stage : {"depth_test", "rop"}) {
    SCOPED_TRACE(stage);
    EXPECT_EQ(plain.counter(stage, "stamps"), 6u);
    EXPECT_EQ(plain.counter(stage, "cache_hits"), 2u);
    EXPECT_EQ(plain.counter(stage, "cache_misses"), 4u);
    EXPECT_EQ(plain.counter(stage, "cache_clear_fills"), 0u);
    EXPECT_EQ(plain.counter(stage, "cache_writebacks"), 4u);
    EXPECT_EQ(plain.counter(stage, "bytes_read"), 4u * 1024);
    EXPECT_EQ(plain.counter(stage, "bytes_written"), 4u * 1024);

    EXPECT_EQ(cleared.counter(stage, "cache_hits"), 2u);
    EXPECT_EQ(cleared.counter(stage, "cache_misses"), 1u);
    EXPECT_EQ(cleared.counter(stage, "cache_clear_fills"), 3u);
    EXPECT_EQ(cleared.counter(stage, "cache_writebacks"), 17u);
    EXPECT_EQ(cleared.counter(stage, "bytes_read"), 1u * 1024);
    EXPECT_EQ(cleared.counter(stage, "bytes_written"), 17u * 1024);
  }
  EXPECT_EQ(plain.counter("rop", "fragments_written"), 6u * 16);

  // Memory: the 96 written pixels hold the fragment's values; without a clear
  // every other pixel keeps what memory held (the fill pattern), after a
  // clear the clear values.
  const Framebuffer p = plain.framebuffer();
  const Framebuffer c = cleared.framebuffer();
  const DepthValue z = encode_depth(DepthFormat::unorm24, 0.5f);
  const DepthValue clear_z = encode_depth(DepthFormat::unorm24, scene.framebuffer.clear_depth);
  const ColorChannel fill = kFill;
  int written = 0;
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) {
      bool in_stamp = false;
      for (const auto& o : origins) {
        in_stamp = in_stamp || (x >= o[0] && x < o[0] + 4 && y >= o[1] && y < o[1] + 4);
      }
      written += in_stamp;
      const size_t i = p.pixel_index(x, y);
      EXPECT_EQ(p.depth[i], in_stamp ? z : 0xA5A5A5A5u) << x << ", " << y;
      EXPECT_EQ(c.depth[i], in_stamp ? z : clear_z) << x << ", " << y;
      const ColorChannel r = encode_unorm8(0.2f);
      EXPECT_EQ(p.color[4 * i], in_stamp ? r : fill) << x << ", " << y;
      EXPECT_EQ(c.color[4 * i], in_stamp ? r : encode_unorm8(scene.framebuffer.clear_color.x))
          << x << ", " << y;
    }
  }
  EXPECT_EQ(written, 96);
}

// ---------------------------------------------------------------------------
// Timing, computed by hand. Clock 1 ns; memory: 32 bytes per cycle, latency
// 20; tiles 16x16. A tile of unorm24 depth or rgba8 colour is 16 rows of 64
// bytes (2 bus cycles each): on an idle bus its 16 rows, issued together,
// complete after 32 + 20 = 52 cycles. rgba16f rows are 128 bytes: 64 + 20 = 84.

struct Recorder {
  std::vector<double> times;  // cycles at which the sink took each token
};

TEST(BackEndTiming, StagesAloneMatchTheCostModel) {
  GpuConfig cfg = config(1, 16, 4, 4, 16, 4);
  cfg.stages["depth_test"] = {1, 2};
  cfg.stages["interpolator"] = {2, 6};
  cfg.stages["rop"] = {1, 4};
  const sc_time cycle = cfg.cycle();

  Scene depth_scene = make_scene(64, 64, ColorFormat::rgba8, DepthFormat::unorm24);
  depth_scene.draws.push_back(Draw{});
  depth_scene.draws[0].state.depth_func = CompareFunc::always;
  const FrameState depth_frame = frame_state(depth_scene);
  const auto tri = full_screen_triangle(depth_frame.framebuffer, 0.5f);
  auto batch = [&](std::vector<std::array<int, 2>> origins) {
    StampBatch b;
    b.primitive = tri;
    for (const auto& o : origins)
      b.stamps.push_back(make_stamp(*tri, o[0], o[1], cfg, depth_frame.framebuffer));
    return b;
  };
  const StampBatch eof{PacketKind::end_of_frame, nullptr, {}, {}};
  const StampBatch clear{PacketKind::clear, nullptr, {}, {}};

  // (a) Depth test, no clear: a batch of 3 stamps misses, one of 2 hits.
  //   batch 1 read at 0: 3 + 52 = 55 busy, readable at 55 + 2 = 57
  //   batch 2 read at 55: 2 busy, readable at 59
  //   end_of_frame read at 57: the dirty tile's rows are written from
  //     57 + 2 = 59, the bus frees at 91, done at 111: forwarded at 111.
  Memory mem_a("mem_a", memory_size(depth_frame), 20, 32, cycle);
  Fifo<StampBatch> in_a("in_a", 16), out_a("out_a", 16);
  DepthTest depth_a("depth_a", cfg, depth_frame, 0);
  depth_a.in(in_a);
  depth_a.out(out_a);
  depth_a.mem.bind(mem_a);
  Recorder rec_a;
  const std::vector<StampBatch> tokens_a = {batch({{0, 0}, {4, 0}, {8, 4}}),
                                            batch({{0, 12}, {12, 12}}), eof};

  // (b) Depth test after a fast clear, framebuffer 32x16 (two tiles, both
  //   owned): no read at all.
  //   clear read at 0: 1 busy, readable at 3
  //   batch (3 stamps) read at 1: fills tile 0 from the clear value, 3
  //     busy, readable at 6
  //   end_of_frame read at 4: writes tile 0 (dirty) and tile 1 (cleared)
  //     from 6: 64 bus cycles, free at 70, done at 90.
  Scene small_scene = depth_scene;
  small_scene.framebuffer.width = 32;
  small_scene.framebuffer.height = 16;
  const FrameState small_frame = frame_state(small_scene);
  Memory mem_b("mem_b", memory_size(small_frame), 20, 32, cycle);
  Fifo<StampBatch> in_b("in_b", 16), out_b("out_b", 16);
  DepthTest depth_b("depth_b", cfg, small_frame, 0);
  depth_b.in(in_b);
  depth_b.out(out_b);
  depth_b.mem.bind(mem_b);
  Recorder rec_b;
  const std::vector<StampBatch> tokens_b = {clear, batch({{0, 0}, {4, 0}, {8, 4}}), eof};

  // (c) Interpolator, ii 2, latency 6: 3 stamps read at 0, readable at
  //   6 + 6 = 12; end_of_frame read at 6, readable at 8 + 6 = 14.
  Fifo<StampBatch> in_c("in_c", 16);
  Fifo<ShadedStampBatch> out_c("out_c", 16);
  Interpolator interp_c("interp_c", cfg, depth_frame, 0);
  interp_c.in(in_c);
  interp_c.out(out_c);
  Recorder rec_c;
  const std::vector<StampBatch> tokens_c = {batch({{0, 0}, {4, 0}, {8, 4}}), eof};

  // (d) ROP, rgba16f, no clear: 2 stamps read at 0 miss: 2 + 84 = 86 busy.
  //   end_of_frame read at 86: the dirty tile's rows are written from
  //   86 + 4 = 90, the bus frees at 154, done at 174: frame_done at 174.
  Scene color_scene = make_scene(64, 64, ColorFormat::rgba16f, DepthFormat::unorm24);
  color_scene.draws.push_back(Draw{});
  const FrameState color_frame = frame_state(color_scene);
  Memory mem_d("mem_d", memory_size(color_frame), 20, 32, cycle);
  Fifo<ShadedStampBatch> in_d("in_d", 16);
  Rop rop_d("rop_d", cfg, color_frame, 0);
  rop_d.in(in_d);
  rop_d.mem.bind(mem_d);
  ShadedStampBatch shaded;
  shaded.primitive = tri;
  shaded.stamps = batch({{0, 0}, {4, 4}}).stamps;
  shaded.colors.assign(32, glm::vec4(0.5f));
  double frame_done_at = -1;
  bool done_before = true;

  auto at = [&] { return sc_core::sc_time_stamp() / cycle; };
  sc_core::sc_spawn([&] {
    for (const auto& t : tokens_a) in_a.write(t);
  });
  sc_core::sc_spawn([&] {
    for (;;) {
      out_a.read();
      rec_a.times.push_back(at());
    }
  });
  sc_core::sc_spawn([&] {
    for (const auto& t : tokens_b) in_b.write(t);
  });
  sc_core::sc_spawn([&] {
    for (;;) {
      out_b.read();
      rec_b.times.push_back(at());
    }
  });
  sc_core::sc_spawn([&] {
    for (const auto& t : tokens_c) in_c.write(t);
  });
  sc_core::sc_spawn([&] {
    for (;;) {
      out_c.read();
      rec_c.times.push_back(at());
    }
  });
  sc_core::sc_spawn([&] {
    in_d.write(shaded);
    in_d.write(ShadedStampBatch{PacketKind::end_of_frame, nullptr, {}, {}, {}});
  });
  sc_core::sc_spawn([&] {
    sc_core::wait(rop_d.frame_done_event());
    frame_done_at = at();
  });
  sc_core::sc_spawn([&] {
    sc_core::wait(173, sc_core::SC_NS);
    done_before = rop_d.frame_done();
  });
  sc_core::sc_start();

  auto count = [](const StatGroup& g, const char* name) {
    return g.to_json().at(name).get<uint64_t>();
  };
  EXPECT_EQ(rec_a.times, (std::vector<double>{57, 59, 111}));
  EXPECT_EQ(count(depth_a.stats(), "busy_cycles"), 55u + 2 + 54);
  EXPECT_EQ(count(depth_a.stats(), "memory_stall_cycles"), 52u + 0 + 53);
  EXPECT_EQ(count(depth_a.stats(), "cache_misses"), 1u);
  EXPECT_EQ(count(depth_a.stats(), "cache_hits"), 4u);  // one lookup per stamp
  EXPECT_EQ(count(depth_a.stats(), "bytes_read"), 1024u);
  EXPECT_EQ(count(depth_a.stats(), "bytes_written"), 1024u);
  EXPECT_EQ(count(depth_a.stats(), "fragments_passed"), 5u * 16);

  EXPECT_EQ(rec_b.times, (std::vector<double>{3, 6, 90}));
  EXPECT_EQ(count(depth_b.stats(), "busy_cycles"), 1u + 3 + 86);
  EXPECT_EQ(count(depth_b.stats(), "bytes_read"), 0u);
  EXPECT_EQ(count(depth_b.stats(), "bytes_written"), 2048u);
  EXPECT_EQ(count(depth_b.stats(), "cache_clear_fills"), 1u);

  EXPECT_EQ(rec_c.times, (std::vector<double>{12, 14}));
  EXPECT_EQ(count(interp_c.stats(), "busy_cycles"), 8u);

  EXPECT_FALSE(done_before);
  EXPECT_TRUE(rop_d.frame_done());
  EXPECT_EQ(frame_done_at, 174);
  EXPECT_EQ(count(rop_d.stats(), "busy_cycles"), 86u + 88);
  EXPECT_EQ(count(rop_d.stats(), "fragments_written"), 32u);
  EXPECT_EQ(count(rop_d.stats(), "bytes_read"), 2048u);
  EXPECT_EQ(count(rop_d.stats(), "bytes_written"), 2048u);
}

// ---------------------------------------------------------------------------
// Tiled surfaces, bursts, compression and the no-fill path, timed by hand
// (docs/architecture.md, "Tiled surfaces and compression"). As above: clock
// 1 ns, 32 bytes per cycle, latency 20, tiles 16x16, depth_test {1, 2}, rop
// {1, 4}; a unorm24 or rgba8 tile is 1024 bytes.
TEST(BackEndTiming, TiledBurstsCompressionAndNoFill) {
  GpuConfig cfg = config(1, 16, 4, 4, 16, 4);
  cfg.stages["depth_test"] = {1, 2};
  cfg.stages["rop"] = {1, 4};
  const sc_time cycle = cfg.cycle();

  Scene scene = make_scene(64, 64, ColorFormat::rgba8, DepthFormat::unorm24);
  scene.draws.push_back(Draw{});
  scene.draws[0].state.depth_func = CompareFunc::always;
  const FrameState frame = frame_state(scene);
  Scene small = scene;  // two tiles, both owned
  small.framebuffer.width = 32;
  small.framebuffer.height = 16;
  const FrameState small_frame = frame_state(small);
  const auto tri = full_screen_triangle(frame.framebuffer, 0.5f);
  auto batch = [&](std::vector<std::array<int, 2>> origins) {
    StampBatch b;
    b.primitive = tri;
    for (const auto& o : origins)
      b.stamps.push_back(make_stamp(*tri, o[0], o[1], cfg, frame.framebuffer));
    return b;
  };
  // Every stamp of tile (tx, ty), and all but its last.
  auto whole_tile = [&](int tx, int ty, bool all) {
    std::vector<std::array<int, 2>> o;
    for (int j = 0; j < 4; ++j) {
      for (int i = 0; i < 4; ++i) o.push_back({tx * 16 + 4 * i, ty * 16 + 4 * j});
    }
    if (!all) o.pop_back();
    return batch(o);
  };
  const StampBatch eof{PacketKind::end_of_frame, nullptr, {}, {}};
  const StampBatch clear{PacketKind::clear, nullptr, {}, {}};

  struct Bench {
    Bench(const char* name, const GpuConfig& c, const FrameState& f, std::vector<StampBatch> t)
        : mem((std::string(name) + "_mem").c_str(), memory_size(f), 20, 32, c.cycle()),
          in((std::string(name) + "_in").c_str(), 16),
          out((std::string(name) + "_out").c_str(), 16),
          depth(name, c, f, 0),
          tokens(std::move(t)) {
      std::memset(mem.data(0, mem.size()), kFill, mem.size());
      depth.in(in);
      depth.out(out);
      depth.mem.bind(mem);
    }
    uint64_t count(const char* name) const {
      return depth.stats().to_json().at(name).get<uint64_t>();
    }
    Memory mem;
    Fifo<StampBatch> in, out;
    DepthTest depth;
    std::vector<StampBatch> tokens;
    std::vector<double> times;
  };

  // (e) Tiled, bursts of 100 bytes: a tile is 10 bursts of 100 bytes (4 bus
  //   cycles each) and one of 24 (1): 41 cycles, the latency once.
  //   batch of 3 stamps read at 0 misses: 3 + 41 + 20 = 64 busy, readable at 66
  //   batch of 2 read at 64: hits, 2 busy, readable at 68
  //   end_of_frame read at 66: the dirty tile leaves at 68 in 11 bursts,
  //     the bus frees at 109, done at 129: forwarded at 129.
  GpuConfig tiled = cfg;
  tiled.surfaces.tiled = true;
  tiled.surfaces.max_burst_bytes = 100;
  Bench e("depth_e", tiled, frame,
          {batch({{0, 0}, {4, 0}, {8, 4}}), batch({{0, 12}, {12, 12}}), eof});

  // (f) Tiled with depth compression (latencies 8 and 8), one cache entry,
  //   32x16 after a clear. Tile 0 and tile 1 each get one stamp at z = 0.5
  //   among the clear depth 0.75: deltas up to 4194303 need 22 bits, coded
  //   in 24: 4 + 4 + 768 = 776 bytes, moved as 800 (25 bus cycles).
  //   clear read at 0: 1 busy, readable at 3
  //   A (tile 0) read at 1: filled from the clear value, 1 busy, readable at 4
  //   B (tile 1) read at 2: filled from the clear value; tile 0 written
  //     back, posted, through the compressor: issued at 2 + 8 = 10, bus
  //     10..35, done at 55; 1 busy, readable at 5
  //   A again read at 3: a compressed fill of 800 bytes issued at 3 and the
  //     write-back of tile 1 issued at 3 + 8 = 11: the earlier arrival goes
  //     first, after the bus frees at 35: fill 35..60, data at 80, usable
  //     at 88; write-back 60..85, done at 105. 85 stall + 1 busy, ends at
  //     89, readable at 91
  //   end_of_frame read at 89: tile 0 (dirty) leaves at 89 + 2 + 8 = 99,
  //     bus 99..124, done at 144 (after tile 1's at 105): forwarded at 144.
  GpuConfig compressed = cfg;
  compressed.tile_cache_entries = 1;
  compressed.surfaces.tiled = true;
  compressed.compression.depth = true;
  Bench f("depth_f", compressed, small_frame,
          {clear, batch({{0, 0}}), batch({{16, 0}}), batch({{0, 0}}), eof});

  // (g) The no-fill path, linear surfaces: a batch writing every pixel of
  //   tile 0 (depth always, writes on) misses without a read; one missing a
  //   stamp of tile 1 reads it.
  //   full batch read at 0: 16 busy, readable at 18
  //   partial batch read at 16: 15 + 52 = 67 busy, readable at 85
  //   end_of_frame read at 83: both tiles leave at 85, 64 bus cycles, done
  //     at 169: forwarded at 169.
  GpuConfig nofill = cfg;
  nofill.surfaces.skip_overwritten_fill = true;
  Bench g("depth_g", nofill, frame, {whole_tile(0, 0, true), whole_tile(1, 0, false), eof});
  // (h) The same tokens without the no-fill path: the full batch reads too,
  //   16 + 52 = 68, readable at 70; the partial one 15 + 52, from 68 to 135,
  //   readable at 137; end_of_frame read at 135: written from 137, done at 221.
  Bench h("depth_h", cfg, frame, {whole_tile(0, 0, true), whole_tile(1, 0, false), eof});

  // (i) ROP, tiled, colour compression and the no-fill path, 16x16 (one
  //   tile): 16 stamps of one colour cover it, unblended: no read, 16 busy.
  //   end_of_frame read at 16: the constant tile is 4 + 4 bytes, moved as
  //   32 (1 bus cycle), issued at 16 + 4 + 8 = 28, done at 49: frame_done at 49.
  Scene one_tile = scene;
  one_tile.framebuffer.width = 16;
  one_tile.framebuffer.height = 16;
  const FrameState one_frame = frame_state(one_tile);
  GpuConfig colour = cfg;
  colour.surfaces.tiled = true;
  colour.surfaces.skip_overwritten_fill = true;
  colour.compression.colour = true;
  Memory mem_i("mem_i", memory_size(one_frame), 20, 32, cycle);
  Fifo<ShadedStampBatch> in_i("in_i", 16);
  Rop rop_i("rop_i", colour, one_frame, 0);
  rop_i.in(in_i);
  rop_i.mem.bind(mem_i);
  ShadedStampBatch shaded;
  shaded.primitive = tri;
  shaded.stamps = whole_tile(0, 0, true).stamps;
  shaded.colors.assign(256, glm::vec4(0.5f, 0.25f, 1.0f, 1.0f));
  double frame_done_at = -1;

  auto at = [&] { return sc_core::sc_time_stamp() / cycle; };
  for (Bench* b : {&e, &f, &g, &h}) {
    sc_core::sc_spawn([b] {
      for (const auto& t : b->tokens) b->in.write(t);
    });
    sc_core::sc_spawn([b, &at] {
      for (;;) {
        b->out.read();
        b->times.push_back(at());
      }
    });
  }
  sc_core::sc_spawn([&] {
    in_i.write(shaded);
    in_i.write(ShadedStampBatch{PacketKind::end_of_frame, nullptr, {}, {}, {}});
  });
  sc_core::sc_spawn([&] {
    sc_core::wait(rop_i.frame_done_event());
    frame_done_at = at();
  });
  sc_core::sc_start();

  EXPECT_EQ(e.times, (std::vector<double>{66, 68, 129}));
  EXPECT_EQ(e.count("busy_cycles"), 64u + 2 + 63);
  EXPECT_EQ(e.count("bytes_read"), 1024u);
  EXPECT_EQ(e.count("bytes_written"), 1024u);
  EXPECT_EQ(e.mem.client_stats(0).requests, 22u);  // 11 bursts each way
  EXPECT_EQ(e.mem.client_stats(0).busy_cycles, 82u);

  EXPECT_EQ(f.times, (std::vector<double>{3, 4, 5, 91, 144}));
  EXPECT_EQ(f.count("cache_clear_fills"), 2u);
  EXPECT_EQ(f.count("cache_misses"), 1u);
  EXPECT_EQ(f.count("compressed_fills"), 1u);
  EXPECT_EQ(f.count("tiles_compressed"), 3u);
  EXPECT_EQ(f.count("tiles_uncompressed"), 0u);
  EXPECT_EQ(f.count("bytes_read"), 800u);
  EXPECT_EQ(f.count("bytes_written"), 3u * 800);
  EXPECT_EQ(f.count("compression_bytes_saved"), 4u * (1024 - 800));
  EXPECT_EQ(f.count("compressor_busy_cycles"), 3u * 8);
  EXPECT_EQ(f.count("decompressor_busy_cycles"), 8u);
  // The memory holds the decoded depths: the stamps at z = 0.5, the rest
  // at the clear depth, in the tiled layout (each 16x16 tile row-major).
  const DepthValue z = encode_depth(DepthFormat::unorm24, 0.5f);
  const DepthValue clear_z = encode_depth(DepthFormat::unorm24, 0.75f);
  for (int t = 0; t < 2; ++t) {
    for (int p = 0; p < 256; ++p) {
      uint32_t v = 0;
      f.mem.debug_read(small_frame.depth_address + static_cast<uint64_t>(t * 256 + p) * 4, &v, 4);
      EXPECT_EQ(v, (p % 16 < 4 && p / 16 < 4) ? z : clear_z) << t << ", " << p;
    }
  }

  EXPECT_EQ(g.times, (std::vector<double>{18, 85, 169}));
  EXPECT_EQ(g.count("cache_overwrite_allocs"), 1u);
  EXPECT_EQ(g.count("cache_misses"), 1u);
  EXPECT_EQ(g.count("bytes_read"), 1024u);
  EXPECT_EQ(h.times, (std::vector<double>{70, 137, 221}));
  EXPECT_EQ(h.count("cache_overwrite_allocs"), 0u);
  EXPECT_EQ(h.count("bytes_read"), 2048u);
  for (int y = 0; y < 16; ++y) {
    for (int x = 0; x < 32; ++x) {
      uint32_t v = 0;
      g.mem.debug_read(frame.depth_address + (static_cast<uint64_t>(y) * 64 + x) * 4, &v, 4);
      EXPECT_EQ(v, (x >= 28 && y >= 12) ? 0xA5A5A5A5u : z) << x << ", " << y;
    }
  }

  EXPECT_EQ(frame_done_at, 49);
  auto count = [](const StatGroup& s, const char* name) {
    return s.to_json().at(name).get<uint64_t>();
  };
  EXPECT_EQ(count(rop_i.stats(), "busy_cycles"), 16u + 33);
  EXPECT_EQ(count(rop_i.stats(), "bytes_read"), 0u);
  EXPECT_EQ(count(rop_i.stats(), "bytes_written"), 32u);
  EXPECT_EQ(count(rop_i.stats(), "cache_overwrite_allocs"), 1u);
  EXPECT_EQ(count(rop_i.stats(), "tiles_compressed"), 1u);
  for (int p = 0; p < 256; ++p) {
    uint8_t c[4];
    mem_i.debug_read(one_frame.color_address + static_cast<uint64_t>(p) * 4, c, 4);
    EXPECT_EQ(c[0], encode_unorm8(0.5f));
    EXPECT_EQ(c[1], encode_unorm8(0.25f));
    EXPECT_EQ(c[2], 255);
  }
}

}  // namespace
}  // namespace gpusim
