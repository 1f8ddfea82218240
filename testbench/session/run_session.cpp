#include "testbench/session/run_session.h"

#include <algorithm>
#include <cstdio>

#include "testbench/io/image_files.h"
#include "testbench/io/message_text.h"
#include "testbench/io/output_file.h"
#include "testbench/session/frame_warnings.h"
#include "testbench/session/session_steps.h"
#include "testbench/sim/memory_budget.h"
#include "traces/trace_filter.h"

namespace gpusim {
namespace {

std::string pixel_text(const Framebuffer& fb, int x, int y) {
  const ColorChannel* c = fb.color_at(x, y);
  char buf[160];
  std::snprintf(buf, sizeof buf, "colour (%g, %g, %g, %g) depth %g",
                decode_color(fb.color_format, c[0]), decode_color(fb.color_format, c[1]),
                decode_color(fb.color_format, c[2]), decode_color(fb.color_format, c[3]),
                decode_depth(fb.depth_format, fb.depth[fb.pixel_index(x, y)]));
  return buf;
}

}  // namespace

CheckReport compare_with_golden(const golden::Result& ref, const GpuRunResult& gpu, unsigned k) {
  CheckReport report;
  const Framebuffer& a = gpu.framebuffer;
  const Framebuffer& b = ref.framebuffer;
  for (int y = 0; y < a.height && !report.pixel; ++y) {
    for (int x = 0; x < a.width; ++x) {
      const size_t p = a.pixel_index(x, y);
      if (std::equal(a.color_at(x, y), a.color_at(x, y) + 4, b.color_at(x, y)) &&
          a.depth[p] == b.depth[p]) {
        continue;
      }
      // The writers of its lower-left render-target pixel.
      const size_t q = size_t{k} * static_cast<size_t>(y) * k * static_cast<size_t>(a.width) +
                       size_t{k} * static_cast<size_t>(x);
      report.pixel = PixelDifference{
          x, y, pixel_text(a, x, y), pixel_text(b, x, y), gpu.last_writer[q], ref.last_writer[q]};
      break;
    }
  }
  report.counts = differences(gpu.counts, ref.stats);
  return report;
}

RunOutcome run_session(const RunRequest& request, Progress& progress) {
  RunOutcome outcome;
  Scene& scene = outcome.scene;
  nlohmann::json driver = nlohmann::json::object();
  scene = prepare_scene(request.scene, request.note, driver, progress);
  const GpuConfig& config = request.config;
  const TraceFormats trace_formats = TraceFormats::parse(request.trace_formats);
  check_memory(estimate_cycle_memory(scene, config, request.check),
               memory_limit(request.memory_mib), request.scene);
  GpuRunOptions options;
  options.record_last_writer = request.check;
  options.progress = &progress;
  options.temporal_decoupling = !request.lockstep;
  // Without a check nothing reads the vertex arrays after the GPU's memory
  // holds them (the warnings read names, lighting and materials): free them
  // before simulating, so that a large mesh is held once.
  if (!request.check) {
    options.scene_arrays_copied = [&scene] {
      for (Draw& d : scene.draws) {
        std::vector<glm::vec4>().swap(d.positions);
        std::vector<glm::vec3>().swap(d.normals);
        std::vector<glm::vec4>().swap(d.colors);
        std::vector<uint32_t>().swap(d.indices);
      }
    };
  }
  // The trace's files, committed with its frame.exr and stats.json below; on
  // any failure they are removed and an earlier trace in the directory stays.
  OutputFiles trace_files;
  options.trace_dir = request.trace_dir;
  options.trace_files = &trace_files;
  options.trace_scene = request.scene;
  options.trace_stages = request.trace_stages;
  options.trace_window = request.trace_window;
  options.trace_prims = request.trace_prims;
  options.trace_formats = request.trace_formats;
  try {
    outcome.result = run_gpu(scene, config, options);
  } catch (const SimulationError& e) {
    throw SessionError(request.scene, e);
  }
  const GpuRunResult& result = outcome.result;
  // No wall-clock figures in stats.json: the same input gives the same bytes.
  outcome.stats = {
      {"model", "cycle"},          {"scene", request.scene},           {"settings", scene.resolved},
      {"config", to_json(config)}, {"stats", result.counts.to_json()}, {"timing", result.timing},
  };
  outcome.stats.update(driver);
  progress.begin(
      "write",
      "frame.exr, frame.png, stats.json into " + printable(request.out_dir) +
          (request.trace_dir.empty() ? "" : ", the trace into " + printable(request.trace_dir)));
  write_frame_outputs(request.out_dir, result.framebuffer, outcome.stats, progress);
  if (!request.trace_dir.empty()) {
    progress.update("writing " + printable(request.trace_dir) + "/frame.exr and stats.json", true);
    write_frame_exr(result.framebuffer, trace_files.add(request.trace_dir + "/frame.exr"));
    write_text_file_atomically(trace_files.add(request.trace_dir + "/stats.json"),
                               outcome.stats.dump(2) + "\n");
    trace_files.commit();
    outcome.trace_files = trace_formats.files();
    outcome.trace_files.insert(outcome.trace_files.begin(), "manifest.json");
  }
  if (request.check) {
    progress.begin("check", "rendering with the golden model");
    outcome.check =
        compare_with_golden(golden::render(scene), result, scene.framebuffer.supersample);
  }
  progress.end();
  outcome.warnings = frame_warnings(scene, result.counts);
  return outcome;
}

}  // namespace gpusim
