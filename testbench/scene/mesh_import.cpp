#include "testbench/scene/mesh_import.h"

#include <assimp/config.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <unistd.h>

#include <algorithm>
#include <assimp/DefaultLogger.hpp>
#include <assimp/Importer.hpp>
#include <assimp/LogStream.hpp>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <utility>

#include "testbench/scene/binary_ply.h"
#include "testbench/scene/texture_image.h"

namespace gpusim {
namespace {

std::string one_line(std::string s) {
  std::replace(s.begin(), s.end(), '\n', ' ');
  std::replace(s.begin(), s.end(), '\r', ' ');
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

bool finite(const glm::vec4& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w);
}

// Replaces `out` only when the material has the key and its value is finite, so
// a file with odd values still gets the documented defaults.
void get_color(const aiMaterial& m, const char* key, unsigned type, unsigned idx, glm::vec4& out) {
  aiColor4D c;
  if (m.Get(key, type, idx, c) != aiReturn_SUCCESS) return;
  // Ambient/specular alpha is unused by the lighting equation; keep it 1.
  const glm::vec4 v{c.r, c.g, c.b, 1.0f};
  if (finite(v)) out = v;
}

Material convert_material(const aiMaterial& m) {
  Material out;
  get_color(m, AI_MATKEY_COLOR_DIFFUSE, out.diffuse);
  get_color(m, AI_MATKEY_COLOR_AMBIENT, out.ambient);
  get_color(m, AI_MATKEY_COLOR_SPECULAR, out.specular);
  float opacity = 1.0f;
  if (m.Get(AI_MATKEY_OPACITY, opacity) == aiReturn_SUCCESS && std::isfinite(opacity)) {
    out.diffuse.a = std::clamp(opacity, 0.0f, 1.0f);
  }
  float shininess = 0.0f;
  if (m.Get(AI_MATKEY_SHININESS, shininess) == aiReturn_SUCCESS && std::isfinite(shininess)) {
    // GL's specular exponent range; glTF roughness conversions can exceed it.
    out.shininess = std::clamp(shininess, 0.0f, 128.0f);
  }
  return out;
}

// assimp's warnings and errors during one import. Importers report some
// damage only there: glTF2 drops faces with out-of-range indices with a
// warning and returns the rest.
class LogCapture {
 public:
  LogCapture() {
    Assimp::DefaultLogger::create("", Assimp::Logger::NORMAL, 0);
    Assimp::DefaultLogger::get()->attachStream(new Stream(m_messages),
                                               Assimp::Logger::Err | Assimp::Logger::Warn);
  }
  ~LogCapture() { Assimp::DefaultLogger::kill(); }
  LogCapture(const LogCapture&) = delete;
  LogCapture& operator=(const LogCapture&) = delete;

  const std::vector<std::string>& messages() const { return m_messages; }
  // The first message containing `text`, or "".
  std::string find(const char* text) const {
    for (const std::string& m : m_messages) {
      if (m.find(text) != std::string::npos) return m;
    }
    return "";
  }

 private:
  // "Warn,  T0: Some faces had ..." -> "Some faces had ...".
  class Stream : public Assimp::LogStream {
   public:
    explicit Stream(std::vector<std::string>& out) : m_out(out) {}
    void write(const char* message) override {
      std::string m = message;
      const size_t colon = m.find(": ");
      if (colon != std::string::npos && colon < 16) m = m.substr(colon + 2);
      m = one_line(m);
      if (!m.empty() && m_out.size() < 16) m_out.push_back(m);
    }

   private:
    std::vector<std::string>& m_out;
  };
  std::vector<std::string> m_messages;
};

// What assimp's parsers print to stderr themselves during one import (the
// OpenGEX parser prints "nullptr returned by creating DDLNode." for
// OpenGEX/empty_camera.ogex): kept out of the terminal, so that an error
// stays one line, and reported with assimp's log.
class StderrCapture {
 public:
  StderrCapture() {
    std::fflush(stderr);
    m_file = std::tmpfile();
    m_saved = m_file != nullptr ? dup(STDERR_FILENO) : -1;
    if (m_saved >= 0) dup2(fileno(m_file), STDERR_FILENO);
  }
  ~StderrCapture() { restore(); }
  StderrCapture(const StderrCapture&) = delete;
  StderrCapture& operator=(const StderrCapture&) = delete;

  // Restores stderr and returns what was written to it, on one line.
  std::string take() {
    restore();
    std::string text;
    if (m_file != nullptr) {
      std::rewind(m_file);
      char buf[512];
      size_t n;
      while ((n = std::fread(buf, 1, sizeof buf, m_file)) > 0 && text.size() < 4096)
        text.append(buf, n);
      std::fclose(m_file);
      m_file = nullptr;
    }
    while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
    return one_line(text);
  }

 private:
  void restore() {
    if (m_saved < 0) return;
    std::fflush(stderr);
    dup2(m_saved, STDERR_FILENO);
    close(m_saved);
    m_saved = -1;
  }
  std::FILE* m_file = nullptr;
  int m_saved = -1;
};

// Whether the file starts with a UTF-16 byte order mark (assimp's text
// importers read UTF-8 or ASCII only; box_UTF16BE.obj gives no faces).
bool starts_utf16(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  unsigned char b[2] = {0, 0};
  in.read(reinterpret_cast<char*>(b), 2);
  return in.gcount() == 2 && ((b[0] == 0xFE && b[1] == 0xFF) || (b[0] == 0xFF && b[1] == 0xFE));
}

// ".PLY" -> ".ply": assimp matches extensions in any case.
std::string lowercase_extension(const std::string& file) {
  std::string ext = std::filesystem::path(file).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext;
}

// A material's diffuse texture (glTF's base colour), decoded once per file
// and shared by every mesh that names it; null without one.
class MaterialTextures {
 public:
  MaterialTextures(const aiScene& scene, const std::string& file)
      : m_scene(scene),
        m_dir(std::filesystem::path(file).parent_path()),
        m_base(std::filesystem::path(file).filename().string()) {}

  struct Use {
    std::shared_ptr<const Texture> texture;
    unsigned uv_channel = 0;
  };
  Use of(const aiMaterial& m) {
    aiString path;
    unsigned uv = 0;
    aiTextureMapMode modes[2] = {aiTextureMapMode_Wrap, aiTextureMapMode_Wrap};
    aiTextureType type = aiTextureType_DIFFUSE;
    if (m.GetTextureCount(type) == 0) type = aiTextureType_BASE_COLOR;
    if (m.GetTextureCount(type) == 0) return {};
    if (m.GetTexture(type, 0, &path, nullptr, &uv, nullptr, nullptr, modes) != aiReturn_SUCCESS) {
      return {};
    }
    std::string name = path.C_Str();
    // A path written on Windows (".\\wall.jpg"): its separators are ours.
    std::replace(name.begin(), name.end(), '\\', '/');
    const std::string key = name + "|" + std::to_string(modes[0]) + std::to_string(modes[1]);
    auto it = m_cache.find(key);
    if (it == m_cache.end()) it = m_cache.emplace(key, load(name, modes)).first;
    return {it->second, uv};
  }

 private:
  std::shared_ptr<const Texture> load(const std::string& name, const aiTextureMapMode* modes) {
    auto t = std::make_shared<Texture>();
    t->name = m_base + " " + name;
    const auto wrap = [&](aiTextureMapMode mode) {
      if (mode == aiTextureMapMode_Wrap) return TextureWrap::repeat;
      if (mode == aiTextureMapMode_Clamp) return TextureWrap::clamp_to_edge;
      throw MeshImportError("texture \"" + name +
                            "\": its wrap mode (mirror or decal) is not "
                            "supported yet");
    };
    t->sampler.wrap_s = wrap(modes[0]);
    t->sampler.wrap_t = wrap(modes[1]);
    // As a model viewer samples: trilinear over generated mipmaps.
    t->sampler.min_filter = TextureFilter::linear_mipmap_linear;
    t->sampler.mag_filter = TextureFilter::linear;
    try {
      const aiTexture* embedded = m_scene.GetEmbeddedTexture(name.c_str());
      if (embedded != nullptr && embedded->mHeight == 0) {
        // A compressed image (a glb's PNG or JPEG): mWidth bytes.
        t->levels.push_back(decode_image(embedded->pcData, embedded->mWidth,
                                         embedded->achFormatHint, std::nullopt, &t->format));
      } else if (embedded != nullptr) {
        // Raw BGRA texels, top row first.
        TextureImage level;
        level.width = static_cast<int>(embedded->mWidth);
        level.height = static_cast<int>(embedded->mHeight);
        if (level.width > kMaxTextureSize || level.height > kMaxTextureSize) {
          throw TextureImageError("larger than " + std::to_string(kMaxTextureSize) +
                                  " texels on a side");
        }
        for (int y = level.height - 1; y >= 0; --y) {
          for (int x = 0; x < level.width; ++x) {
            const aiTexel& c = embedded->pcData[size_t(y) * level.width + x];
            level.texels.insert(level.texels.end(), {c.r, c.g, c.b, c.a});
          }
        }
        t->format = TextureFormat::rgba8;
        t->levels.push_back(std::move(level));
      } else {
        std::filesystem::path p = name;
        if (p.is_relative()) p = m_dir / p;
        t->levels.push_back(read_image_file(p.string(), std::nullopt, &t->format));
      }
    } catch (const TextureImageError& e) {
      throw MeshImportError("texture \"" + name + "\": " + e.what());
    }
    generate_mipmaps(*t);
    return t;
  }

  const aiScene& m_scene;
  const std::filesystem::path m_dir;
  const std::string m_base;
  std::map<std::string, std::shared_ptr<const Texture>> m_cache;
};

}  // namespace

std::vector<ImportedMesh> import_mesh(const std::string& file, bool textures) {
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) throw MeshImportError("is a directory");
  // assimp picks its importer by the name's extension: only a .ply may take
  // the direct path, which gives what assimp would (binary_ply.h).
  const std::string ext = lowercase_extension(file);
  if (ext == ".ply") {
    if (std::optional<std::vector<ImportedMesh>> mesh = read_binary_ply(file))
      return std::move(*mesh);
  }
  return import_mesh_with_assimp(file, textures);
}

bool is_mesh_file_name(const std::string& file) {
  const std::string ext = lowercase_extension(file);
  return ext.size() > 1 && ext != ".json" && Assimp::Importer().IsExtensionSupported(ext);
}

std::vector<ImportedMesh> import_mesh_with_assimp(const std::string& file, bool with_textures) {
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) throw MeshImportError("is a directory");
  Assimp::Importer importer;
  const unsigned flags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                         aiProcess_GenSmoothNormals | aiProcess_PreTransformVertices |
                         aiProcess_SortByPType;
  const LogCapture log;
  // Read, drop the lights and cameras (a scene file has its own), and
  // validate before post-processing: assimp's steps assume a valid scene
  // graph and crash on some importers' output otherwise (RAW/WithColor.raw
  // leaves a null node: a segfault in PreTransformVertices; a light without
  // a node in OpenGEX/camera.ogex: an ai_assert abort).
  importer.SetPropertyInteger(AI_CONFIG_PP_RVC_FLAGS, aiComponent_LIGHTS | aiComponent_CAMERAS);
  StderrCapture printed;
  const aiScene* scene = importer.ReadFile(file, aiProcess_RemoveComponent);
  if (scene != nullptr) scene = importer.ApplyPostProcessing(aiProcess_ValidateDataStructure);
  if (scene != nullptr) scene = importer.ApplyPostProcessing(flags);
  const std::string stderr_text = printed.take();
  if (scene == nullptr) {
    throw MeshImportError(one_line(importer.GetErrorString()) +
                          (stderr_text.empty() ? "" : " (assimp printed: " + stderr_text + ")"));
  }
  // Geometry assimp dropped is not the file's geometry: refuse it.
  const std::string dropped = log.find("out-of-range ind");
  if (!dropped.empty()) throw MeshImportError(dropped);

  std::vector<ImportedMesh> out;
  MaterialTextures textures(*scene, file);
  for (unsigned mi = 0; mi < scene->mNumMeshes; ++mi) {
    const aiMesh* mesh = scene->mMeshes[mi];
    if (mesh == nullptr || mesh->mVertices == nullptr) continue;
    // Faces by kind: 3 indices a triangle, 2 a line, 1 a point. Triangulate
    // has split polygons and leaves lines and points alone; SortByPType has
    // put each kind in its own aiMesh, so normally only one list fills.
    std::vector<uint32_t> by_size[4];
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices < 1 || face.mNumIndices > 3) continue;
      for (unsigned k = 0; k < face.mNumIndices; ++k) {
        if (face.mIndices[k] >= mesh->mNumVertices) {
          throw MeshImportError("mesh " + std::to_string(mi) + " face " + std::to_string(f) +
                                " has an out-of-range vertex index");
        }
        by_size[face.mNumIndices].push_back(face.mIndices[k]);
      }
    }
    if (by_size[1].empty() && by_size[2].empty() && by_size[3].empty()) continue;

    ImportedMesh im;
    im.index = mi;

    const auto where = [&](unsigned v) {
      return "mesh " + std::to_string(mi) + " vertex " + std::to_string(v);
    };
    im.positions.reserve(mesh->mNumVertices);
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      const aiVector3D& p = mesh->mVertices[v];
      const glm::vec4 pos{p.x, p.y, p.z, 1.0f};
      if (!finite(pos)) throw MeshImportError(where(v) + " has a non-finite position");
      im.positions.push_back(pos);
    }
    if (mesh->mNormals != nullptr) {
      im.normals.reserve(mesh->mNumVertices);
      for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
        const aiVector3D& n = mesh->mNormals[v];
        if (!finite(glm::vec4(n.x, n.y, n.z, 0.0f))) {
          throw MeshImportError(where(v) + " has a non-finite normal");
        }
        im.normals.emplace_back(n.x, n.y, n.z);
      }
    }
    if (mesh->mColors[0] != nullptr) {
      im.colors.reserve(mesh->mNumVertices);
      for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
        const aiColor4D& c = mesh->mColors[0][v];
        const glm::vec4 col{c.r, c.g, c.b, c.a};
        if (!finite(col)) throw MeshImportError(where(v) + " has a non-finite colour");
        im.colors.push_back(col);
      }
    }
    if (mesh->mMaterialIndex < scene->mNumMaterials &&
        scene->mMaterials[mesh->mMaterialIndex] != nullptr) {
      const aiMaterial& material = *scene->mMaterials[mesh->mMaterialIndex];
      im.material = convert_material(material);
      const MaterialTextures::Use use =
          with_textures ? textures.of(material) : MaterialTextures::Use{};
      // Without its UV channel a texture has nothing to map it with.
      if (use.texture && use.uv_channel < AI_MAX_NUMBER_OF_TEXTURECOORDS &&
          mesh->mTextureCoords[use.uv_channel] != nullptr) {
        im.texture = use.texture;
        im.texcoords.reserve(mesh->mNumVertices);
        for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
          const aiVector3D& uv = mesh->mTextureCoords[use.uv_channel][v];
          if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) {
            throw MeshImportError(where(v) + " has a non-finite texture coordinate");
          }
          im.texcoords.emplace_back(uv.x, uv.y);
        }
      }
    }
    const std::pair<unsigned, PrimitiveType> kinds[] = {
        {3, PrimitiveType::triangles}, {2, PrimitiveType::lines}, {1, PrimitiveType::points}};
    for (const auto& [size, primitive] : kinds) {
      if (by_size[size].empty()) continue;
      ImportedMesh part = im;  // a copy of the vertices per kind: rare, see above
      part.primitive = primitive;
      part.indices = std::move(by_size[size]);
      out.push_back(std::move(part));
    }
  }
  if (out.empty()) {
    std::string why;
    if (starts_utf16(file)) why = "it is UTF-16 encoded: save it as UTF-8";
    for (const std::string& m : log.messages()) {
      if (why.size() > 200) break;
      why += (why.empty() ? "assimp: " : "; ") + m;
    }
    throw MeshImportError("the file has no triangles, lines or points" +
                          (why.empty() ? "" : " (" + why + ")"));
  }
  return out;
}

}  // namespace gpusim
