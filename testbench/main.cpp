// gpusim: the command line. Subcommands render a scene with a model, or compare
// frames. Bad input ends in one line on stderr naming the file and the problem
// and exit status 2; outputs are written all together or not at all.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <map>
#include <string>
#include <systemc>

#include "testbench/golden/golden_model.h"
#include "hw/input_error.h"
#include "testbench/io/image_compare.h"
#include "testbench/io/image_files.h"
#include "testbench/io/output_file.h"
#include "testbench/scene/scene.h"

namespace gpusim {
namespace {

constexpr int kExitError = 2;

// frame.exr, frame.png and stats.json into dir, committed together.
void write_frame_outputs(const std::string& dir, const Framebuffer& fb,
                         const nlohmann::json& stats) {
  create_output_directory(dir);
  OutputFiles files;
  write_frame_exr(fb, files.add(dir + "/frame.exr"));
  write_frame_png(fb, files.add(dir + "/frame.png"));
  write_text_file_atomically(files.add(dir + "/stats.json"), stats.dump(2) + "\n");
  files.commit();
}

int run_golden(const std::string& scene_path, const std::string& out_dir) {
  const Scene scene = load_scene(scene_path);
  const auto start = std::chrono::steady_clock::now();
  const golden::Result result = golden::render(scene);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  // No wall-clock figures in stats.json: the same input gives the same bytes.
  const nlohmann::json stats = {
      {"model", "golden"},
      {"scene", scene_path},
      {"settings", scene.resolved},
      {"stats", result.stats.to_json()},
  };
  write_frame_outputs(out_dir, result.framebuffer, stats);

  const golden::Stats& s = result.stats;
  std::printf("golden: %s rendered in %.3f s\n", scene_path.c_str(), seconds);
  std::printf("  triangles: %llu in, %llu culled, %llu clipped, %llu rasterized\n",
              static_cast<unsigned long long>(s.triangles_in),
              static_cast<unsigned long long>(s.triangles_culled),
              static_cast<unsigned long long>(s.triangles_clipped),
              static_cast<unsigned long long>(s.triangles_rasterized));
  std::printf("  fragments: %llu generated, %llu passed depth, %llu written\n",
              static_cast<unsigned long long>(s.fragments_generated),
              static_cast<unsigned long long>(s.fragments_passed_depth),
              static_cast<unsigned long long>(s.fragments_written));
  std::printf("  frame: %s/frame.exr (%dx%d), %s/frame.png, %s/stats.json\n", out_dir.c_str(),
              result.framebuffer.width, result.framebuffer.height, out_dir.c_str(),
              out_dir.c_str());
  return 0;
}

struct CompareArgs {
  std::string a, b;
  bool exact = false;
  float tolerance = 0.0f;
  std::vector<std::string> channel_tolerances;  // "R=0.004"
  std::string diff_png;
};

int run_compare(const CompareArgs& args) {
  CompareOptions options;
  options.exact = args.exact;
  options.default_tolerance = args.tolerance;
  for (const std::string& spec : args.channel_tolerances) {
    const size_t eq = spec.find('=');
    float value = 0.0f;
    size_t used = 0;
    try {
      if (eq != std::string::npos) value = std::stof(spec.substr(eq + 1), &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (eq == std::string::npos || eq == 0 || used == 0 || used != spec.size() - eq - 1 ||
        !(value >= 0.0f)) {
      throw InputError("--channel-tolerance " + spec +
                       ": expected CHANNEL=VALUE with VALUE >= 0, e.g. R=0.004");
    }
    options.tolerance[spec.substr(0, eq)] = value;
  }
  const Image a = read_exr(args.a);
  const Image b = read_exr(args.b);
  const CompareResult result = compare_images(a, b, options, args.a, args.b);
  if (!args.diff_png.empty()) write_diff_heatmap(a, b, args.diff_png, options);
  print_compare_report(std::cout, result, args.a, args.b);
  return result.pass() ? 0 : 1;
}

int main_with_errors(int argc, char** argv) {
  CLI::App app{"gpusim: a fixed-function GPU modeled in SystemC, and its golden model"};
  app.require_subcommand(1);

  std::string scene_path, out_dir = "out";
  CLI::App* golden = app.add_subcommand("golden", "Render a scene with the golden model");
  golden->add_option("scene", scene_path, "Scene file (JSON, docs/scene-format.md)")->required();
  golden->add_option("--out", out_dir, "Output directory for frame.exr, frame.png, stats.json")
      ->capture_default_str();

  CompareArgs cmp;
  CLI::App* compare = app.add_subcommand(
      "compare",
      "Compare two EXR frames; exit 0 when equal within tolerance, 1 when not, 2 on error");
  compare->add_option("a", cmp.a, "First EXR")->required();
  compare->add_option("b", cmp.b, "Second EXR")->required();
  CLI::Option* exact =
      compare->add_flag("--exact", cmp.exact, "Require bit-identical values in every channel");
  CLI::Option* tolerance =
      compare->add_option("--tolerance", cmp.tolerance, "Largest |a - b| accepted in any channel")
          ->check(CLI::NonNegativeNumber);
  CLI::Option* channel_tolerance =
      compare->add_option("--channel-tolerance", cmp.channel_tolerances,
                          "Per-channel tolerance, CHANNEL=VALUE (repeatable), e.g. Z=1e-6");
  compare->add_option("--diff", cmp.diff_png, "Write a heat-map PNG of the difference");
  exact->excludes(tolerance)->excludes(channel_tolerance);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "gpusim: " << e.what() << " (see gpusim --help)\n";
    return kExitError;
  }

  if (golden->parsed()) return run_golden(scene_path, out_dir);
  if (compare->parsed()) return run_compare(cmp);
  return kExitError;
}

}  // namespace
}  // namespace gpusim

int sc_main(int argc, char* argv[]) {
  try {
    return gpusim::main_with_errors(argc, argv);
  } catch (const gpusim::InputError& e) {
    std::cerr << "gpusim: " << e.what() << "\n";
  } catch (const std::exception& e) {
    std::cerr << "gpusim: internal error: " << e.what() << "\n";
  }
  return gpusim::kExitError;
}

// Our own main() takes precedence over libsystemc's: it silences SystemC's
// banner (unless the user asks for it) before the kernel starts.
int main(int argc, char* argv[]) {
  setenv("SC_COPYRIGHT_MESSAGE", "DISABLE", 0);
  return sc_core::sc_elab_and_sim(argc, argv);
}
