// gpusim_reference: renders scenes with Mesa's llvmpipe (testbench/reference/
// gl_reference.h) into EXR files in the simulator's layout, for the
// regression suite (scripts/regress, docs/validation.md).
//
//   gpusim_reference SCENE --out FILE.exr [--png FILE.png] [--stats FILE.json] [--repeat N]
//   gpusim_reference --batch LIST     LIST: lines "SCENE OUT.exr [OUT.png [STATS.json]]"
//                                     ("-" for no PNG), one OpenGL context for all
//   gpusim_reference --info           the renderer and version, nothing rendered
//
// --stats also records the render's wall-clock time (`timing`: the median of
// --repeat N renders of the frame in one context, from the clear to
// glFinish() returning; see ReferenceResult), for scripts/bench.
//
// Exit status: 0 done, 2 bad input (one line naming the file and the
// problem), 3 no usable OpenGL (no EGL, no llvmpipe, a GL error), 4 some
// scene not rendered because OpenGL cannot draw it (Bresenham lines: the
// output says which; the other scenes of a batch are rendered).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <systemc>
#include <vector>

#include "hw/input_error.h"
#include "testbench/driver/painter_sort.h"
#include "testbench/io/image_files.h"
#include "testbench/io/output_file.h"
#include "testbench/reference/gl_reference.h"
#include "testbench/scene/scene.h"

namespace gpusim {
namespace {

constexpr int kExitError = 2;
constexpr int kExitNoGl = 3;
constexpr int kExitNotRendered = 4;

nlohmann::json stats_json(const reference::ReferenceStats& s) {
  return {{"triangles", s.triangles},
          {"triangles_invalid", s.triangles_invalid},
          {"triangles_exact", s.triangles_exact},
          {"triangles_clipped", s.triangles_clipped},
          {"triangles_beyond_viewport", s.triangles_beyond_viewport},
          {"lines", s.lines},
          {"lines_invalid", s.lines_invalid},
          {"lines_exact", s.lines_exact},
          {"lines_clipped", s.lines_clipped},
          {"lines_beyond_viewport", s.lines_beyond_viewport},
          {"points", s.points},
          {"points_invalid", s.points_invalid},
          {"points_exact", s.points_exact},
          {"points_discarded", s.points_discarded},
          {"unfilled_draws", s.unfilled_draws},
          {"native_draws", s.native_draws},
          {"expanded_draws", s.expanded_draws}};
}

struct Job {
  std::string scene, exr, png, stats;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  if (n == 0) return 0.0;
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

nlohmann::json timing_json(const reference::ReferenceResult& r) {
  return {{"repeat", r.render_seconds.size()},
          {"render_seconds", median(r.render_seconds)},
          {"render_seconds_first", r.render_seconds.empty() ? 0.0 : r.render_seconds.front()},
          {"render_seconds_each", r.render_seconds},
          {"prepare_seconds", r.prepare_seconds},
          {"covers",
           "render_seconds: median over the repetitions of glClear, every draw call and "
           "glFinish() returning, in one context with the vertices already uploaded; "
           "prepare_seconds: once, the spec's vertex stage on the CPU, triangle classification "
           "and uploads. Neither includes context creation, scene loading, framebuffer "
           "allocation or read-back"}};
}

void render_job(reference::GlReference& gl, const Job& job, int repeat) {
  Scene scene = load_scene(job.scene);
  // The driver's visibility option rewrites the draws before any renderer.
  painter::apply_visibility(scene);
  const reference::ReferenceResult result = gl.render(scene, repeat);
  OutputFiles files;
  write_frame_exr(result.framebuffer, files.add(job.exr));
  if (!job.png.empty()) write_frame_png(result.framebuffer, files.add(job.png));
  if (!job.stats.empty()) {
    const nlohmann::json j = {{"scene", job.scene},
                              {"renderer", gl.renderer()},
                              {"version", gl.version()},
                              {"viewport_side", gl.viewport_side()},
                              {"stats", stats_json(result.stats)},
                              {"timing", timing_json(result)}};
    write_text_file_atomically(files.add(job.stats), j.dump(2) + "\n");
  }
  files.commit();
  const reference::ReferenceStats& s = result.stats;
  std::printf(
      "reference: %s -> %s: %llu triangles (%llu exact, %llu clipped by OpenGL, %llu invalid, "
      "%llu beyond the viewport)\n",
      job.scene.c_str(), job.exr.c_str(), static_cast<unsigned long long>(s.triangles),
      static_cast<unsigned long long>(s.triangles_exact),
      static_cast<unsigned long long>(s.triangles_clipped),
      static_cast<unsigned long long>(s.triangles_invalid),
      static_cast<unsigned long long>(s.triangles_beyond_viewport));
  if (s.lines > 0) {
    std::printf("  %llu lines (%llu exact, %llu clipped by OpenGL, %llu invalid)\n",
                static_cast<unsigned long long>(s.lines),
                static_cast<unsigned long long>(s.lines_exact),
                static_cast<unsigned long long>(s.lines_clipped),
                static_cast<unsigned long long>(s.lines_invalid));
  }
  if (s.points > 0) {
    std::printf(
        "  %llu points (%llu exact, %llu discarded by the spec and left to OpenGL's "
        "clipper, %llu invalid)\n",
        static_cast<unsigned long long>(s.points), static_cast<unsigned long long>(s.points_exact),
        static_cast<unsigned long long>(s.points_discarded),
        static_cast<unsigned long long>(s.points_invalid));
  }
  if (repeat > 1) {
    std::printf("  rendered %d times in %.4f s median (first %.4f s), prepared in %.4f s\n", repeat,
                median(result.render_seconds), result.render_seconds.front(),
                result.prepare_seconds);
  }
}

std::vector<Job> read_batch(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open");
  std::vector<Job> jobs;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    std::istringstream fields(line);
    Job job;
    if (!(fields >> job.scene)) continue;  // blank line
    std::string extra;
    if (!(fields >> job.exr) || (fields >> job.png && fields >> job.stats && fields >> extra)) {
      throw InputError(path + ": line " + std::to_string(number) +
                       ": expected SCENE OUT.exr [OUT.png [STATS.json]]");
    }
    if (job.png == "-") job.png.clear();
    jobs.push_back(job);
  }
  return jobs;
}

int main_with_errors(int argc, char** argv) {
  CLI::App app{"gpusim_reference: render scenes with Mesa's llvmpipe (OpenGL) as EXR references"};
  Job job;
  std::string batch;
  bool info = false;
  int repeat = 1;
  app.add_option("scene", job.scene, "Scene file (JSON, docs/scene-format.md)");
  app.add_option("--out", job.exr,
                 "Output EXR (R, G, B, A half; Z float), like gpusim golden's frame.exr");
  app.add_option("--png", job.png, "Also write an 8-bit PNG preview");
  app.add_option("--stats", job.stats,
                 "Also write how the primitives were handed to OpenGL (JSON)");
  app.add_option(
      "--batch", batch,
      "Render every line \"SCENE OUT.exr [OUT.png [STATS.json]]\" of this file (\"-\": no PNG)");
  app.add_flag("--info", info, "Print GL_RENDERER and GL_VERSION and exit");
  app.add_option("--repeat", repeat,
                 "Draw each frame N times in one context and record each render's time "
                 "(--stats: the median); the output is the same")
      ->check(CLI::Range(1, 1000));
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "gpusim_reference: " << e.what() << " (see gpusim_reference --help)\n";
    return kExitError;
  }
  std::vector<Job> jobs;
  if (!batch.empty()) {
    jobs = read_batch(batch);
  } else if (!job.scene.empty()) {
    if (job.exr.empty()) {
      std::cerr << "gpusim_reference: --out FILE.exr is required with a scene\n";
      return kExitError;
    }
    jobs.push_back(job);
  } else if (!info) {
    std::cerr
        << "gpusim_reference: give a scene, --batch LIST or --info (see gpusim_reference --help)\n";
    return kExitError;
  }

  bool not_rendered = false;
  try {
    reference::GlReference gl;
    if (info) {
      std::printf("GL_RENDERER: %s\nGL_VERSION: %s\nviewport side: %d\n", gl.renderer().c_str(),
                  gl.version().c_str(), gl.viewport_side());
    }
    for (const Job& j : jobs) {
      try {
        render_job(gl, j, repeat);
      } catch (const reference::NotRenderable& e) {
        // Said plainly, and the exit status says it too: never a reference.
        std::printf("reference: %s: NOT RENDERED: %s\n", j.scene.c_str(), e.what());
        not_rendered = true;
      }
    }
  } catch (const reference::ReferenceError& e) {
    std::cerr << "gpusim_reference: no usable OpenGL reference: " << e.what() << "\n";
    return kExitNoGl;
  }
  return not_rendered ? kExitNotRendered : 0;
}

}  // namespace
}  // namespace gpusim

int sc_main(int argc, char* argv[]) {
  try {
    return gpusim::main_with_errors(argc, argv);
  } catch (const gpusim::InputError& e) {
    std::cerr << "gpusim_reference: " << e.what() << "\n";
  } catch (const std::exception& e) {
    std::cerr << "gpusim_reference: internal error: " << e.what() << "\n";
  }
  return gpusim::kExitError;
}

// libsystemc (linked through gpusim_hw) owns main() otherwise; this tool runs
// no simulation, so it calls sc_main directly.
int main(int argc, char* argv[]) {
  return sc_main(argc, argv);
}
