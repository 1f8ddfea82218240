#include "testbench/session/frame_warnings.h"

#include <sstream>
#include <utility>

#include "testbench/io/message_text.h"

namespace gpusim {
namespace {

// Whether a lit material is white on every colour channel even where the
// surface is turned 60 degrees from each light (n.L = 0.5; spec section 2,
// attenuation taken as 1): its shading then shows almost no shape. Specular
// counts only with shininess 0, where pow(n.H, 0) = 1 on every lit surface.
bool saturates(const Scene& scene, const Material& m) {
  glm::vec3 c = glm::vec3(m.emission) + glm::vec3(scene.global_ambient) * glm::vec3(m.ambient);
  for (const Light& l : scene.lights) {
    c += glm::vec3(l.ambient) * glm::vec3(m.ambient) +
         0.5f * glm::vec3(l.diffuse) * glm::vec3(m.diffuse);
    if (m.shininess == 0.0f) c += glm::vec3(l.specular) * glm::vec3(m.specular);
  }
  return c.r >= 1.0f && c.g >= 1.0f && c.b >= 1.0f;
}

}  // namespace

std::string mesh_file_note(const Scene& scene) {
  if (!scene.from_mesh_file) return "";
  return "gpusim: " + printable(scene.path) +
         " is a mesh, not a scene file: rendering it alone, lit by one directional light (a "
         "scene file sets the camera, lights and states: docs/scene-format.md)";
}

std::string auto_camera_note(const Scene& scene) {
  if (!scene.auto_camera) return "";
  const nlohmann::json& c = scene.resolved["camera"];
  std::ostringstream os;
  os << "gpusim: scene has no camera: framing the meshes' bounding box (eye " << vec_text(c["eye"])
     << ", target " << vec_text(c["target"]) << ", fovy " << c["fovy"].get<double>()
     << "); stats.json's settings.camera has every value";
  return os.str();
}

std::vector<std::string> frame_warnings(const Scene& scene, const PipelineCounts& c) {
  std::vector<std::string> lines;
  const std::string info = "`gpusim info " + printable(scene.path) + "`";
  for (const Draw& d : scene.draws) {
    if (d.lighting && saturates(scene, d.material)) {
      const Material& m = d.material;
      std::ostringstream os;
      os << "warning: " << printable(d.name)
         << ": its material saturates the lighting, so it renders flat white-ish (ambient "
         << vec_text(glm::vec3(m.ambient)) << ", diffuse " << vec_text(glm::vec3(m.diffuse))
         << ", specular " << vec_text(glm::vec3(m.specular)) << ", shininess " << m.shininess
         << "); give the draw a \"material\" with lower values: " << info << " lists the materials";
      lines.push_back(os.str());
    }
  }
  const uint64_t triangles = c.triangles_in;
  const uint64_t reaching = c.triangles_rasterized - c.triangles_offscreen + c.triangles_unfilled;
  if (triangles > 0 && reaching == 0) {
    std::string why;
    for (auto [count, what] : {std::pair{c.triangles_culled, "culled"},
                               {c.triangles_offscreen, "off-screen"},
                               {c.triangles_clipped_away, "clipped away"},
                               {c.triangles_degenerate, "degenerate"},
                               {c.triangles_invalid, "invalid"}}) {
      if (count > 0) why += (why.empty() ? "" : ", ") + std::to_string(count) + " " + what;
    }
    lines.push_back("warning: none of the " + std::to_string(triangles) +
                    " triangles reaches the frame (" + why +
                    "); check the camera and the cull state: " + info +
                    " prints the camera and the bounding box");
  }
  if (triangles + c.lines_in + c.points_in > 0 && c.fragments_generated == 0) {
    lines.push_back(
        "warning: the frame has no fragments: only the clear colour is drawn; check the camera: " +
        info + " prints it and the bounding box");
  }
  return lines;
}

}  // namespace gpusim
