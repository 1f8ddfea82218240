#include "testbench/session/session_steps.h"

#include "testbench/driver/painter_sort.h"
#include "testbench/io/image_files.h"
#include "testbench/io/message_text.h"
#include "testbench/io/output_file.h"
#include "testbench/session/frame_warnings.h"

namespace gpusim {

MemoryLimit memory_limit(uint64_t mib) {
  if (mib == 0) return default_memory_limit();
  const uint64_t bytes = mib > (UINT64_MAX >> 20) ? UINT64_MAX : mib << 20;
  return MemoryLimit{bytes, "--memory-limit " + std::to_string(mib)};
}

Scene prepare_scene(const std::string& path, const std::function<void(const std::string&)>& note,
                    nlohmann::json& stats_sections, Progress& progress) {
  progress.begin("load", "reading " + printable(path));
  Scene scene =
      load_scene(path, [&](const std::string& what) { progress.update(printable(what), true); });
  for (const std::string& line : {mesh_file_note(scene), auto_camera_note(scene)}) {
    if (!line.empty() && note) note(line);
  }
  if (scene.visibility == Visibility::painter)
    progress.begin("driver", "sorting the draws back to front (painter)");
  if (const auto painter = painter::apply_visibility(scene))
    stats_sections["painter"] = painter->to_json();
  check_scene_limits(scene);
  return scene;
}

void write_frame_outputs(const std::string& dir, const Framebuffer& fb, const nlohmann::json& stats,
                         Progress& progress) {
  create_output_directory(dir);
  OutputFiles files;
  const auto add = [&](const std::string& name) {
    progress.update("writing " + printable(dir) + "/" + name, true);
    return files.add(dir + "/" + name);
  };
  write_frame_exr(fb, add("frame.exr"));
  write_frame_png(fb, add("frame.png"));
  write_text_file_atomically(add("stats.json"), stats.dump(2) + "\n");
  files.commit();
}

}  // namespace gpusim
