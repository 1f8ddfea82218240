// The resolve stage alone (stages/resolve.h): its box filter over a colour
// buffer of N samples per pixel written here, its wait for every unit's
// end of frame, and its cost: ii per clear token, and per output tile its
// read stall plus ii per output stamp and sample pass.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "hw/simulation_context.h"
#include "stages/resolve.h"

namespace gpusim {
namespace {

// The test's sample values: distinct per pixel, sample and channel.
uint8_t sample_value(int x, int y, unsigned s, int ch) {
  return static_cast<uint8_t>(x * 7 + y * 13 + static_cast<int>(s) * 29 + ch * 5);
}

// Writes the tokens of every unit in order, one unit after the other.
struct Host : sc_core::sc_module {
  sc_core::sc_vector<FifoOutPort<ControlToken>> out;
  std::vector<PacketKind> tokens;
  Host(sc_core::sc_module_name name, unsigned units, std::vector<PacketKind> t)
      : sc_core::sc_module(name), out("out", units), tokens(std::move(t)) {
    SC_HAS_PROCESS(Host);
    SC_THREAD(run);
  }
  void run() {
    for (PacketKind k : tokens) {
      for (auto& port : out) {
        ControlToken token;
        token.kind = k;
        port->write(token);
      }
    }
  }
};

struct Case {
  unsigned samples, supersample, samples_per_pass;
};

class ResolveStage : public ::testing::TestWithParam<Case> {};

TEST_P(ResolveStage, AveragesEverySampleAtItsCost) {
  const Case c = GetParam();
  GpuConfig config = GpuConfig::baseline();  // row-major surfaces, one channel
  config.units = 2;
  config.tile_size = 16;
  config.stamp = {4, 4};
  config.samples_per_pass = c.samples_per_pass;
  config.stages["resolve"] = {3, 4};
  FrameState frame;
  FramebufferDesc& fb = frame.framebuffer;
  const int out_w = 40, out_h = 24;  // 3 x 2 output tiles, the last column and row partial
  const int k = static_cast<int>(c.supersample);
  fb.width = out_w * k;
  fb.height = out_h * k;
  fb.samples = c.samples;
  fb.supersample = c.supersample;
  fb.color_format = ColorFormat::rgba8;
  const uint64_t pixel_bytes = 4ull * c.samples;
  frame.color_address = 0;
  frame.resolve_address = static_cast<uint64_t>(fb.width) * fb.height * pixel_bytes;
  const uint64_t size = frame.resolve_address + static_cast<uint64_t>(out_w) * out_h * 4;

  fresh_simulation_context();
  Memory memory("memory", size, 20, 32, config.cycle());
  uint8_t* rt = memory.data(0, frame.resolve_address);
  for (int y = 0; y < fb.height; ++y) {
    for (int x = 0; x < fb.width; ++x) {
      for (unsigned s = 0; s < c.samples; ++s) {
        for (int ch = 0; ch < 4; ++ch) {
          rt[(static_cast<uint64_t>(y) * fb.width + x) * pixel_bytes + 4 * s + ch] =
              sample_value(x, y, s, ch);
        }
      }
    }
  }
  Resolve resolve("resolve", config, frame);
  Host host("host", config.units, {PacketKind::clear, PacketKind::clear, PacketKind::end_of_frame});
  std::vector<std::unique_ptr<Fifo<ControlToken>>> fifos;
  for (unsigned u = 0; u < config.units; ++u) {
    fifos.push_back(
        std::make_unique<Fifo<ControlToken>>(("rop_to_resolve_" + std::to_string(u)).c_str(), 4));
    host.out[u](*fifos.back());
    resolve.in[u](*fifos.back());
  }
  resolve.mem.bind(memory);
  sc_core::sc_start();

  ASSERT_TRUE(resolve.frame_done());
  // Each output pixel: the mean of its k x k render-target pixels' samples,
  // rounded half up (docs/pipeline-spec.md, section 14).
  const uint8_t* out = memory.data(frame.resolve_address, static_cast<uint64_t>(out_w) * out_h * 4);
  int wrong = 0;
  const double n = static_cast<double>(k * k) * c.samples;
  for (int y = 0; y < out_h; ++y) {
    for (int x = 0; x < out_w; ++x) {
      for (int ch = 0; ch < 4; ++ch) {
        double sum = 0.0;
        for (int j = 0; j < k; ++j)
          for (int i = 0; i < k; ++i)
            for (unsigned s = 0; s < c.samples; ++s)
              sum += sample_value(x * k + i, y * k + j, s, ch);
        const unsigned want = static_cast<unsigned>(std::floor(sum / n + 0.5));
        const unsigned got = out[(static_cast<size_t>(y) * out_w + x) * 4 + ch];
        if (got != want && wrong++ < 5) {
          ADD_FAILURE() << "pixel (" << x << ", " << y << ") channel " << ch << ": " << got
                        << ", want " << want;
        }
      }
    }
  }
  EXPECT_EQ(wrong, 0);

  // The cost model: ii per clear token (each unit's copy is one token), and
  // per tile ii x its stamps x sample passes on top of the read stall.
  const nlohmann::json stats = resolve.stats().to_json();
  const uint64_t ii = 3;
  const uint64_t passes = (k * k * c.samples + c.samples_per_pass - 1) / c.samples_per_pass;
  // 40 x 24 pixels: tiles of 16 x 16, 16 x 8, 8 x 16, 8 x 8 pixels hold 16,
  // 8, 8, 4 stamps; two of the first, one of each other.
  const uint64_t stamps = 2 * 16 + 2 * 8 + 8 + 4 * 1;
  ASSERT_EQ(stamps, 60u);
  EXPECT_EQ(stats["tiles"], 6);
  EXPECT_EQ(stats["pixels"], out_w * out_h);
  EXPECT_EQ(stats["samples"], static_cast<uint64_t>(out_w * out_h) * k * k * c.samples);
  EXPECT_EQ(stats["frames"], 1);
  EXPECT_EQ(stats["tokens_in"], 3 * config.units);
  EXPECT_EQ(stats["busy_cycles"].get<uint64_t>() - stats["memory_stall_cycles"].get<uint64_t>(),
            2 * ii + ii * stamps * passes);
  // The reads of every tile wait for the memory's latency at least.
  EXPECT_GE(stats["memory_stall_cycles"].get<uint64_t>(), 6u * 20u);
}

INSTANTIATE_TEST_SUITE_P(Samples, ResolveStage,
                         ::testing::Values(Case{4, 1, 4}, Case{8, 1, 4}, Case{2, 2, 4},
                                           Case{16, 1, 3}, Case{1, 3, 4}));

}  // namespace
}  // namespace gpusim
