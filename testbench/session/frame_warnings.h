// What `run` and `golden` say on stderr about a frame that rendered, but
// probably not as meant (stats.json does not change): each a line with a
// hint, for the command line to print.
#pragma once

#include <string>
#include <vector>

#include "hw/pipeline_counts.h"
#include "testbench/scene/scene.h"

namespace gpusim {

// "gpusim: scene has no camera: framing ..." when the loader framed the
// meshes (the frame depends on it); empty otherwise.
std::string auto_camera_note(const Scene& scene);
// The note for a mesh given in place of a scene file (Scene::from_mesh_file),
// or "".
std::string mesh_file_note(const Scene& scene);

// "warning: ..." lines: a lit material that saturates (white on every colour
// channel even where the surface is turned 60 degrees from each light), no
// triangle reaching the frame, no fragments at all.
std::vector<std::string> frame_warnings(const Scene& scene, const PipelineCounts& counts);

}  // namespace gpusim
