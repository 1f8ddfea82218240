#include "testbench/session/replay_session.h"

#include <chrono>

#include "testbench/gl/apitrace_reader.h"
#include "testbench/gl/gl_driver.h"
#include "testbench/golden/golden_model.h"
#include "testbench/io/image_files.h"
#include "testbench/io/message_text.h"
#include "testbench/io/output_file.h"
#include "testbench/session/session_steps.h"
#include "testbench/sim/gpu_run.h"
#include "testbench/sim/memory_budget.h"

namespace gpusim {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

}  // namespace

ReplayOutcome replay_session(const ReplayRequest& request, Progress& progress,
                             const ReplayCallbacks& callbacks) {
  const std::string model = request.cycle ? "cycle" : "golden";
  progress.begin("driver", "reading " + printable(request.trace));
  gl::ApitraceReader reader(request.trace);
  OutputDirectory out_dir(request.out_dir);
  gl::GlDriver driver;
  driver.set_capture(request.first == 0);
  if (callbacks.opened) callbacks.opened();
  ReplayOutcome outcome;
  // One GPU for the replay, reset between frames (a frame with another
  // netlist elaborates another).
  GpuRunner gpu(request.config, GpuRunOptions{});
  gl::TraceCall call;
  Clock::time_point frame_start = Clock::now();
  while (reader.next(call)) {
    if (!driver.call(call)) {
      if ((call.number & 0xFFF) == 0) {
        progress.update(
            "frame " + std::to_string(outcome.frames_seen) + ", call " +
            std::to_string(call.number) + ", " +
            std::to_string(reader.bytes_read() * 100 / std::max<uint64_t>(reader.file_size(), 1)) +
            "% of the trace read");
      }
      continue;
    }
    gl::DriverFrame frame = driver.take_frame();
    ++outcome.frames_seen;
    driver.set_capture(frame.index + 1 >= request.first && frame.index + 1 <= request.last);
    if (frame.index < request.first) {
      frame_start = Clock::now();
      continue;
    }
    ReplayedFrame done;
    done.index = frame.index;
    done.end_call = frame.end_call;
    done.draws = frame.scene.draws.size();
    done.vertices = frame.vertices;
    done.primitives = frame.primitives;
    done.unsupported = frame.features.any_unsupported();
    done.driver_seconds = seconds_since(frame_start);
    const Scene& scene = frame.scene;
    check_scene_limits(scene);
    const std::string n = std::to_string(frame.index);
    progress.begin("render", "frame " + n + ": " + std::to_string(scene.draws.size()) +
                                 " draws through the " + model + " model");
    const Clock::time_point render_start = Clock::now();
    nlohmann::json stats = {
        {"model", model}, {"scene", request.trace + " frame " + n}, {"trace", request.trace}};
    Framebuffer fb;
    if (request.cycle) {
      GpuRunResult result;
      try {
        result = gpu.run(scene);
      } catch (const SimulationError& e) {
        throw SessionError(request.trace + " frame " + n, e);
      }
      done.cycles = result.cycles;
      fb = std::move(result.framebuffer);
      stats["config"] = to_json(request.config);
      stats["stats"] = result.counts.to_json();
      stats["timing"] = result.timing;
    } else {
      golden::Result result = golden::render(scene, golden::RenderOptions{false});
      fb = std::move(result.framebuffer);
      stats["stats"] = result.stats.to_json();
    }
    done.render_seconds = seconds_since(render_start);
    stats["driver"] = frame.to_json();
    // No wall-clock figures in the stats: the same trace gives the same bytes.
    progress.begin("write", "frame_" + n + ".exr, .png, stats_" + n + ".json");
    OutputFiles files;
    write_frame_exr(fb, files.add(request.out_dir + "/frame_" + n + ".exr"));
    // The PNG as the window shows it: opaque, like apitrace's images, so that
    // a reader that premultiplies alpha compares the same colours (the EXR
    // keeps the alpha channel).
    Framebuffer opaque = fb;
    for (size_t i = 3; i < opaque.color.size(); i += 4) {
      opaque.color[i] = encode_color(opaque.color_format, 1.0f);
    }
    write_frame_png(opaque, files.add(request.out_dir + "/frame_" + n + ".png"));
    write_text_file_atomically(files.add(request.out_dir + "/stats_" + n + ".json"),
                               stats.dump(2) + "\n");
    files.commit();
    out_dir.keep();
    progress.begin("driver", "reading " + printable(request.trace));
    outcome.features.merge(frame.features);
    ++outcome.rendered;
    outcome.driver_seconds += done.driver_seconds;
    outcome.render_seconds += done.render_seconds;
    if (callbacks.frame) callbacks.frame(done);
    frame_start = Clock::now();
    if (frame.index >= request.last) break;
  }
  progress.end();
  return outcome;
}

}  // namespace gpusim
