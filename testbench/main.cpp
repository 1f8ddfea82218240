// gpusim: the command line. Subcommands render a scene with a model, or compare
// frames. Bad input ends in one line on stderr naming the file and the problem
// and exit status 2 (4 for compare, whose exit codes are idiff's); a
// simulation that hangs or whose counters do not balance ends in a report and
// exit status 3 (docs/robustness.md); outputs are written all together or not
// at all.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <iostream>
#include <map>
#include <new>
#include <optional>
#include <string>
#include <systemc>
#include <vector>

#include "hw/gpu_config.h"
#include "hw/input_error.h"
#include "testbench/gl/feature_report.h"
#include "testbench/io/image_compare.h"
#include "testbench/io/message_text.h"
#include "testbench/scene/scene.h"
#include "testbench/session/golden_session.h"
#include "testbench/session/replay_session.h"
#include "testbench/session/run_session.h"
#include "testbench/session/session_steps.h"
#include "testbench/sim/config_defaults.h"
#include "testbench/sim/gpu_run.h"
#include "testbench/sim/progress.h"
#include "traces/stats_summary.h"
#include "traces/trace_filter.h"
#include "traces/trace_follow.h"
#include "traces/trace_reader.h"
#include "traces/trace_summary.h"

namespace gpusim {
namespace {

constexpr int kExitError = 2;
constexpr int kExitSimulation = 3;

// A number from `low` to `high` (infinite: no bound), its error said in
// words ("'abc' is not a number", "-1 is below 0"): CLI11's own validators
// print an unbounded range up to DBL_MAX, all 309 digits of it.
CLI::Validator number_in(double low, double high = HUGE_VAL) {
  const auto text = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return std::string(buf);
  };
  const std::string bounds =
      std::isinf(high) ? ">= " + text(low) : "from " + text(low) + " to " + text(high);
  return CLI::Validator(
      [=](std::string& value) -> std::string {
        char* end = nullptr;
        errno = 0;
        const double v = std::strtod(value.c_str(), &end);
        if (value.empty() || end != value.c_str() + value.size() || errno == ERANGE ||
            std::isnan(v)) {
          return "'" + value + "' is not a number";
        }
        if (v < low) return value + " is below " + text(low) + ": it must be " + bounds;
        if (v > high) return value + " is above " + text(high) + ": it must be " + bounds;
        return std::string();
      },
      "NUMBER " + bounds);
}

// A simulation failure: "gpusim: <scene>: <report>" on stderr, exit 3.
int report_simulation_error(const std::string& scene_path, const SimulationError& e) {
  std::cerr << "gpusim: " << printable(scene_path) << ": " << printable_report(e.what()) << "\n";
  return kExitSimulation;
}

// The summary's primitive and fragment lines from the counters both models
// report (docs/pipeline-spec.md, section 13); lines and points only when the
// frame has some. Off-screen triangles are rasterized without a pixel, so
// they are shown apart: "rasterized" is the ones that reach the frame.
void print_counts(const PipelineCounts& c) {
  auto u = [](uint64_t v) { return static_cast<unsigned long long>(v); };
  std::printf(
      "  triangles: %llu in, %llu culled, %llu clipped, %llu rasterized, %llu off-screen or "
      "between pixel centres",
      u(c.triangles_in), u(c.triangles_culled), u(c.triangles_clipped),
      u(c.triangles_rasterized - c.triangles_offscreen), u(c.triangles_offscreen));
  if (c.triangles_unfilled > 0) {
    std::printf(", %llu drawn as lines or points", u(c.triangles_unfilled));
  }
  std::printf("\n");
  if (c.lines_in > 0 || c.lines_rasterized > 0) {
    std::printf("  lines: %llu in, %llu clipped away, %llu clipped, %llu rasterized\n",
                u(c.lines_in), u(c.lines_clipped_away), u(c.lines_clipped), u(c.lines_rasterized));
  }
  if (c.points_in > 0 || c.points_rasterized > 0) {
    std::printf("  points: %llu in, %llu clipped away, %llu rasterized\n", u(c.points_in),
                u(c.points_clipped_away), u(c.points_rasterized));
  }
  std::printf("  fragments: %llu generated, %llu passed depth, %llu written\n",
              u(c.fragments_generated), u(c.fragments_passed_depth), u(c.fragments_written));
}

// --progress, --quiet, --progress-interval (run and golden).
struct ProgressArgs {
  bool force = false, quiet = false;
  double interval = 1.0;  // seconds between state lines off a terminal
};

void add_progress_options(CLI::App* cmd, ProgressArgs& p) {
  CLI::Option* force = cmd->add_flag(
      "--progress", p.force,
      "Show progress on stderr even when it is not a terminal: a line per phase and the state "
      "every --progress-interval seconds");
  CLI::Option* quiet = cmd->add_flag("--quiet", p.quiet, "Show no progress, even on a terminal");
  force->excludes(quiet);
  cmd->add_option("--progress-interval", p.interval,
                  "Seconds between progress lines when stderr is not a terminal")
      ->capture_default_str()
      ->check(number_in(0.0));
}

// The progress display on stderr; its phases' wall times end the summary.
Progress make_progress(const ProgressArgs& p) {
  return Progress(Progress::mode_for(p.force, p.quiet, isatty(STDERR_FILENO)), std::cerr,
                  p.interval);
}

// Lines for stderr: a session's notes and warnings.
void print_lines(const std::vector<std::string>& lines) {
  for (const std::string& l : lines) std::cerr << l << "\n";
}

int run_golden(const std::string& scene_path, const std::string& out_dir, uint64_t memory_mib,
               const ProgressArgs& progress_args) {
  Progress progress = make_progress(progress_args);
  GoldenRequest request;
  request.scene = scene_path;
  request.out_dir = out_dir;
  request.memory_mib = memory_mib;
  request.note = [](const std::string& line) { std::cerr << line << "\n"; };
  GoldenOutcome outcome;
  try {
    outcome = golden_session(request, progress);
  } catch (const SessionError& e) {
    progress.interrupt();
    return report_simulation_error(e.where(), e);
  }
  const Framebuffer& fb = outcome.result.framebuffer;
  std::printf("golden: %s rendered in %.3f s\n", scene_path.c_str(), outcome.seconds);
  print_counts(outcome.result.stats);
  std::printf("  frame: %s/frame.exr (%dx%d), %s/frame.png, %s/stats.json\n", out_dir.c_str(),
              fb.width, fb.height, out_dir.c_str(), out_dir.c_str());
  std::printf("  wall: %s\n", progress.wall_summary().c_str());
  std::fflush(stdout);  // the summary, then its warnings, when both go to a terminal
  print_lines(outcome.warnings);
  return 0;
}

struct RunArgs {
  std::string scene;
  std::string config;             // --config FILE ("-": standard input)
  std::vector<std::string> sets;  // --set KEY=VALUE, in the order given
  unsigned units = 0;
  bool units_given = false;  // --units N: --set units=N after every --set
  std::string out_dir = "out";
  bool check = false;
  bool lockstep = false;    // --lockstep: no temporal decoupling
  uint64_t memory_mib = 0;  // 0: the machine's
  // --trace DIR and its filters (docs/traces.md); empty: not traced.
  std::string trace_dir, trace_stages, trace_window, trace_prims;
  std::string trace_formats;  // --trace-formats; empty: every format
};

// The GPU configuration of `run`: the --config file (or the defaults), then
// each --set in order, then --units, validated as a file is; an error names
// the file or the option at fault (docs/gpu-config.md).
GpuConfig resolve_config(const RunArgs& args) {
  nlohmann::json base = nlohmann::json::object();
  GpuConfig config;
  if (!args.config.empty()) {
    base = load_gpu_config_json(args.config);
    config = gpu_config_from_json(base, args.config == "-" ? "standard input" : args.config);
  }
  std::vector<ConfigOverride> overrides;
  for (const std::string& s : args.sets) overrides.push_back({"--set " + s, s});
  if (args.units_given) {
    const std::string n = std::to_string(args.units);
    overrides.push_back({"--units " + n, "units=" + n});
  }
  return overrides.empty() ? config : gpu_config_with_overrides(base, overrides);
}

// `--check`'s lines: the first differing pixel and every differing counter,
// or that the frame is bit-exact.
bool print_check(const CheckReport& check, const Framebuffer& fb) {
  if (const auto& p = check.pixel) {
    std::printf("check: FAIL: first differing pixel x=%d y=%d\n", p->x, p->y);
    std::printf("  cycle model: %s, last written by primitive %lld\n", p->cycle.c_str(),
                static_cast<long long>(p->cycle_writer));
    std::printf("  golden:      %s, last written by primitive %lld\n", p->golden.c_str(),
                static_cast<long long>(p->golden_writer));
  }
  for (const CountDifference& d : check.counts) {
    std::printf("check: FAIL: %s is %llu in the cycle model, %llu in the golden model\n",
                d.name.c_str(), static_cast<unsigned long long>(d.a),
                static_cast<unsigned long long>(d.b));
  }
  if (check.ok()) {
    std::printf("check: bit-exact with the golden model (%dx%d colour and depth, all counters)\n",
                fb.width, fb.height);
  }
  return check.ok();
}

int run_cycle_model(const RunArgs& args, const ProgressArgs& progress_args) {
  Progress progress = make_progress(progress_args);
  RunRequest request;
  request.scene = args.scene;
  request.config = resolve_config(args);
  request.out_dir = args.out_dir;
  request.check = args.check;
  request.lockstep = args.lockstep;
  request.memory_mib = args.memory_mib;
  request.trace_dir = args.trace_dir;
  request.trace_stages = args.trace_stages;
  request.trace_window = args.trace_window;
  request.trace_prims = args.trace_prims;
  request.trace_formats = args.trace_formats;
  request.note = [](const std::string& line) { std::cerr << line << "\n"; };
  RunOutcome outcome;
  try {
    outcome = run_session(request, progress);
  } catch (const SessionError& e) {
    progress.interrupt();
    return report_simulation_error(e.where(), e);  // a hang, or counters that do not balance
  }
  const GpuRunResult& result = outcome.result;
  const GpuConfig& config = request.config;
  const double mhz = config.clock_mhz;
  std::printf(
      "run: %s on %u unit%s: %llu cycles (%.3f ms at %g MHz), simulated in %.3f s (%.3g "
      "cycles/s)\n",
      args.scene.c_str(), config.units, config.units == 1 ? "" : "s",
      static_cast<unsigned long long>(result.cycles),
      static_cast<double>(result.cycles) / (mhz * 1e3), mhz, result.wall_seconds,
      static_cast<double>(result.cycles) / std::max(result.wall_seconds, 1e-9));
  print_counts(result.counts);
  std::printf("  frame: %s/frame.exr, %s/frame.png, %s/stats.json\n", args.out_dir.c_str(),
              args.out_dir.c_str(), args.out_dir.c_str());
  if (!outcome.trace_files.empty()) {
    std::printf("  trace: %s (%s)\n", args.trace_dir.c_str(),
                join(outcome.trace_files, ", ").c_str());
  }
  std::printf("  wall: %s\n", progress.wall_summary().c_str());
  std::fflush(stdout);
  print_lines(outcome.warnings);
  if (outcome.check && !print_check(*outcome.check, result.framebuffer)) return 1;
  return 0;
}

// `gpusim replay TRACE`: an apitrace trace of a fixed-function OpenGL program
// through the GL driver (testbench/gl/gl_driver.h) onto the GPU
// (docs/replay.md).
struct ReplayArgs {
  std::string trace;
  int64_t frame = -1;  // --frame N
  std::string frames;  // --frames A:B
  std::string model = "cycle";
  std::string config;
  std::string out_dir = "replay";
  bool strict = false;
};

// The frames to render, inclusive; last = UINT32_MAX: to the end.
std::pair<uint32_t, uint32_t> replay_range(const ReplayArgs& args) {
  if (args.frame >= 0)
    return {static_cast<uint32_t>(args.frame), static_cast<uint32_t>(args.frame)};
  if (args.frames.empty()) return {0, UINT32_MAX};
  const size_t colon = args.frames.find(':');
  const auto parse = [&](const std::string& text, uint32_t empty) -> uint32_t {
    if (text.empty()) return empty;
    char* end = nullptr;
    errno = 0;
    const unsigned long long v = std::strtoull(text.c_str(), &end, 10);
    if (*end != '\0' || errno != 0 || text[0] == '-' || v >= UINT32_MAX) {
      throw InputError("replay: --frames " + printable(args.frames) +
                       ": expected A:B, frame numbers from 0 (either side may be empty)");
    }
    return static_cast<uint32_t>(v);
  };
  if (colon == std::string::npos) {
    throw InputError("replay: --frames " + printable(args.frames) + ": expected A:B");
  }
  const uint32_t a = parse(args.frames.substr(0, colon), 0);
  const uint32_t b = parse(args.frames.substr(colon + 1), UINT32_MAX);
  if (a > b) throw InputError("replay: --frames " + printable(args.frames) + ": A is after B");
  return {a, b};
}

int run_replay(const ReplayArgs& args, const ProgressArgs& progress_args) {
  using Clock = std::chrono::steady_clock;
  const auto [first, last] = replay_range(args);
  if (args.model != "cycle" && args.model != "golden") {
    throw InputError("replay: --model " + printable(args.model) + ": expected cycle or golden");
  }
  ReplayRequest request;
  request.trace = args.trace;
  request.first = first;
  request.last = last;
  request.cycle = args.model == "cycle";
  request.out_dir = args.out_dir;
  const bool cycle = request.cycle;
  if (!args.config.empty()) {
    request.config = gpu_config_from_json(load_gpu_config_json(args.config),
                                          args.config == "-" ? "standard input" : args.config);
  }
  const Clock::time_point replay_start = Clock::now();
  Progress progress = make_progress(progress_args);
  ReplayCallbacks callbacks;
  callbacks.opened = [&] {
    std::printf("replay: %s through the %s model\n", args.trace.c_str(),
                cycle ? "cycle" : "golden");
  };
  callbacks.frame = [&](const ReplayedFrame& f) {
    std::printf("  frame %u (swap at call %u): %zu draws, %llu vertices, %llu primitives", f.index,
                f.end_call, f.draws, static_cast<unsigned long long>(f.vertices),
                static_cast<unsigned long long>(f.primitives));
    if (cycle) std::printf(", %llu cycles", static_cast<unsigned long long>(f.cycles));
    std::printf("; driver %.3f s, %s %.3f s%s\n", f.driver_seconds, cycle ? "simulation" : "golden",
                f.render_seconds, f.unsupported ? "; uses unsupported features" : "");
    std::fflush(stdout);
  };
  ReplayOutcome outcome;
  try {
    outcome = replay_session(request, progress, callbacks);
  } catch (const SessionError& e) {
    progress.interrupt();
    return report_simulation_error(e.where(), e);
  }
  const uint32_t rendered = outcome.rendered, frames_seen = outcome.frames_seen;
  const gl::FeatureReport& total = outcome.features;
  if (frames_seen == 0) {
    // Without --frame or --frames, the only way to render nothing.
    throw InputError("replay: " + printable(args.trace) +
                     " has no complete frame: no glXSwapBuffers or eglSwapBuffers ends one; a "
                     "program that draws through EGL is recorded with apitrace trace --api egl "
                     "(docs/replay.md, \"Recording traces\")");
  }
  if (rendered == 0 || (last != UINT32_MAX && first + rendered <= last)) {
    throw InputError("replay: " + printable(args.trace) + " has " + std::to_string(frames_seen) +
                     " complete frame" + (frames_seen == 1 ? "" : "s") + " (numbered from 0); " +
                     (args.frame >= 0 ? "--frame " + std::to_string(args.frame)
                                      : "--frames " + printable(args.frames)) +
                     " asks for more");
  }
  std::printf("  %u frame%s into %s/; driver %.3f s, %s %.3f s\n", rendered,
              rendered == 1 ? "" : "s", args.out_dir.c_str(), outcome.driver_seconds,
              cycle ? "simulation" : "golden", outcome.render_seconds);
  for (const auto& [what, count] : total.unsupported()) {
    std::printf("  unsupported: %s: %llu\n", what.c_str(), static_cast<unsigned long long>(count));
  }
  for (const auto& [what, count] : total.ignored()) {
    std::printf("  ignored: %s: %llu\n", what.c_str(), static_cast<unsigned long long>(count));
  }
  // The phases repeat per frame: their sums, in order of first appearance.
  std::vector<std::pair<std::string, double>> sums;
  for (const auto& [phase, seconds] : progress.phases()) {
    // A copy: C++17 lambdas cannot capture a structured binding (clang refuses).
    const std::string name = phase;
    auto it =
        std::find_if(sums.begin(), sums.end(), [&](const auto& p) { return p.first == name; });
    if (it == sums.end()) {
      sums.emplace_back(phase, seconds);
    } else {
      it->second += seconds;
    }
  }
  std::string wall;
  for (const auto& [phase, seconds] : sums) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%s%s %.3f s", wall.empty() ? "" : ", ", phase.c_str(), seconds);
    wall += buf;
  }
  std::printf("  wall: %s; total %.3f s\n", wall.c_str(),
              std::chrono::duration<double>(Clock::now() - replay_start).count());
  std::fflush(stdout);
  if (args.strict && total.any_unsupported()) {
    std::cerr << "gpusim: replay: " << total.unsupported().size()
              << " unsupported feature(s) used (--strict)\n";
    return kExitError;
  }
  return 0;
}

// `gpusim info SCENE`: what the loader made of a scene, to place a camera or
// see why a frame looks wrong: framebuffer, camera, bounding boxes,
// primitives, materials and lights. Values come from Scene::resolved (as in
// stats.json) and the Draws.
int run_info(const std::string& scene_path) {
  const Scene scene = load_scene(scene_path);
  const nlohmann::json& r = scene.resolved;
  const nlohmann::json& fb = r["framebuffer"];
  std::printf("scene: %s\n", printable(scene_path).c_str());
  std::string antialiasing;
  if (scene.framebuffer.samples > 1)
    antialiasing += ", " + std::to_string(scene.framebuffer.samples) + " samples per pixel";
  if (scene.framebuffer.supersample > 1)
    antialiasing += ", supersampled " + std::to_string(scene.framebuffer.supersample) + "x";
  std::printf("framebuffer: %dx%d%s, %s colour, %s depth, clear colour %s, clear depth %g\n",
              fb["width"].get<int>(), fb["height"].get<int>(), antialiasing.c_str(),
              fb["color_format"].get<std::string>().c_str(),
              fb["depth_format"].get<std::string>().c_str(), vec_text(fb["clear_color"]).c_str(),
              fb["clear_depth"].get<double>());

  const nlohmann::json& cam = r["camera"];
  std::string camera = cam["type"].get<std::string>();
  if (scene.auto_camera) {
    camera += ", framed automatically on the meshes' bounding box";
  }
  if (camera == "none") camera += ": raw positions are clip coordinates";
  std::string values;
  for (const char* key :
       {"eye", "target", "up", "fovy", "aspect", "left", "right", "bottom", "top", "near", "far"}) {
    if (!cam.contains(key)) continue;
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", cam[key].is_number() ? cam[key].get<double>() : 0.0);
    values += std::string(values.empty() ? "" : ", ") + key + " " +
              (cam[key].is_array() ? vec_text(cam[key]) : buf);
  }
  std::printf("camera: %s\n", camera.c_str());
  if (!values.empty()) std::printf("  %s\n", values.c_str());
  if (cam["type"] == "matrices") {
    std::printf("  view %s\n  projection %s\n", cam["view"].dump().c_str(),
                cam["projection"].dump().c_str());
  }

  const auto box_text = [](const Bounds& b) {
    if (b.empty()) return std::string("empty");
    return "min " + vec_text(b.min) + ", max " + vec_text(b.max) + ", size " +
           vec_text(b.max - b.min) + ", centre " + vec_text((b.min + b.max) * 0.5f);
  };
  Bounds meshes;
  uint64_t totals[3] = {0, 0, 0};  // by PrimitiveKind
  for (size_t i = 0; i < scene.draws.size(); ++i) {
    if (r["draws"][i].contains("mesh")) meshes.add(world_bounds(scene.draws[i]));
    const Draw& d = scene.draws[i];
    totals[static_cast<int>(primitive_kind_of(d.primitive))] +=
        primitive_count(d.primitive, d.vertex_count());
  }
  std::printf("bounding box of the meshes (world space): %s\n", box_text(meshes).c_str());
  std::printf("ambient: %s\n", vec_text(r["ambient"]).c_str());

  std::printf("lights: %zu\n", scene.lights.size());
  for (size_t i = 0; i < r["lights"].size(); ++i) {
    const nlohmann::json& l = r["lights"][i];
    const bool point = l["type"] == "point";
    std::printf("  lights[%zu]: %s, %s %s", i, l["type"].get<std::string>().c_str(),
                point ? "position" : "direction",
                vec_text(l[point ? "position" : "direction"]).c_str());
    if (point) std::printf(", attenuation %s", vec_text(l["attenuation"]).c_str());
    std::printf(", ambient %s, diffuse %s, specular %s\n", vec_text(l["ambient"]).c_str(),
                vec_text(l["diffuse"]).c_str(), vec_text(l["specular"]).c_str());
  }

  const char* kinds[3] = {"points", "lines", "triangles"};  // PrimitiveKind order
  std::printf("draws: %zu (%llu triangles, %llu lines, %llu points)\n", scene.draws.size(),
              static_cast<unsigned long long>(totals[2]),
              static_cast<unsigned long long>(totals[1]),
              static_cast<unsigned long long>(totals[0]));
  for (size_t i = 0; i < scene.draws.size(); ++i) {
    const Draw& d = scene.draws[i];
    const nlohmann::json& dr = r["draws"][i];
    const bool mesh = dr.contains("mesh");
    // The assembly when it is not the kind's plain list ("triangle_strip").
    const std::string kind = kinds[static_cast<int>(primitive_kind_of(d.primitive))];
    const std::string type(to_string(d.primitive));
    std::printf("  %s: %llu %s%s, %s, %s\n", printable(d.name).c_str(),
                static_cast<unsigned long long>(primitive_count(d.primitive, d.vertex_count())),
                kind.c_str(), type == kind ? "" : (" (" + type + ")").c_str(),
                d.lighting ? "lit" : "unlit", mesh ? "mesh" : "raw positions");
    std::printf("    bounding box%s: %s\n", mesh ? " (world space)" : " (after transform, / w)",
                box_text(world_bounds(d)).c_str());
    const nlohmann::json& m = dr["material"];
    std::printf(
        "    material (%s): ambient %s, diffuse %s, specular %s, emission %s, shininess %g\n",
        dr["material_from"].get<std::string>().c_str(), vec_text(m["ambient"]).c_str(),
        vec_text(m["diffuse"]).c_str(), vec_text(m["specular"]).c_str(),
        vec_text(m["emission"]).c_str(), m["shininess"].get<double>());
    if (d.texture >= 0) {
      const Texture& t = scene.textures[static_cast<size_t>(d.texture)];
      std::printf("    texture %s: %dx%d %s, %zu level%s, min %s, mag %s, wrap %s %s, %s\n",
                  printable(t.name).c_str(), t.levels[0].width, t.levels[0].height,
                  std::string(to_string(t.format)).c_str(), t.levels.size(),
                  t.levels.size() == 1 ? "" : "s",
                  std::string(to_string(t.sampler.min_filter)).c_str(),
                  std::string(to_string(t.sampler.mag_filter)).c_str(),
                  std::string(to_string(t.sampler.wrap_s)).c_str(),
                  std::string(to_string(t.sampler.wrap_t)).c_str(),
                  std::string(to_string(d.texture_env.mode)).c_str());
    }
  }
  if (r.contains("clears")) {
    // Placed by the number of draws before them (docs/scene-format.md, "Clears").
    std::printf("clears: %zu\n", r["clears"].size());
    for (const nlohmann::json& c : r["clears"]) {
      std::printf("  after %llu draw%s:", c["before_draw"].get<unsigned long long>(),
                  c["before_draw"] == 1 ? "" : "s");
      if (c.contains("color")) std::printf(" colour %s", vec_text(c["color"]).c_str());
      if (c.contains("depth")) std::printf(" depth %g", c["depth"].get<double>());
      std::printf("\n");
    }
  }
  return 0;
}

// gpusim compare's exit codes are idiff's: 0 PASS, 1 WARNING, 2 FAILURE
// (Verdict), 3 images of different sizes or channels, 4 an input that cannot
// be read or a bad command line.
constexpr int kExitCompareMismatch = 3;
constexpr int kExitCompareError = 4;

struct CompareArgs {
  std::string a, b;
  CompareOptions options;
  std::vector<std::string> channel_tolerances;  // "R=0.004", "RGBA=0.004"
  std::string diff_png;
};

int run_compare(CompareArgs args) {
  try {
    for (const std::string& spec : args.channel_tolerances) {
      args.options.channel_fail.push_back(parse_channel_threshold(spec));
    }
    const Image a = read_image(args.a);
    const Image b = read_image(args.b);
    args.options.common_channels = a.png || b.png;
    const CompareResult result = compare_images(a, b, args.options, args.a, args.b);
    // The heat-map first: an unwritable path is then the only line printed.
    const double max =
        args.diff_png.empty() ? 0.0 : write_diff_heatmap(a, b, args.diff_png, args.options);
    print_compare_report(std::cout, result, args.a, args.b);
    if (!args.diff_png.empty()) {
      std::cout << "heat-map " << args.diff_png;
      if (max > 0.0) {
        std::cout << ": black = not failing; a failing pixel by its largest channel error e, "
                     "linear: blue (e -> 0), red (e = "
                  << max / 2.0 << "), yellow (e = " << max << " or infinite); legend bar below\n";
      } else if (result.failing_pixels == 0) {
        std::cout << ": black, no failing pixel\n";
      } else {
        std::cout << ": every failing pixel's error is infinite (yellow), the rest black\n";
      }
    }
    return static_cast<int>(result.verdict);
  } catch (const ImageMismatch& e) {
    std::cout.flush();
    std::cerr << "gpusim: " << printable(e.what()) << "\n";
    return kExitCompareMismatch;
  } catch (const InputError& e) {
    std::cout.flush();
    std::cerr << "gpusim: " << printable(e.what()) << "\n";
    return kExitCompareError;
  }
}

// `gpusim trace summary DIR [--json]` and `gpusim trace follow DIR --prim N |
// --pixel X,Y` (docs/traces.md): read a trace written by `run --trace`.
struct TraceArgs {
  std::string dir;
  bool json = false;
  int64_t prim = -1;
  std::string pixel;  // "X,Y"
};

int run_trace_summary(const TraceArgs& args) {
  const TraceReader reader(args.dir);
  const TraceSummary summary(reader);
  if (args.json) {
    std::cout << summary.json().dump(2) << "\n";
  } else {
    std::cout << summary.text();
  }
  return 0;
}

int run_trace_follow(const TraceArgs& args, bool by_prim) {
  const TraceReader reader(args.dir);
  const TraceFollow follow(reader);
  if (by_prim) {
    std::cout << follow.prim_text(args.prim);
    return 0;
  }
  // X,Y: two non-negative integers.
  const size_t comma = args.pixel.find(',');
  int x = -1, y = -1;
  size_t used_x = 0, used_y = 0;
  try {
    if (comma != std::string::npos) {
      x = std::stoi(args.pixel.substr(0, comma), &used_x);
      y = std::stoi(args.pixel.substr(comma + 1), &used_y);
    }
  } catch (const std::exception&) {
    used_x = used_y = 0;
  }
  if (comma == std::string::npos || used_x == 0 || used_x != comma || used_y == 0 ||
      used_y != args.pixel.size() - comma - 1 || x < 0 || y < 0) {
    throw InputError("--pixel " + args.pixel +
                     ": expected X,Y (non-negative integers), e.g. 12,34");
  }
  // The frame's final value at the pixel, from DIR/frame.exr (rows top first).
  const TraceFollow::FrameLookup frame = [&](int px,
                                             int py) -> std::optional<TraceFollow::PixelValue> {
    const Image img = read_exr(reader.path("frame.exr"));
    // A supersampled frame's trace is in render-target pixels, k per output
    // pixel on each side: show the output pixel they resolve into.
    const int k = img.width > 0 ? std::max(1, reader.manifest().width / img.width) : 1;
    px /= k;
    py /= k;
    if (px >= img.width || py >= img.height) return std::nullopt;
    const size_t p = static_cast<size_t>(img.height - 1 - py) * img.width + px;
    TraceFollow::PixelValue v;
    const char* names[5] = {"R", "G", "B", "A", "Z"};
    for (int k = 0; k < 5; ++k) {
      const std::vector<float>* c = img.find(names[k]);
      (k < 4 ? v.rgba[k] : v.depth) = c ? (*c)[p] : std::nanf("");
    }
    return v;
  };
  std::cout << follow.pixel_text(x, y, frame);
  return 0;
}

// `gpusim stats summary STATS.json [--json]` and `gpusim stats diff A B
// [--json]` (docs/stats.md): read what `run --out DIR` wrote in DIR/stats.json.
struct StatsArgs {
  std::string a, b;
  bool json = false;
};

int run_stats_summary(const StatsArgs& args) {
  const StatsSummary summary(read_stats_file(args.a, true), args.a);
  std::cout << (args.json ? summary.json().dump(2) + "\n" : summary.text());
  return 0;
}

int run_stats_diff(const StatsArgs& args) {
  const nlohmann::json a = read_stats_file(args.a, false);
  const nlohmann::json b = read_stats_file(args.b, false);
  const StatsDiff diff(a, args.a, b, args.b);
  std::cout << (args.json ? diff.json().dump(2) + "\n" : diff.text());
  return 0;
}

// ---------------------------------------------------------------- messages

// Levenshtein distance, for "did you mean" suggestions.
size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1] ? 1 : 0)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

// The candidate closest to `word`, if it is close enough to be a likely typo.
std::string closest(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  size_t best_distance = std::max<size_t>(2, word.size() / 3) + 1;
  for (const std::string& c : candidates) {
    const size_t d = edit_distance(word, c);
    if (d < best_distance) best_distance = d, best = c;
  }
  return best;
}

// The most deeply nested subcommand that was parsed (`app` itself when none).
const CLI::App* deepest_parsed(const CLI::App* app) {
  for (const CLI::App* sub : app->get_subcommands()) {  // the parsed ones
    return deepest_parsed(sub);
  }
  return app;
}

// "run", "trace follow": the command words leading to `app`.
std::string command_path(const CLI::App* app) {
  std::string path;
  for (; app->get_parent() != nullptr; app = app->get_parent()) {
    path = path.empty() ? app->get_name() : app->get_name() + " " + path;
  }
  return path;
}

// One line for a command-line error CLI11 reported, naming the word at fault,
// in the order it was typed, and the help to read.
std::string parse_error_message(const CLI::App& app, const CLI::ParseError& e, int argc,
                                char** argv) {
  const CLI::App* where = deepest_parsed(&app);
  const std::string path = command_path(where);
  const std::string prefix = path.empty() ? "" : path + ": ";
  const std::string help = "see gpusim " + (path.empty() ? "" : path + " ") + "--help";
  std::vector<std::string> subcommands;
  const std::function<bool(const CLI::App*)> all = [](const CLI::App*) { return true; };
  for (const CLI::App* sub : where->get_subcommands(all)) subcommands.push_back(sub->get_name());

  // The words after the command path, in the order typed.
  std::vector<std::string> words(argv + 1, argv + argc);
  size_t depth = path.empty() ? 0 : std::count(path.begin(), path.end(), ' ') + 1;
  size_t first = 0;
  for (; depth > 0 && first < words.size(); ++first) {
    if (words[first].empty() || words[first][0] != '-') --depth;
  }

  if (dynamic_cast<const CLI::ExtrasError*>(&e) != nullptr ||
      (!subcommands.empty() && dynamic_cast<const CLI::RequiredError*>(&e) != nullptr)) {
    // The first word this command does not know: an option or a positional.
    std::vector<std::string> options;
    for (const CLI::Option* o : where->get_options()) {
      for (const std::string& n : o->get_lnames()) options.push_back("--" + n);
      for (const std::string& n : o->get_snames()) options.push_back("-" + n);
    }
    for (size_t i = first; i < words.size(); ++i) {
      const std::string& w = words[i];
      if (w.size() > 1 && w[0] == '-') {
        const std::string name = w.substr(0, w.find('='));
        if (std::find(options.begin(), options.end(), name) != options.end()) continue;
        const std::string suggestion = closest(name, options);
        std::string hint = suggestion.empty() ? "" : " (did you mean " + suggestion + "?)";
        // `run --tile-size 32`: a GPU configuration key, set in the --config file.
        std::string key = name.substr(name.find_first_not_of('-'));
        std::replace(key.begin(), key.end(), '-', '_');
        if (path == "run" && to_json(GpuConfig{}).contains(key)) {
          hint = " (" + key + " is a GPU configuration key: --set " + key +
                 "=VALUE, or in the --config file; docs/gpu-config.md)";
        }
        return prefix + "unknown option " + name + hint + "; " + help;
      }
    }
    if (!subcommands.empty()) {
      // A command that takes a subcommand, given none or an unknown one.
      for (size_t i = first; i < words.size(); ++i) {
        if (words[i].empty() || words[i][0] == '-') continue;
        const std::string suggestion = closest(words[i], subcommands);
        return prefix + "unknown command '" + words[i] + "'" +
               (suggestion.empty() ? "" : " (did you mean " + suggestion + "?)") +
               "; commands: " + join(subcommands, ", ") + "; " + help;
      }
      return prefix + "a command is required: " + join(subcommands, ", ") + "; " + help;
    }
    const std::vector<std::string> extras = where->remaining();
    if (!extras.empty()) {
      // remaining() may list them in reverse: report the first one typed.
      for (size_t i = first; i < words.size(); ++i) {
        if (std::find(extras.begin(), extras.end(), words[i]) != extras.end()) {
          return prefix + "unexpected argument '" + words[i] + "'; " + help;
        }
      }
    }
  }
  return prefix + e.what() + "; " + help;
}

// `gpusim sweep ...` (docs/sweeps.md): the sweep runner is
// scripts/gpusim_sweep.py; it runs every point with this very binary.
int run_sweep(int argc, char** argv) {
  std::string self(4096, '\0');
  const ssize_t n = readlink("/proc/self/exe", self.data(), self.size() - 1);
  if (n <= 0) throw InputError("sweep: cannot resolve /proc/self/exe");
  self.resize(static_cast<size_t>(n));
  const char* env_script = std::getenv("GPUSIM_SWEEP_SCRIPT");
  const std::string script = env_script != nullptr
                                 ? env_script
                                 : std::string(GPUSIM_SOURCE_DIR) + "/scripts/gpusim_sweep.py";
  const std::string python = "/usr/bin/python3";
  std::vector<std::string> args = {python, script, "--gpusim", self};
  for (int i = 2; i < argc; ++i) args.push_back(argv[i]);
  std::vector<char*> cargs;
  for (std::string& a : args) cargs.push_back(a.data());
  cargs.push_back(nullptr);
  std::cout.flush();
  execv(python.c_str(), cargs.data());
  throw InputError("sweep: cannot run " + python + " " + script + ": " + std::strerror(errno));
}

int main_with_errors(int argc, char** argv) {
  if (argc >= 2 && std::string(argv[1]) == "sweep") return run_sweep(argc, argv);
  CLI::App app{"gpusim: a fixed-function GPU modeled in SystemC, and its golden model"};
  app.require_subcommand(1);

  std::string scene_path, out_dir = "out";
  uint64_t golden_memory_mib = 0;
  CLI::App* golden = app.add_subcommand("golden", "Render a scene with the golden model");
  golden->add_option("scene", scene_path, "Scene file (JSON, docs/scene-format.md)")->required();
  golden->add_option("--out", out_dir, "Output directory for frame.exr, frame.png, stats.json")
      ->capture_default_str();
  const char* memory_help =
      "Refuse a scene needing more than this many MiB (default: the machine's physical "
      "memory or its control group's limit)";
  golden->add_option("--memory-limit", golden_memory_mib, memory_help);
  ProgressArgs progress_args;
  add_progress_options(golden, progress_args);

  RunArgs run;
  CLI::App* run_cmd = app.add_subcommand("run", "Simulate the cycle-modeled GPU on a scene");
  run_cmd->add_option("scene", run.scene, "Scene file (JSON, docs/scene-format.md)")->required();
  run_cmd->add_option("--config", run.config,
                      "GPU configuration (JSON, docs/gpu-config.md); - reads standard input");
  run_cmd
      ->add_option("--set", run.sets,
                   "Set one configuration key by its dotted path, after --config: KEY=VALUE, "
                   "VALUE JSON or else a string (stages.primitive_setup.ii=2, stamp=[8,8]); "
                   "repeatable, in order")
      ->allow_extra_args(false)
      ->take_all()
      ->expected(1);
  CLI::Option* units_option = run_cmd->add_option(
      "--units", run.units, "Tile rasterizer units: --set units=N, applied after every --set");
  run_cmd->add_option("--out", run.out_dir, "Output directory for frame.exr, frame.png, stats.json")
      ->capture_default_str();
  run_cmd->add_flag(
      "--check", run.check,
      "Also render with the golden model and compare bit for bit (exit 1 on a difference)");
  run_cmd->add_flag("--lockstep", run.lockstep,
                    "Run every stage in the kernel's time, without temporal decoupling "
                    "(docs/architecture.md): slower, the same frame and stats.json");
  run_cmd->add_option("--memory-limit", run.memory_mib, memory_help);
  add_progress_options(run_cmd, progress_args);
  CLI::Option* trace_option =
      run_cmd->add_option("--trace", run.trace_dir,
                          "Record a trace into this directory (docs/traces.md): manifest.json, "
                          "signals.vcd, signals.gtkw, "
                          "timeline.json, transactions.bin, fragments.bin, frame.exr, stats.json");
  run_cmd
      ->add_option("--trace-stages", run.trace_stages,
                   "Trace only these stages: comma-separated names or kinds (depth_test_2, rop)")
      ->needs(trace_option);
  run_cmd
      ->add_option("--trace-window", run.trace_window,
                   "Trace only cycles [START, END): START:END, either side may be empty")
      ->needs(trace_option);
  run_cmd
      ->add_option("--trace-prims", run.trace_prims,
                   "Trace only items and fragments of primitives A to B (inclusive): A:B")
      ->needs(trace_option);
  run_cmd
      ->add_option("--trace-formats", run.trace_formats,
                   "Write only these trace files: comma-separated of vcd (signals.vcd and "
                   "signals.gtkw), timeline, transactions, fragments (default: all)")
      ->needs(trace_option);

  ReplayArgs replay;
  CLI::App* replay_cmd = app.add_subcommand(
      "replay", "Replay an apitrace trace of a fixed-function OpenGL program (docs/replay.md)");
  replay_cmd->add_option("trace", replay.trace, "apitrace trace file (.trace)")->required();
  CLI::Option* frame_option =
      replay_cmd->add_option("--frame", replay.frame, "Render only frame N (from 0)")
          ->check(number_in(0.0));
  replay_cmd
      ->add_option("--frames", replay.frames,
                   "Render frames A to B inclusive: A:B, either side may be empty (default: all)")
      ->excludes(frame_option);
  replay_cmd->add_option("--model", replay.model, "cycle or golden")->capture_default_str();
  replay_cmd->add_option("--config", replay.config,
                         "GPU configuration (JSON, docs/gpu-config.md); - reads standard input");
  replay_cmd
      ->add_option("--out", replay.out_dir,
                   "Output directory for frame_N.exr, frame_N.png, stats_N.json")
      ->capture_default_str();
  replay_cmd->add_flag("--strict", replay.strict,
                       "Exit 2 when a rendered frame used an unsupported feature");
  add_progress_options(replay_cmd, progress_args);

  std::string info_scene;
  CLI::App* info = app.add_subcommand(
      "info", "Print a scene's framebuffer, camera, bounding boxes, primitives, materials, lights");
  info->add_option("scene", info_scene, "Scene file (JSON, docs/scene-format.md)")->required();

  CompareArgs cmp;
  CLI::App* compare = app.add_subcommand(
      "compare",
      "Compare two images (OpenEXR or 8-bit PNG) as idiff does; exit 0 PASS, 1 WARNING, "
      "2 FAILURE, 3 different sizes or channels, 4 unreadable input or bad command line");
  compare->add_option("a", cmp.a, "First image (EXR or PNG)")->required();
  compare->add_option("b", cmp.b, "Second image (EXR or PNG)")->required();
  CLI::Option* exact = compare->add_flag(
      "--exact", cmp.options.exact,
      "A pixel fails when any channel's bits differ (NaN equals NaN); replaces the thresholds");
  CLI::Option* fail =
      compare
          ->add_option("--fail,--tolerance", cmp.options.fail,
                       "Fail threshold: a pixel fails when any channel's |a - b| exceeds it")
          ->check(number_in(0.0))
          ->capture_default_str();
  CLI::Option* channel_tolerance = compare->add_option(
      "--channel-tolerance", cmp.channel_tolerances,
      "Fail threshold of some channels, overriding --fail/--tolerance for them: CHANNEL=VALUE or "
      "a group of R, G, B, A, Z (RGBA=0.004, RGB=0.01, Z=1e-6); repeatable, later wins");
  CLI::Option* warn =
      compare
          ->add_option("--warn", cmp.options.warn,
                       "Warn threshold of every channel (default: each channel's fail threshold)")
          ->check(number_in(0.0));
  compare
      ->add_option("--failpercent", cmp.options.fail_percent,
                   "FAILURE only when more than this % of the pixels fail")
      ->check(number_in(0.0, 100.0))
      ->capture_default_str();
  compare
      ->add_option("--warnpercent", cmp.options.warn_percent,
                   "WARNING only when more than this % of the pixels warn")
      ->check(number_in(0.0, 100.0))
      ->capture_default_str();
  compare
      ->add_option("--hardfail", cmp.options.hard_fail,
                   "FAILURE when any channel's error exceeds this, whatever --failpercent")
      ->check(number_in(0.0));
  compare
      ->add_option("--hardwarn", cmp.options.hard_warn,
                   "WARNING when any channel's error exceeds this, whatever --warnpercent")
      ->check(number_in(0.0));
  compare->add_option(
      "--diff", cmp.diff_png,
      "Write a heat-map PNG of the failing pixels with a legend bar below (docs/validation.md)");
  exact->excludes(fail)->excludes(channel_tolerance)->excludes(warn);
  compare->footer(
      "How the options combine (as OpenImageIO's idiff, thresholds absolute): each channel's fail "
      "threshold is its --channel-tolerance if given (later ones win), else --fail (--tolerance "
      "is the same option), default 1e-06, which accepts the depth differences of a few 1e-07 "
      "between float32 or unorm24 depth computed two ways but not one unorm8 or half step in "
      "colour. A channel's warn threshold is --warn if given, else its fail threshold (idiff "
      "keeps its -warn at 1e-06). A pixel fails (warns) when any channel's |a - b| exceeds its "
      "fail (warn) threshold; --exact makes a pixel fail and warn when any channel's bits differ "
      "instead. The result is FAILURE (exit 2) when more than --failpercent % of the pixels fail "
      "or any error exceeds --hardfail, else WARNING (exit 1) when more than --warnpercent % warn "
      "or any error exceeds --hardwarn, else PASS (exit 0); so failing pixels within "
      "--failpercent give WARNING unless --warnpercent allows them too. NaN against a number, "
      "and +inf against -inf or a number, is an infinite error. A PNG (8-bit, value/255) against "
      "an EXR compares the channels both have (R, G, B, and A if the PNG has alpha); two EXRs "
      "must have the same channels (else exit 3). PSNR = 20 log10(1 / RMS error), for data in "
      "[0, 1].");

  // Listed for --help only: main_with_errors() hands `sweep` to run_sweep().
  app.add_subcommand("sweep",
                     "Run a design-space sweep of scenes x configurations, locally or on Slurm "
                     "(docs/sweeps.md); sweep collect DIR, sweep plot DIR");

  TraceArgs trace_args;
  CLI::App* trace = app.add_subcommand("trace", "Inspect a trace written by run --trace");
  trace->require_subcommand(1);
  CLI::App* trace_summary = trace->add_subcommand(
      "summary", "Per-stage utilization, the bottleneck, FIFO occupancy, unit load balance");
  trace_summary->add_option("dir", trace_args.dir, "Trace directory (run --trace DIR)")->required();
  trace_summary->add_flag("--json", trace_args.json, "Print JSON instead of text");
  CLI::App* trace_follow = trace->add_subcommand(
      "follow", "Follow a primitive through the stages, or a pixel's fragments");
  trace_follow->add_option("dir", trace_args.dir, "Trace directory (run --trace DIR)")->required();
  CLI::Option* prim_option = trace_follow->add_option(
      "--prim", trace_args.prim, "Primitive id: every stage it passed, with cycles and unit");
  CLI::Option* pixel_option = trace_follow->add_option(
      "--pixel", trace_args.pixel,
      "X,Y (window coordinates, origin lower left): every fragment that touched the pixel");
  prim_option->excludes(pixel_option);

  StatsArgs stats_args;
  CLI::App* stats = app.add_subcommand("stats", "Read a run's stats.json without a trace");
  stats->require_subcommand(1);
  CLI::App* stats_summary = stats->add_subcommand(
      "summary",
      "Per-stage utilization, the bottleneck, rates, memory and unit load balance of a stats.json");
  stats_summary->add_option("stats", stats_args.a, "stats.json of gpusim run --out DIR")
      ->required();
  stats_summary->add_flag("--json", stats_args.json, "Print JSON instead of text");
  CLI::App* stats_diff = stats->add_subcommand(
      "diff", "Every number that differs between two stats.json, largest relative change first");
  stats_diff->add_option("a", stats_args.a, "First stats.json")->required();
  stats_diff->add_option("b", stats_args.b, "Second stats.json")->required();
  stats_diff->add_flag("--json", stats_args.json, "Print JSON instead of text");

  std::string config_table;
  CLI::App* config_cmd = app.add_subcommand(
      "config",
      "Print the default GPU configuration (every key, stages and FIFOs in pipeline order, each "
      "stage's cost with its reason) or a table of docs/gpu-config.md");
  config_cmd->add_flag("--defaults", "The default configuration file (the default)");
  bool config_renamed = false;
  config_cmd->add_flag("--renamed", config_renamed,
                       "The renamed stages' former kinds, still read with a warning: JSON "
                       "{former: current}");
  config_cmd
      ->add_option("--markdown", config_table,
                   "A generated table of the docs instead: stages or fifos (docs/gpu-config.md), "
                   "costs (docs/architecture.md)")
      ->check(CLI::IsMember({"stages", "fifos", "costs"}));

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "gpusim: " << parse_error_message(app, e, argc, argv) << "\n";
    return deepest_parsed(&app) == compare ? kExitCompareError : kExitError;
  }

  if (golden->parsed()) return run_golden(scene_path, out_dir, golden_memory_mib, progress_args);
  if (run_cmd->parsed()) {
    run.units_given = units_option->count() > 0;
    return run_cycle_model(run, progress_args);
  }
  if (replay_cmd->parsed()) return run_replay(replay, progress_args);
  if (info->parsed()) return run_info(info_scene);
  if (config_cmd->parsed()) {
    if (config_renamed) {
      nlohmann::json renamed = nlohmann::json::object();
      for (const StageSpec* s : StageRegistry::all()) {
        for (const std::string& former : s->former_kinds) renamed[former] = s->kind;
      }
      std::cout << renamed.dump() << "\n";
      return 0;
    }
    const PipelineKinds kinds = pipeline_kinds();
    std::cout << (config_table.empty() ? default_config_text(kinds)
                                       : markdown_table(kinds, config_table));
    return 0;
  }
  if (compare->parsed()) return run_compare(cmp);
  if (trace_summary->parsed()) return run_trace_summary(trace_args);
  if (stats_summary->parsed()) return run_stats_summary(stats_args);
  if (stats_diff->parsed()) return run_stats_diff(stats_args);
  if (trace_follow->parsed()) {
    if (prim_option->count() == 0 && pixel_option->count() == 0) {
      throw InputError("trace follow: give --prim N or --pixel X,Y");
    }
    return run_trace_follow(trace_args, prim_option->count() > 0);
  }
  return kExitError;
}

}  // namespace
}  // namespace gpusim

int sc_main(int argc, char* argv[]) {
  try {
    return gpusim::main_with_errors(argc, argv);
  } catch (const gpusim::SimulationError& e) {
    // A report of several lines; the first names the scene.
    std::cerr << "gpusim: " << gpusim::printable_report(e.what()) << "\n";
    return gpusim::kExitSimulation;
  } catch (const gpusim::InputError& e) {
    std::cerr << "gpusim: " << gpusim::printable(e.what()) << "\n";
  } catch (const std::bad_alloc&) {
    std::cerr << "gpusim: out of memory\n";
  } catch (const std::exception& e) {
    std::cerr << "gpusim: internal error: " << gpusim::printable(e.what()) << "\n";
  }
  return gpusim::kExitError;
}

// Our own main() takes precedence over libsystemc's: it silences SystemC's
// banner (unless the user asks for it) before the kernel starts.
int main(int argc, char* argv[]) {
  setenv("SC_COPYRIGHT_MESSAGE", "DISABLE", 0);
  return sc_core::sc_elab_and_sim(argc, argv);
}
