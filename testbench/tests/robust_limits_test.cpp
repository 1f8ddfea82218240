// Limits (docs/robustness.md, "Limits"): the memory a run will need is
// estimated up front from the framebuffer size and the scene's arrays, and a
// request beyond the limit (the machine's memory, or --memory-limit) fails at
// once, with the figures, before anything large is allocated.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "testbench/sim/gpu_run.h"
#include "testbench/sim/memory_budget.h"

namespace gpusim {
namespace {

namespace fs = std::filesystem;

Scene scene_with(int width, int height) {
  Scene s;
  s.path = "limits.json";
  s.framebuffer.width = width;
  s.framebuffer.height = height;
  Draw d;
  d.name = "draws[0]";
  d.positions = {{-1, -1, 0, 1}, {1, -1, 0, 1}, {0, 1, 0, 1}, {0, 0, 0, 1}};
  d.colors.assign(4, glm::vec4(1.0f));
  d.indices = {0, 1, 2, 2, 1, 3};
  d.normals.assign(4, glm::vec3(0, 0, 1));
  d.lighting = true;
  s.draws.push_back(d);
  return s;
}

TEST(Limits, FormatBytes) {
  EXPECT_EQ(format_bytes(0), "0 B");
  EXPECT_EQ(format_bytes(1023), "1023 B");
  EXPECT_EQ(format_bytes(1536), "1.5 KiB");
  EXPECT_EQ(format_bytes(768ull << 20), "768 MiB");
  EXPECT_EQ(format_bytes(5ull << 30), "5.0 GiB");
}

TEST(Limits, EstimatesFollowTheFramebufferAndTheArrays) {
  const Scene small = scene_with(64, 32), big = scene_with(8192, 8192);
  // The GPU memory image is what load_frame() lays out, built once, in place.
  const MemoryEstimate e = estimate_cycle_memory(small, GpuConfig{}, false);
  uint64_t image = 0;
  for (const auto& p : e.parts) {
    if (p.what.find("GPU memory image") != std::string::npos) image = p.bytes;
  }
  EXPECT_EQ(image, load_frame(small).memory.size());
  // Antialiased: N samples per render-target pixel, k^2 render-target pixels
  // per output pixel, plus the resolve's output image.
  for (const auto& [samples, k] : {std::pair{4u, 1u}, std::pair{2u, 3u}, std::pair{1u, 2u}}) {
    Scene aa = small;
    aa.framebuffer.samples = samples;
    aa.framebuffer.supersample = k;
    uint64_t aa_image = 0;
    for (const auto& p : estimate_cycle_memory(aa, GpuConfig{}, false).parts) {
      if (p.what.find("GPU memory image") != std::string::npos) aa_image = p.bytes;
    }
    EXPECT_EQ(aa_image, load_frame(aa).memory.size()) << samples << " samples, x" << k;
    // The golden model's render target: 12 bytes per sample, plus the output.
    uint64_t golden_fb = 0;
    for (const auto& p : estimate_golden_memory(aa).parts) {
      if (p.what.find("golden framebuffer") != std::string::npos) golden_fb = p.bytes;
    }
    EXPECT_EQ(golden_fb, 12ull * 64 * 32 * (1 + k * k * samples)) << samples << " samples, x" << k;
  }
  // 8192x8192: 64 Mi pixels; the golden framebuffer holds 12 bytes a pixel,
  // the output images 16 (`gpusim golden` keeps no last-writer map): 1.75 GiB
  // and the few bytes of the scene's arrays and its shaded-vertex cache.
  const MemoryEstimate g = estimate_golden_memory(big);
  EXPECT_GT(g.total(), 28ull * 8192 * 8192);
  EXPECT_LT(g.total(), 28ull * 8192 * 8192 + 4096);
  EXPECT_EQ(g.describe().find("last writer"), std::string::npos) << g.describe();
  // The golden model's shaded-vertex cache: 64-byte vertex and 8-byte tag
  // per entry, the next power of two of the positions, at most 2^16 entries.
  const auto cache_bytes = [](size_t positions) {
    Scene s = scene_with(64, 32);
    s.draws[0].positions.resize(positions, glm::vec4(0, 0, 0, 1));
    for (const auto& p : estimate_golden_memory(s).parts) {
      if (p.what.find("shaded-vertex cache") != std::string::npos) return p.bytes;
    }
    return uint64_t{0};
  };
  EXPECT_EQ(cache_bytes(4), 4u * 72);
  EXPECT_EQ(cache_bytes(1000), 1024u * 72);
  EXPECT_EQ(cache_bytes(10'000'000), 65536u * 72);
  EXPECT_GT(estimate_cycle_memory(big, GpuConfig{}, true).total(),
            estimate_cycle_memory(big, GpuConfig{}, false).total());
  EXPECT_NE(g.describe().find("golden framebuffer 8192x8192: 768 MiB"), std::string::npos)
      << g.describe();
}

TEST(Limits, RequestBeyondTheLimitFailsWithTheFigures) {
  const Scene big = scene_with(8192, 8192);
  const MemoryLimit limit{256ull << 20, "--memory-limit 256"};
  try {
    check_memory(estimate_golden_memory(big), limit, "big.json");
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind("big.json: needs about 1.8 GiB", 0), 0u) << m;
    EXPECT_NE(m.find("GiB (scene arrays: "), std::string::npos) << m;
    EXPECT_NE(m.find("more than the 256 MiB available (--memory-limit 256)"), std::string::npos)
        << m;
  }
  EXPECT_NO_THROW(check_memory(estimate_golden_memory(scene_with(64, 64)), limit, "small.json"));
}

TEST(Limits, DefaultLimitIsTheMachinesMemory) {
  const MemoryLimit limit = default_memory_limit();
  const uint64_t physical = static_cast<uint64_t>(sysconf(_SC_PHYS_PAGES)) *
                            static_cast<uint64_t>(sysconf(_SC_PAGE_SIZE));
  EXPECT_GT(limit.bytes, 64ull << 20);
  EXPECT_LE(limit.bytes, physical);
  EXPECT_FALSE(limit.source.empty());
  EXPECT_NO_THROW(check_scene_limits(scene_with(8192, 8192)));
}

// End to end: the largest framebuffer under a 100 MiB limit fails at once
// (no 64 Mi-pixel clear, no 2 GiB allocation) with one line, exit 2.
TEST(Limits, CommandLineRefusesAtOnce) {
  const fs::path dir = fs::path(::testing::TempDir()) / ("gpusim_lim_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "big.json")
      << R"({"framebuffer": {"width": 8192, "height": 8192}, "draws": [{"positions": [[-1,-1,0],[1,-1,0],[0,1,0]]}]})";
  for (const char* cmd : {"golden", "run"}) {
    const auto start = std::chrono::steady_clock::now();
    const std::string line = std::string(GPUSIM_BINARY_DIR) + "/gpusim " + cmd + " " +
                             (dir / "big.json").string() + " --memory-limit 100 --out " +
                             (dir / "out").string() + " 2>" + (dir / "err").string();
    const int st = std::system(line.c_str());
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ASSERT_TRUE(WIFEXITED(st));
    EXPECT_EQ(WEXITSTATUS(st), 2) << cmd;
    std::ifstream in(dir / "err");
    std::stringstream err;
    err << in.rdbuf();
    const std::string m = err.str();
    EXPECT_EQ(std::count(m.begin(), m.end(), '\n'), 1) << m;
    EXPECT_NE(m.find((dir / "big.json").string() + ": needs about "), std::string::npos) << m;
    EXPECT_NE(m.find("framebuffer 8192x8192"), std::string::npos) << m;
    EXPECT_NE(m.find("more than the 100 MiB available (--memory-limit 100)"), std::string::npos)
        << m;
    EXPECT_LT(seconds, 5.0) << cmd << " took " << seconds << " s";
    EXPECT_FALSE(fs::exists(dir / "out"));
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace gpusim
