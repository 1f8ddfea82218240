#include "testbench/sim/memory_budget.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <limits>

#include "hw/framebuffer.h"
#include "testbench/golden/golden_model.h"
#include "testbench/sim/gpu_run.h"

namespace gpusim {
namespace {

constexpr uint64_t kAlignment = 64;  // as load_frame() lays buffers out

uint64_t align(uint64_t v) {
  return (v + kAlignment - 1) / kAlignment * kAlignment;
}

uint64_t pixels(const Scene& s) {
  return static_cast<uint64_t>(s.framebuffer.width) * static_cast<uint64_t>(s.framebuffer.height);
}

// Render-target pixels and samples (docs/pipeline-spec.md, section 14):
// k^2 pixels per output pixel, N samples each.
uint64_t target_pixels(const Scene& s) {
  const uint64_t k = s.framebuffer.supersample;
  return pixels(s) * k * k;
}
uint64_t target_samples(const Scene& s) {
  return target_pixels(s) * s.framebuffer.samples;
}

std::string size_text(const Scene& s) {
  std::string t = std::to_string(s.framebuffer.width) + "x" + std::to_string(s.framebuffer.height);
  if (s.framebuffer.supersample > 1)
    t += " supersampled x" + std::to_string(s.framebuffer.supersample);
  if (s.framebuffer.samples > 1) t += ", " + std::to_string(s.framebuffer.samples) + " samples";
  return t;
}

// Bytes of the Framebuffers a model holds: the output image's (colour
// channels and depth per pixel) and, when antialiased, the render target's
// (per sample).
uint64_t framebuffer_bytes(const Scene& s) {
  const uint64_t per_sample = 4 * sizeof(ColorChannel) + sizeof(DepthValue);
  const bool resolved = target_samples(s) != pixels(s);
  return (pixels(s) + (resolved ? target_samples(s) : 0)) * per_sample;
}

// The vertex arrays the scene holds already (they count against the limit).
uint64_t scene_array_bytes(const Scene& s) {
  uint64_t n = 0;
  for (const Draw& d : s.draws) {
    n += d.positions.size() * sizeof(glm::vec4) + d.normals.size() * sizeof(glm::vec3) +
         d.colors.size() * sizeof(glm::vec4) + d.indices.size() * sizeof(uint32_t);
  }
  return n;
}

// What golden::render holds for its largest draw: the shaded-vertex cache,
// a golden::ShadedVertex and a tag per entry, as many entries as the next
// power of two of the draw's positions, at most golden::kShadedVertexCache.
uint64_t golden_draw_bytes(const Scene& s) {
  uint64_t most = 0;
  for (const Draw& d : s.draws) {
    uint64_t entries = 1;
    while (entries < std::min<uint64_t>(d.positions.size(), golden::kShadedVertexCache)) {
      entries *= 2;
    }
    most = std::max<uint64_t>(most, entries * (sizeof(golden::ShadedVertex) + sizeof(int64_t)));
  }
  return most;
}

// load_frame()'s image: colour, depth, then every draw's arrays, each aligned.
uint64_t gpu_image_bytes(const Scene& s) {
  const uint64_t n = target_samples(s);
  const unsigned color = color_bytes_per_pixel(s.framebuffer.color_format);
  uint64_t end = align(n * color) + n * depth_bytes_per_pixel(s.framebuffer.depth_format);
  if (n != pixels(s)) end = align(end) + pixels(s) * color;  // the resolve's output
  for (const Draw& d : s.draws) {
    end = align(end) + d.positions.size() * sizeof(glm::vec4);
    if (d.lighting && !d.normals.empty()) end = align(end) + d.normals.size() * sizeof(glm::vec3);
    if (!d.colors.empty()) end = align(end) + d.colors.size() * sizeof(glm::vec4);
    if (!d.indices.empty()) end = align(end) + d.indices.size() * sizeof(uint32_t);
  }
  return align(end);
}

// frame.exr (four half channels and float depth) and frame.png (rgba8).
uint64_t output_bytes(const Scene& s) {
  return pixels(s) * (4 * 2 + 4 + 4);
}

uint64_t read_number(const char* path) {
  std::ifstream in(path);
  std::string text;
  if (!(in >> text) || text.empty() || text.find_first_not_of("0123456789") != std::string::npos) {
    return std::numeric_limits<uint64_t>::max();  // absent, or "max": no limit
  }
  try {
    return std::stoull(text);
  } catch (const std::exception&) {
    return std::numeric_limits<uint64_t>::max();
  }
}

}  // namespace

uint64_t MemoryEstimate::total() const {
  uint64_t n = 0;
  for (const Part& p : parts) n += p.bytes;
  return n;
}

std::string MemoryEstimate::describe() const {
  std::string s = format_bytes(total()) + " (";
  bool first = true;
  for (const Part& p : parts) {
    if (p.bytes == 0) continue;
    s += (first ? "" : ", ") + p.what + ": " + format_bytes(p.bytes);
    first = false;
  }
  return s + ")";
}

std::string format_bytes(uint64_t bytes) {
  if (bytes < 1024) return std::to_string(bytes) + " B";
  static const char* units[] = {"KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  double v = static_cast<double>(bytes);
  int u = -1;
  while (v >= 1024.0 && u < 5) {
    v /= 1024.0;
    ++u;
  }
  char buf[32];
  std::snprintf(buf, sizeof buf, v < 10.0 ? "%.1f %s" : "%.0f %s", v, units[u]);
  return buf;
}

MemoryEstimate estimate_golden_memory(const Scene& scene) {
  MemoryEstimate e;
  e.parts.push_back({"scene arrays", scene_array_bytes(scene)});
  e.parts.push_back({"golden framebuffer " + size_text(scene), framebuffer_bytes(scene)});
  e.parts.push_back({"largest draw's shaded-vertex cache", golden_draw_bytes(scene)});
  e.parts.push_back({"output images", output_bytes(scene)});
  return e;
}

MemoryEstimate estimate_cycle_memory(const Scene& scene, const GpuConfig& config, bool check) {
  MemoryEstimate e;
  e.parts.push_back({"scene arrays", scene_array_bytes(scene)});
  // run_gpu builds the image in the GPU's memory: one copy.
  e.parts.push_back({"GPU memory image", gpu_image_bytes(scene)});
  e.parts.push_back({"framebuffer " + size_text(scene) + " read back", framebuffer_bytes(scene)});
  uint64_t most_vertices = 0;
  for (const Draw& d : scene.draws) {
    if (!d.indices.empty()) most_vertices = std::max<uint64_t>(most_vertices, d.positions.size());
  }
  if (config.vertex_cache_entries > 0) {
    e.parts.push_back({"vertex cache map", most_vertices * sizeof(uint32_t)});
  }
  if (check) {
    e.parts.push_back(
        {"per-pixel last writer (x2, --check)", 2 * target_pixels(scene) * sizeof(int64_t)});
    e.parts.push_back({"golden framebuffer (--check)", framebuffer_bytes(scene)});
    e.parts.push_back({"largest draw's shaded-vertex cache (--check)", golden_draw_bytes(scene)});
  }
  e.parts.push_back({"output images", output_bytes(scene)});
  return e;
}

MemoryLimit default_memory_limit() {
  MemoryLimit limit;
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page = sysconf(_SC_PAGE_SIZE);
  limit.bytes = pages > 0 && page > 0 ? static_cast<uint64_t>(pages) * static_cast<uint64_t>(page)
                                      : std::numeric_limits<uint64_t>::max();
  limit.source = "physical memory";
  // cgroup v2, then v1: a container's limit below the machine's memory.
  for (const char* path :
       {"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"}) {
    const uint64_t v = read_number(path);
    if (v < limit.bytes) {
      limit.bytes = v;
      limit.source = std::string("control group limit, ") + path;
    }
  }
  return limit;
}

void check_memory(const MemoryEstimate& estimate, const MemoryLimit& limit,
                  const std::string& scene_path) {
  if (estimate.total() <= limit.bytes) return;
  throw InputError(scene_path + ": needs about " + estimate.describe() + ", more than the " +
                   format_bytes(limit.bytes) + " available (" + limit.source + ")");
}

void check_scene_limits(const Scene& scene) {
  constexpr uint64_t kMax = std::numeric_limits<uint32_t>::max();
  for (const Draw& d : scene.draws) {
    if (d.positions.size() > kMax || d.vertex_count() > kMax) {
      throw InputError(scene.path + ": " + d.name + ": " + std::to_string(d.positions.size()) +
                       " positions and " + std::to_string(d.indices.size()) +
                       " indices exceed the GPU's 32-bit counts (at most " + std::to_string(kMax) +
                       ")");
    }
  }
}

}  // namespace gpusim
