// The vertex shader (stages/vertex_shader.h) against golden::shade_vertex,
// bit for bit, for every vertex of the spider mesh, a lit sphere and two
// random unlit draws (with colours, with the material's). The vertex fetch,
// with its cache disabled, feeds it (so the fetched vertices of a batch are
// its valid slots in order) and a sink takes its batches; the scenes and
// the driver's loading come from testbench/tests/front_end_bench.h. One
// sc_start per TEST (ctest runs each in its own process).
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "hw/fifo.h"
#include "hw/memory.h"
#include "hw/vertex_packets.h"
#include "stages/vertex_fetch.h"
#include "stages/vertex_shader.h"
#include "testbench/golden/golden_model.h"
#include "testbench/scene/scene.h"
#include "testbench/tests/front_end_bench.h"

namespace gpusim {
namespace {

using namespace test;

// Four floats, bit for bit.
bool same_bits(const glm::vec4& a, const glm::vec4& b) {
  return bits(a.x) == bits(b.x) && bits(a.y) == bits(b.y) && bits(a.z) == bits(b.z) &&
         bits(a.w) == bits(b.w);
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

}  // namespace
}  // namespace gpusim
