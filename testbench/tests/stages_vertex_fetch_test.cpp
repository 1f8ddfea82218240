// The vertex fetch (stages/vertex_fetch.h): its post-transform cache's tags
// (hits for a known index pattern, FIFO replacement, flushing between draws,
// the cache disabled, non-indexed draws) and its memory traffic (requests,
// bursts of consecutive indices, bytes per attribute), counted by hand. It
// runs in the front-end bench (testbench/tests/front_end_bench.h), whose
// stream is also checked against the golden model, and whose clipper holds
// the cache's data half (its cache_writes and cache_reads mirror the fetch's
// misses and hits). One sc_start per TEST (ctest runs each in its own
// process).
#include <gtest/gtest.h>

#include <cstdint>

#include "testbench/scene/scene.h"
#include "testbench/tests/front_end_bench.h"

namespace gpusim {
namespace {

using namespace test;

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
  FrontEndBench bench("bench", config, frame);
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
  FrontEndBench bench("bench", config, frame);
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

}  // namespace
}  // namespace gpusim
