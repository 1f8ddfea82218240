#include "testbench/reference/gl_reference.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "hw/pixel_formats.h"
#include "testbench/golden/golden_model.h"

namespace gpusim::reference {
namespace {

// The OpenGL entry points used, all resolved through eglGetProcAddress
// (Mesa resolves core functions too: EGL_KHR_get_all_proc_addresses).
#define GPUSIM_GL_FUNCTIONS(X)                                                 \
  X(PFNGLGETSTRINGPROC, glGetString)                                           \
  X(PFNGLGETERRORPROC, glGetError)                                             \
  X(PFNGLGETINTEGERVPROC, glGetIntegerv)                                       \
  X(PFNGLENABLEPROC, glEnable)                                                 \
  X(PFNGLDISABLEPROC, glDisable)                                               \
  X(PFNGLVIEWPORTPROC, glViewport)                                             \
  X(PFNGLCLIPCONTROLPROC, glClipControl)                                       \
  X(PFNGLDEPTHRANGEPROC, glDepthRange)                                         \
  X(PFNGLSCISSORPROC, glScissor)                                               \
  X(PFNGLCLEARCOLORPROC, glClearColor)                                         \
  X(PFNGLCLEARDEPTHPROC, glClearDepth)                                         \
  X(PFNGLCLEARPROC, glClear)                                                   \
  X(PFNGLCOLORMASKPROC, glColorMask)                                           \
  X(PFNGLDEPTHMASKPROC, glDepthMask)                                           \
  X(PFNGLDEPTHFUNCPROC, glDepthFunc)                                           \
  X(PFNGLCULLFACEPROC, glCullFace)                                             \
  X(PFNGLFRONTFACEPROC, glFrontFace)                                           \
  X(PFNGLPOLYGONOFFSETPROC, glPolygonOffset)                                   \
  X(PFNGLBLENDFUNCPROC, glBlendFunc)                                           \
  X(PFNGLBLENDEQUATIONPROC, glBlendEquation)                                   \
  X(PFNGLPROVOKINGVERTEXPROC, glProvokingVertex)                               \
  X(PFNGLPIXELSTOREIPROC, glPixelStorei)                                       \
  X(PFNGLREADPIXELSPROC, glReadPixels)                                         \
  X(PFNGLFINISHPROC, glFinish)                                                 \
  X(PFNGLGENFRAMEBUFFERSPROC, glGenFramebuffers)                               \
  X(PFNGLDELETEFRAMEBUFFERSPROC, glDeleteFramebuffers)                         \
  X(PFNGLBINDFRAMEBUFFERPROC, glBindFramebuffer)                               \
  X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, glCheckFramebufferStatus)                 \
  X(PFNGLFRAMEBUFFERRENDERBUFFERPROC, glFramebufferRenderbuffer)               \
  X(PFNGLGENRENDERBUFFERSPROC, glGenRenderbuffers)                             \
  X(PFNGLDELETERENDERBUFFERSPROC, glDeleteRenderbuffers)                       \
  X(PFNGLBINDRENDERBUFFERPROC, glBindRenderbuffer)                             \
  X(PFNGLRENDERBUFFERSTORAGEPROC, glRenderbufferStorage)                       \
  X(PFNGLRENDERBUFFERSTORAGEMULTISAMPLEPROC, glRenderbufferStorageMultisample) \
  X(PFNGLBLITFRAMEBUFFERPROC, glBlitFramebuffer)                               \
  X(PFNGLGENVERTEXARRAYSPROC, glGenVertexArrays)                               \
  X(PFNGLDELETEVERTEXARRAYSPROC, glDeleteVertexArrays)                         \
  X(PFNGLBINDVERTEXARRAYPROC, glBindVertexArray)                               \
  X(PFNGLGENBUFFERSPROC, glGenBuffers)                                         \
  X(PFNGLDELETEBUFFERSPROC, glDeleteBuffers)                                   \
  X(PFNGLBINDBUFFERPROC, glBindBuffer)                                         \
  X(PFNGLBUFFERDATAPROC, glBufferData)                                         \
  X(PFNGLVERTEXATTRIBPOINTERPROC, glVertexAttribPointer)                       \
  X(PFNGLENABLEVERTEXATTRIBARRAYPROC, glEnableVertexAttribArray)               \
  X(PFNGLDRAWARRAYSPROC, glDrawArrays)                                         \
  X(PFNGLDRAWELEMENTSPROC, glDrawElements)                                     \
  X(PFNGLCREATESHADERPROC, glCreateShader)                                     \
  X(PFNGLSHADERSOURCEPROC, glShaderSource)                                     \
  X(PFNGLCOMPILESHADERPROC, glCompileShader)                                   \
  X(PFNGLGETSHADERIVPROC, glGetShaderiv)                                       \
  X(PFNGLGETSHADERINFOLOGPROC, glGetShaderInfoLog)                             \
  X(PFNGLDELETESHADERPROC, glDeleteShader)                                     \
  X(PFNGLCREATEPROGRAMPROC, glCreateProgram)                                   \
  X(PFNGLATTACHSHADERPROC, glAttachShader)                                     \
  X(PFNGLLINKPROGRAMPROC, glLinkProgram)                                       \
  X(PFNGLGETPROGRAMIVPROC, glGetProgramiv)                                     \
  X(PFNGLGETPROGRAMINFOLOGPROC, glGetProgramInfoLog)                           \
  X(PFNGLDELETEPROGRAMPROC, glDeleteProgram)                                   \
  X(PFNGLUSEPROGRAMPROC, glUseProgram)                                         \
  X(PFNGLGETUNIFORMLOCATIONPROC, glGetUniformLocation)                         \
  X(PFNGLUNIFORM1IPROC, glUniform1i)                                           \
  X(PFNGLUNIFORM1FPROC, glUniform1f)                                           \
  X(PFNGLUNIFORM4FVPROC, glUniform4fv)                                         \
  X(PFNGLLINEWIDTHPROC, glLineWidth)                                           \
  X(PFNGLPOINTSIZEPROC, glPointSize)                                           \
  X(PFNGLPOLYGONMODEPROC, glPolygonMode)                                       \
  X(PFNGLGENTEXTURESPROC, glGenTextures)                                       \
  X(PFNGLDELETETEXTURESPROC, glDeleteTextures)                                 \
  X(PFNGLBINDTEXTUREPROC, glBindTexture)                                       \
  X(PFNGLACTIVETEXTUREPROC, glActiveTexture)                                   \
  X(PFNGLTEXIMAGE2DPROC, glTexImage2D)                                         \
  X(PFNGLTEXPARAMETERIPROC, glTexParameteri)                                   \
  X(PFNGLTEXPARAMETERFPROC, glTexParameterf)                                   \
  X(PFNGLTEXPARAMETERIVPROC, glTexParameteriv)

struct Gl {
#define GPUSIM_GL_MEMBER(type, name) type name = nullptr;
  GPUSIM_GL_FUNCTIONS(GPUSIM_GL_MEMBER)
#undef GPUSIM_GL_MEMBER

  void load() {
#define GPUSIM_GL_LOAD(type, name)                         \
  name = reinterpret_cast<type>(eglGetProcAddress(#name)); \
  if (name == nullptr) throw ReferenceError("eglGetProcAddress(\"" #name "\") failed");
    GPUSIM_GL_FUNCTIONS(GPUSIM_GL_LOAD)
#undef GPUSIM_GL_LOAD
  }
};

// Fragment colour modes (uniform u_mode).
// kModeWindowGouraud also serves screen interpolation in clip space: the
// colour in the noperspective varying and 1/w = 1.
constexpr int kModeWindowGouraud = 0;  // window-space vertex: colour/w over 1/w, per fragment
constexpr int kModeClipGouraud = 1;    // clip-space vertex: OpenGL's perspective correction
constexpr int kModeFlat = 2;           // provoking vertex's colour (glProvokingVertex's choice)
// Phong (spec section 9b): the colour lit per fragment from the normal and
// eye position, interpolated as modes 0 and 1 interpolate the colour.
constexpr int kModeWindowPhong = 3;
constexpr int kModeClipPhong = 4;
// Lights the fragment shader's Phong lighting takes (uniform arrays).
constexpr size_t kMaxPhongLights = 8;

const char* const kVertexShader = R"(#version 330 core
layout(location = 0) in vec4 a_position;
layout(location = 1) in vec4 a_color;
layout(location = 2) in vec4 a_color_over_w;
layout(location = 3) in float a_inv_w;
layout(location = 4) in vec3 a_normal;
layout(location = 5) in vec3 a_eye;
layout(location = 6) in vec3 a_normal_over_w;
layout(location = 7) in vec3 a_eye_over_w;
layout(location = 8) in vec2 a_texcoord;
layout(location = 9) in vec2 a_texcoord_over_w;
smooth out vec4 v_color;
flat out vec4 v_flat_color;
noperspective out vec4 v_color_over_w;
noperspective out float v_inv_w;
smooth out vec3 v_normal;
smooth out vec3 v_eye;
noperspective out vec3 v_normal_over_w;
noperspective out vec3 v_eye_over_w;
smooth out vec2 v_texcoord;
noperspective out vec2 v_texcoord_over_w;
void main() {
  gl_Position = a_position;
  v_color = a_color;
  v_flat_color = a_color;
  v_color_over_w = a_color_over_w;
  v_inv_w = a_inv_w;
  v_normal = a_normal;
  v_eye = a_eye;
  v_normal_over_w = a_normal_over_w;
  v_eye_over_w = a_eye_over_w;
  v_texcoord = a_texcoord;
  v_texcoord_over_w = a_texcoord_over_w;
}
)";

// Compiled four times: with and without PHONG (Phong draws) and TEXTURED
// (textured draws). llvmpipe runs both sides of a branch on a uniform under
// its execution mask, so one shader with the per-fragment lighting in it
// would pay for the lighting loop on every fragment of every draw
// (measured: the fill-bound benchmark frame 47 times slower); likewise the
// texture fetch. The program without either is the untextured shader
// unchanged (its fragments' colours bit for bit).
const char* const kFragmentShaderBody = R"(
uniform int u_mode;
smooth in vec4 v_color;
flat in vec4 v_flat_color;
noperspective in vec4 v_color_over_w;
noperspective in float v_inv_w;
smooth in vec3 v_normal;
smooth in vec3 v_eye;
noperspective in vec3 v_normal_over_w;
noperspective in vec3 v_eye_over_w;
#ifdef PHONG
// Phong: the scene's lights in eye space (u_light_vector.w: 1 point, 0
// directional; u_light_attenuation: constant, linear, quadratic) and the
// draw's material (u_emission.a unused, u_diffuse.a the colour's alpha).
uniform int u_light_count;
uniform vec4 u_light_vector[8];
uniform vec4 u_light_ambient[8];
uniform vec4 u_light_diffuse[8];
uniform vec4 u_light_specular[8];
uniform vec4 u_light_attenuation[8];
uniform vec4 u_global_ambient;
uniform vec4 u_emission;
uniform vec4 u_ambient;
uniform vec4 u_diffuse;
uniform vec4 u_specular;
uniform float u_shininess;
// The spec's normalize: v unchanged when its squared length is not > 0.
vec3 spec_normalize(vec3 v) {
  float len2 = dot(v, v);
  return len2 > 0.0 ? v * (1.0 / sqrt(len2)) : v;
}
// Section 2's equation, evaluated at the fragment (section 9b).
vec4 phong(vec3 normal, vec3 e) {
  vec3 n = spec_normalize(normal);
  vec3 c = u_emission.rgb + u_global_ambient.rgb * u_ambient.rgb;
  for (int i = 0; i < u_light_count; ++i) {
    vec3 L = u_light_vector[i].xyz;
    float att = 1.0;
    if (u_light_vector[i].w > 0.5) {
      vec3 d = u_light_vector[i].xyz - e;
      float d2 = dot(d, d);
      float dist = sqrt(d2);
      L = dist > 0.0 ? d * (1.0 / dist) : d;
      vec3 k = u_light_attenuation[i].xyz;
      att = 1.0 / (k.x + k.y * dist + k.z * d2);
    }
    float ndotl = max(dot(n, L), 0.0);
    float spec = 0.0;
    if (ndotl > 0.0) {
      vec3 H = spec_normalize(L + vec3(0.0, 0.0, 1.0));
      // C's pow(0, 0) is 1; GLSL leaves it undefined.
      float x = max(dot(n, H), 0.0);
      spec = u_shininess == 0.0 ? 1.0 : pow(x, u_shininess);
    }
    c += att * (u_light_ambient[i].rgb * u_ambient.rgb + u_light_diffuse[i].rgb * u_diffuse.rgb * ndotl
                + u_light_specular[i].rgb * u_specular.rgb * spec);
  }
  return vec4(c, u_diffuse.a);
}
#endif
#ifdef TEXTURED
// Texturing (spec section 9c): the draw's texture on unit 0; its base
// format (kBase*: 0 alpha, 1 luminance, 2 luminance_alpha, 3 intensity,
// 4 rgb, 5 rgba); the environment mode (shader_env_mode: 0 modulate,
// 1 replace, 2 decal, 3 blend, 4 add) and colour. The texture coordinate
// is interpolated as the colour is whatever the shading (flat shading is
// the colour's alone): u_texcoord_window, (s, t)/w over 1/w; otherwise
// OpenGL's perspective correction.
uniform sampler2D u_texture;
uniform int u_base_format;
uniform int u_env_mode;
uniform vec4 u_env_color;
uniform bool u_texcoord_window;
smooth in vec2 v_texcoord;
noperspective in vec2 v_texcoord_over_w;
// GL 1.5's texture environment, tables 3.22 and 3.23: the fragment colour
// cf and the filtered texel ct. The swizzles give ct GL's expansion of the
// base format, but the table still depends on it: a channel the format
// lacks leaves cf's, and DECAL is defined for RGB and RGBA only (others
// leave the fragment unchanged).
vec4 texture_env(vec4 cf, vec4 ct) {
  bool has_color = u_base_format != 0;
  bool has_alpha = u_base_format == 0 || u_base_format == 2 || u_base_format == 3 ||
                   u_base_format == 5;
  bool intensity = u_base_format == 3;
  vec4 c = cf;
  if (u_env_mode == 0) {
    if (has_color) c.rgb = cf.rgb * ct.rgb;
    if (has_alpha) c.a = cf.a * ct.a;
  } else if (u_env_mode == 1) {
    if (has_color) c.rgb = ct.rgb;
    if (has_alpha) c.a = ct.a;
  } else if (u_env_mode == 2) {
    if (u_base_format == 4) {
      c.rgb = ct.rgb;
    } else if (u_base_format == 5) {
      c.rgb = cf.rgb * (1.0 - ct.a) + ct.rgb * ct.a;
    }
  } else if (u_env_mode == 3) {
    if (has_color) c.rgb = cf.rgb * (1.0 - ct.rgb) + u_env_color.rgb * ct.rgb;
    if (intensity) {
      c.a = cf.a * (1.0 - ct.a) + u_env_color.a * ct.a;
    } else if (has_alpha) {
      c.a = cf.a * ct.a;
    }
  } else {
    if (has_color) c.rgb = cf.rgb + ct.rgb;
    if (intensity) {
      c.a = cf.a + ct.a;
    } else if (has_alpha) {
      c.a = cf.a * ct.a;
    }
  }
  return c;
}
#endif
// The spec's clamp01 (NaN -> 0).
vec4 clamp01(vec4 c) {
  return vec4(c.r > 0.0 ? min(c.r, 1.0) : 0.0, c.g > 0.0 ? min(c.g, 1.0) : 0.0,
              c.b > 0.0 ? min(c.b, 1.0) : 0.0, c.a > 0.0 ? min(c.a, 1.0) : 0.0);
}
out vec4 o_color;
void main() {
  vec4 c;
  if (u_mode == 0) {
    c = v_color_over_w / v_inv_w;
  } else if (u_mode == 1) {
    c = v_color;
#ifdef PHONG
  } else if (u_mode == 3) {
    c = phong(v_normal_over_w / v_inv_w, v_eye_over_w / v_inv_w);
  } else if (u_mode == 4) {
    c = phong(v_normal, v_eye);
#endif
  } else {
    c = v_flat_color;
  }
#ifdef TEXTURED
  // The environment takes the colour clamped, as GL's fixed function does
  // (and the spec's interpolated colour is).
  vec2 st = u_texcoord_window ? v_texcoord_over_w / v_inv_w : v_texcoord;
  c = texture_env(clamp01(c), texture(u_texture, st));
#endif
  // Clamped; a float buffer keeps the clamped value.
  o_color = clamp01(c);
}
)";

// Texturing's constants as the fragment shader takes them: the base format
// (u_base_format) and the environment mode (u_env_mode).
constexpr int kBaseAlpha = 0, kBaseLuminance = 1, kBaseLuminanceAlpha = 2, kBaseIntensity = 3,
              kBaseRgb = 4, kBaseRgba = 5;

int shader_env_mode(TextureEnvMode m) {
  switch (m) {
    case TextureEnvMode::modulate:
      return 0;
    case TextureEnvMode::replace:
      return 1;
    case TextureEnvMode::decal:
      return 2;
    case TextureEnvMode::blend:
      return 3;
    case TextureEnvMode::add:
      return 4;
  }
  return 0;
}

// A scene texture format in a core profile, which has no ALPHA, LUMINANCE
// or INTENSITY textures: one- and two-channel formats are R8 and RG8 with
// a swizzle giving GL's expansion of the base format (GL 1.5, table 3.15).
// The 16-bit formats are stored little-endian with red in the high bits,
// which is GL's packed UNSIGNED_SHORT_5_6_5 and _4_4_4_4 on this
// (little-endian) host.
struct GlTextureFormat {
  GLint internal;
  GLenum format, type;
  GLint swizzle[4];
  int base;  // kBase*
};

GlTextureFormat gl_texture_format(TextureFormat f) {
  switch (f) {
    case TextureFormat::alpha8:
      return {GL_R8, GL_RED, GL_UNSIGNED_BYTE, {GL_ZERO, GL_ZERO, GL_ZERO, GL_RED}, kBaseAlpha};
    case TextureFormat::luminance8:
      return {GL_R8, GL_RED, GL_UNSIGNED_BYTE, {GL_RED, GL_RED, GL_RED, GL_ONE}, kBaseLuminance};
    case TextureFormat::luminance_alpha8:
      return {
          GL_RG8, GL_RG, GL_UNSIGNED_BYTE, {GL_RED, GL_RED, GL_RED, GL_GREEN}, kBaseLuminanceAlpha};
    case TextureFormat::intensity8:
      return {GL_R8, GL_RED, GL_UNSIGNED_BYTE, {GL_RED, GL_RED, GL_RED, GL_RED}, kBaseIntensity};
    case TextureFormat::rgb8:
      return {GL_RGB8, GL_RGB, GL_UNSIGNED_BYTE, {GL_RED, GL_GREEN, GL_BLUE, GL_ONE}, kBaseRgb};
    case TextureFormat::rgba8:
      return {
          GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE, {GL_RED, GL_GREEN, GL_BLUE, GL_ALPHA}, kBaseRgba};
    case TextureFormat::rgb565:
      return {GL_RGB565,
              GL_RGB,
              GL_UNSIGNED_SHORT_5_6_5,
              {GL_RED, GL_GREEN, GL_BLUE, GL_ONE},
              kBaseRgb};
    case TextureFormat::rgba4444:
      return {GL_RGBA4,
              GL_RGBA,
              GL_UNSIGNED_SHORT_4_4_4_4,
              {GL_RED, GL_GREEN, GL_BLUE, GL_ALPHA},
              kBaseRgba};
  }
  return {GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE, {GL_RED, GL_GREEN, GL_BLUE, GL_ALPHA}, kBaseRgba};
}

GLint gl_wrap(TextureWrap w) {
  switch (w) {
    case TextureWrap::repeat:
      return GL_REPEAT;
    case TextureWrap::clamp_to_edge:
      return GL_CLAMP_TO_EDGE;
    case TextureWrap::mirrored_repeat:
      return GL_MIRRORED_REPEAT;
    case TextureWrap::clamp:
      break;  // GL_CLAMP: not in a core profile (render() refuses it)
  }
  return GL_CLAMP_TO_EDGE;
}

GLint gl_filter(TextureFilter f) {
  switch (f) {
    case TextureFilter::nearest:
      return GL_NEAREST;
    case TextureFilter::linear:
      return GL_LINEAR;
    case TextureFilter::nearest_mipmap_nearest:
      return GL_NEAREST_MIPMAP_NEAREST;
    case TextureFilter::linear_mipmap_nearest:
      return GL_LINEAR_MIPMAP_NEAREST;
    case TextureFilter::nearest_mipmap_linear:
      return GL_NEAREST_MIPMAP_LINEAR;
    case TextureFilter::linear_mipmap_linear:
      return GL_LINEAR_MIPMAP_LINEAR;
  }
  return GL_LINEAR;
}

// One vertex as OpenGL receives it.
struct GlVertex {
  float position[4];
  float color[4];
  float color_over_w[4];
  float inv_w;
  // Phong draws (spec section 9b); 0 in others.
  float normal[3];
  float eye[3];
  float normal_over_w[3];
  float eye_over_w[3];
  // Textured draws (spec section 9c); 0 in others.
  float texcoord[2];
  float texcoord_over_w[2];
};

GLenum gl_primitive(PrimitiveType p) {
  switch (p) {
    case PrimitiveType::triangles:
      return GL_TRIANGLES;
    case PrimitiveType::triangle_strip:
      return GL_TRIANGLE_STRIP;
    case PrimitiveType::triangle_fan:
      return GL_TRIANGLE_FAN;
    case PrimitiveType::points:
      return GL_POINTS;
    case PrimitiveType::lines:
      return GL_LINES;
    case PrimitiveType::line_strip:
      return GL_LINE_STRIP;
    case PrimitiveType::line_loop:
      return GL_LINE_LOOP;
  }
  return GL_TRIANGLES;
}

// Line assembly (spec section 3): the vertex slots of each line in API order,
// the second one provoking; a loop's closing line is (n - 1, 0).
std::vector<std::array<uint32_t, 2>> assemble_lines(PrimitiveType type, size_t n) {
  std::vector<std::array<uint32_t, 2>> out;
  if (n < 2) return out;
  const uint32_t last = static_cast<uint32_t>(n - 1);
  if (type == PrimitiveType::lines) {
    for (uint32_t i = 0; i + 1 < n; i += 2) out.push_back({i, i + 1});
  } else {
    for (uint32_t i = 0; i < last; ++i) out.push_back({i, i + 1});
    if (type == PrimitiveType::line_loop) out.push_back({last, 0});
  }
  return out;
}

GLenum gl_compare(CompareFunc f) {
  switch (f) {
    case CompareFunc::never:
      return GL_NEVER;
    case CompareFunc::less:
      return GL_LESS;
    case CompareFunc::equal:
      return GL_EQUAL;
    case CompareFunc::lequal:
      return GL_LEQUAL;
    case CompareFunc::greater:
      return GL_GREATER;
    case CompareFunc::notequal:
      return GL_NOTEQUAL;
    case CompareFunc::gequal:
      return GL_GEQUAL;
    case CompareFunc::always:
      return GL_ALWAYS;
  }
  return GL_LESS;
}

GLenum gl_blend_factor(BlendFactor f) {
  switch (f) {
    case BlendFactor::zero:
      return GL_ZERO;
    case BlendFactor::one:
      return GL_ONE;
    case BlendFactor::src_color:
      return GL_SRC_COLOR;
    case BlendFactor::one_minus_src_color:
      return GL_ONE_MINUS_SRC_COLOR;
    case BlendFactor::dst_color:
      return GL_DST_COLOR;
    case BlendFactor::one_minus_dst_color:
      return GL_ONE_MINUS_DST_COLOR;
    case BlendFactor::src_alpha:
      return GL_SRC_ALPHA;
    case BlendFactor::one_minus_src_alpha:
      return GL_ONE_MINUS_SRC_ALPHA;
    case BlendFactor::dst_alpha:
      return GL_DST_ALPHA;
    case BlendFactor::one_minus_dst_alpha:
      return GL_ONE_MINUS_DST_ALPHA;
    case BlendFactor::src_alpha_saturate:
      return GL_SRC_ALPHA_SATURATE;
  }
  return GL_ONE;
}

GLenum gl_blend_equation(BlendEquation e) {
  switch (e) {
    case BlendEquation::add:
      return GL_FUNC_ADD;
    case BlendEquation::subtract:
      return GL_FUNC_SUBTRACT;
    case BlendEquation::reverse_subtract:
      return GL_FUNC_REVERSE_SUBTRACT;
  }
  return GL_FUNC_ADD;
}

bool finite4(const glm::vec4& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w);
}

}  // namespace

struct GlReference::Impl {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  Gl gl;
  bool gl_loaded = false;  // every entry point resolved
  // The shader programs, indexed by kProgramPhong | kProgramTextured (per-
  // fragment lighting, texturing), each with its u_mode location;
  // `program_in_use` says which one is in use.
  static constexpr int kProgramPhong = 1, kProgramTextured = 2;
  GLuint programs[4] = {0, 0, 0, 0};
  GLint mode_locations[4] = {-1, -1, -1, -1};
  int program_in_use = 0;
  GLuint vao = 0;
  GLuint vertex_buffer = 0;
  GLuint index_buffer = 0;
  int viewport_side = 0;
  std::string renderer, version;

  // Per render. width x height: the render target (the framebuffer's size
  // times `supersample`, spec section 14), which every rule below uses.
  int width = 0, height = 0;
  unsigned samples = 1, supersample = 1;
  int tx = 0, ty = 0;  // window position of NDC (0, 0) in the V x V viewport
  // The draw being prepared: its viewport transform in render-target
  // pixels (the scene's viewport times `supersample`) and depth range.
  golden::ViewportTransform vp;
  ReferenceStats stats;

  // One OpenGL draw call, prepared before the timed part of a render: its
  // vertices shaded by the spec's vertex stage, converted and uploaded.
  // The viewport a batch's vertices are written for.
  enum class Viewport {
    // V x V with NDC (0, 0) at window (tx, ty): snapped window coordinates
    // pass exactly (see the header).
    centered,
    // V x V with NDC (0, 0) at window (0, 0): the viewport transform is a
    // multiplication by the power of two V/2 alone, so any float window
    // coordinate passes exactly (points: the spec's point rule starts from
    // the unsnapped x_w, section 8c).
    origin,
    // The scene's own W x H viewport: OpenGL's clipper decides against the
    // scene's view volume itself (points the spec discards).
    framebuffer,
  };
  struct Batch {
    const RenderState* state = nullptr;
    golden::ViewportTransform vp;  // the draw's (render-target pixels)
    PixelBounds bounds;            // the draw rectangle (spec section 8d)
    bool window_space = true;
    Viewport viewport = Viewport::centered;
    bool flat = false;                // flat colour whatever the state says (points, section 9)
    const Material* phong = nullptr;  // lit per fragment with this material (section 9b)
    const Draw* textured = nullptr;   // the textured draw it belongs to (section 9c), if any
    GLenum primitive = GL_TRIANGLES;
    GLsizei count = 0;
    bool indexed = false;
    GLuint vertex_buffer = 0, index_buffer = 0;
  };
  std::vector<Batch> batches;
  std::vector<GLuint> batch_buffers;           // every buffer object of `batches`
  const Material* m_phong_material = nullptr;  // the draw being prepared's, if Phong
  const Draw* m_textured_draw = nullptr;       // the draw being prepared, if textured
  // The scene's textures as texture objects, one per Scene::textures entry.
  std::vector<GLuint> textures;
  std::vector<TextureFormat> texture_formats;

  // Separate from the constructor so that ~Impl releases what a failed
  // init() had already created.
  void init() {
    // Mesa's software rasterizer, whatever hardware the machine has.
    setenv("LIBGL_ALWAYS_SOFTWARE", "1", 1);
    setenv("GALLIUM_DRIVER", "llvmpipe", 1);

    auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
        eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (get_platform_display == nullptr)
      throw ReferenceError("EGL has no eglGetPlatformDisplayEXT");
    display = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (display == EGL_NO_DISPLAY)
      throw ReferenceError("no EGL surfaceless display (Mesa's EGL missing?)");
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display, &major, &minor)) {
      display = EGL_NO_DISPLAY;  // nothing to terminate
      throw ReferenceError("eglInitialize failed on the surfaceless platform");
    }
    if (!eglBindAPI(EGL_OPENGL_API)) throw ReferenceError("eglBindAPI(EGL_OPENGL_API) failed");

    const EGLint config_attribs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE,
                                     EGL_OPENGL_BIT, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint configs = 0;
    if (!eglChooseConfig(display, config_attribs, &config, 1, &configs) || configs < 1) {
      config = nullptr;  // EGL_NO_CONFIG_KHR: fine for a context used with FBOs only
    }
    const EGLint context_attribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                      4,
                                      EGL_CONTEXT_MINOR_VERSION,
                                      5,
                                      EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                      EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                      EGL_NONE};
    context = eglCreateContext(display, config, EGL_NO_CONTEXT, context_attribs);
    if (context == EGL_NO_CONTEXT) throw ReferenceError("cannot create an OpenGL 4.5 core context");
    if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
      throw ReferenceError("eglMakeCurrent without a surface failed");
    }
    gl.load();
    gl_loaded = true;
    renderer = reinterpret_cast<const char*>(gl.glGetString(GL_RENDERER));
    version = reinterpret_cast<const char*>(gl.glGetString(GL_VERSION));
    if (renderer.find("llvmpipe") == std::string::npos) {
      throw ReferenceError("GL_RENDERER is \"" + renderer + "\", not llvmpipe");
    }

    // The viewport for window-space triangles: the largest power of two the
    // implementation allows, at most 16384 (so x_ndc * V/2 + tx stays exact).
    GLint dims[2] = {0, 0};
    gl.glGetIntegerv(GL_MAX_VIEWPORT_DIMS, dims);
    GLint bounds[2] = {0, 0};
    gl.glGetIntegerv(GL_VIEWPORT_BOUNDS_RANGE, bounds);
    viewport_side = 1;
    const int limit = std::min({dims[0], dims[1], 16384, std::max(0, -bounds[0]) * 2});
    while (viewport_side * 2 <= limit) viewport_side *= 2;
    if (viewport_side < 1024) throw ReferenceError("viewport limits too small for the reference");

    build_program();
    gl.glGenVertexArrays(1, &vao);
    gl.glBindVertexArray(vao);
    gl.glGenBuffers(1, &vertex_buffer);
    gl.glGenBuffers(1, &index_buffer);
    gl.glBindBuffer(GL_ARRAY_BUFFER, vertex_buffer);
    set_attribute_pointers();
    gl.glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, index_buffer);
    check("context set-up");
  }

  // The vertex layout (GlVertex), read from the bound GL_ARRAY_BUFFER.
  void set_attribute_pointers() {
    const GLsizei stride = sizeof(GlVertex);
    gl.glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, stride,
                             reinterpret_cast<const void*>(offsetof(GlVertex, position)));
    gl.glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, stride,
                             reinterpret_cast<const void*>(offsetof(GlVertex, color)));
    gl.glVertexAttribPointer(2, 4, GL_FLOAT, GL_FALSE, stride,
                             reinterpret_cast<const void*>(offsetof(GlVertex, color_over_w)));
    gl.glVertexAttribPointer(3, 1, GL_FLOAT, GL_FALSE, stride,
                             reinterpret_cast<const void*>(offsetof(GlVertex, inv_w)));
    gl.glVertexAttribPointer(4, 3, GL_FLOAT, GL_FALSE, stride,
                             reinterpret_cast<const void*>(offsetof(GlVertex, normal)));
    gl.glVertexAttribPointer(5, 3, GL_FLOAT, GL_FALSE, stride,
                             reinterpret_cast<const void*>(offsetof(GlVertex, eye)));
    gl.glVertexAttribPointer(6, 3, GL_FLOAT, GL_FALSE, stride,
                             reinterpret_cast<const void*>(offsetof(GlVertex, normal_over_w)));
    gl.glVertexAttribPointer(7, 3, GL_FLOAT, GL_FALSE, stride,
                             reinterpret_cast<const void*>(offsetof(GlVertex, eye_over_w)));
    gl.glVertexAttribPointer(8, 2, GL_FLOAT, GL_FALSE, stride,
                             reinterpret_cast<const void*>(offsetof(GlVertex, texcoord)));
    gl.glVertexAttribPointer(9, 2, GL_FLOAT, GL_FALSE, stride,
                             reinterpret_cast<const void*>(offsetof(GlVertex, texcoord_over_w)));
    for (GLuint i = 0; i < 10; ++i) gl.glEnableVertexAttribArray(i);
  }

  ~Impl() {
    if (display != EGL_NO_DISPLAY) {
      if (context != EGL_NO_CONTEXT) {
        if (gl_loaded) {
          gl.glDeleteBuffers(1, &vertex_buffer);
          gl.glDeleteBuffers(1, &index_buffer);
          gl.glDeleteVertexArrays(1, &vao);
          for (const GLuint p : programs) gl.glDeleteProgram(p);
        }
        eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(display, context);
      }
      eglTerminate(display);
    }
  }

  void check(const char* what) {
    const GLenum e = gl.glGetError();
    if (e != GL_NO_ERROR) {
      char buf[96];
      std::snprintf(buf, sizeof buf, "OpenGL error 0x%04x in %s", static_cast<unsigned>(e), what);
      throw ReferenceError(buf);
    }
  }

  GLuint compile(GLenum type, const char* source) {
    const GLuint s = gl.glCreateShader(type);
    gl.glShaderSource(s, 1, &source, nullptr);
    gl.glCompileShader(s);
    GLint ok = 0;
    gl.glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
      char log[2048] = {0};
      gl.glGetShaderInfoLog(s, sizeof log, nullptr, log);
      throw ReferenceError(std::string("shader compilation failed: ") + log);
    }
    return s;
  }

  GLuint link_program(int variant) {
    const GLuint vs = compile(GL_VERTEX_SHADER, kVertexShader);
    const std::string fragment =
        std::string("#version 330 core\n") + (variant & kProgramPhong ? "#define PHONG 1\n" : "") +
        (variant & kProgramTextured ? "#define TEXTURED 1\n" : "") + kFragmentShaderBody;
    const GLuint fs = compile(GL_FRAGMENT_SHADER, fragment.c_str());
    const GLuint program = gl.glCreateProgram();
    gl.glAttachShader(program, vs);
    gl.glAttachShader(program, fs);
    gl.glLinkProgram(program);
    gl.glDeleteShader(vs);
    gl.glDeleteShader(fs);
    GLint ok = 0;
    gl.glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
      char log[2048] = {0};
      gl.glGetProgramInfoLog(program, sizeof log, nullptr, log);
      throw ReferenceError(std::string("program link failed: ") + log);
    }
    return program;
  }

  void build_program() {
    for (int variant = 0; variant < 4; ++variant) {
      programs[variant] = link_program(variant);
      mode_locations[variant] = gl.glGetUniformLocation(programs[variant], "u_mode");
    }
    use_program(0);
  }

  void use_program(int variant) {
    if (programs[variant] == 0) return;
    gl.glUseProgram(programs[variant]);
    program_in_use = variant;
  }

  // A uniform of the program in use.
  GLint uniform(const char* name) const {
    return gl.glGetUniformLocation(programs[program_in_use], name);
  }

  // The frame's lights for Phong draws (spec section 9b), eye space, in both
  // Phong programs. render() refuses a Phong draw under more lights than the
  // shader takes.
  void set_lights(const Scene& scene) {
    for (const int variant : {kProgramPhong, kProgramPhong | kProgramTextured}) {
      use_program(variant);  // glUniform sets the program in use
      set_lights_in_use(scene);
    }
    use_program(0);
  }

  void set_lights_in_use(const Scene& scene) {
    const size_t n = std::min(scene.lights.size(), kMaxPhongLights);
    std::vector<glm::vec4> vec(n), amb(n), dif(n), spe(n), att(n);
    for (size_t i = 0; i < n; ++i) {
      const Light& l = scene.lights[i];
      vec[i] = glm::vec4(l.vector, l.type == LightType::point ? 1.0f : 0.0f);
      amb[i] = l.ambient;
      dif[i] = l.diffuse;
      spe[i] = l.specular;
      att[i] = glm::vec4(l.constant_attenuation, l.linear_attenuation, l.quadratic_attenuation, 0);
    }
    const GLsizei count = static_cast<GLsizei>(n);
    gl.glUniform1i(uniform("u_light_count"), count);
    if (n > 0) {
      gl.glUniform4fv(uniform("u_light_vector"), count, &vec[0][0]);
      gl.glUniform4fv(uniform("u_light_ambient"), count, &amb[0][0]);
      gl.glUniform4fv(uniform("u_light_diffuse"), count, &dif[0][0]);
      gl.glUniform4fv(uniform("u_light_specular"), count, &spe[0][0]);
      gl.glUniform4fv(uniform("u_light_attenuation"), count, &att[0][0]);
    }
    gl.glUniform4fv(uniform("u_global_ambient"), 1, &scene.global_ambient[0]);
    check("light uniforms");
  }

  // A vertex the spec leaves unclipped, in window space (see the header).
  // With screen interpolation the spec's varying weight is 1 (section 9), so
  // the noperspective varyings carry the varyings themselves and 1.
  GlVertex window_vertex(const golden::ShadedVertex& v, Interpolation interpolation) const {
    const golden::WindowVertex w = golden::to_window(v, vp, interpolation);
    const double half = viewport_side / 2;
    GlVertex out{};
    // Exact: X/256 - tx is a multiple of 2^-8 below 2^16 in magnitude, and
    // dividing by the power of two V/2 only shifts the exponent.
    out.position[0] = static_cast<float>((w.x / 256.0 - tx) / half);
    out.position[1] = static_cast<float>((w.y / 256.0 - ty) / half);
    out.position[2] = w.z;
    out.position[3] = 1.0f;
    for (int k = 0; k < 4; ++k) {
      out.color[k] = v.color[k];
      out.color_over_w[k] = w.color_over_w[k];
    }
    out.inv_w = w.inv_w;
    for (int k = 0; k < 3; ++k) {
      out.normal_over_w[k] = w.normal_over_w[k];
      out.eye_over_w[k] = w.eye_over_w[k];
    }
    for (int k = 0; k < 2; ++k) {
      out.texcoord[k] = v.texcoord[k];
      out.texcoord_over_w[k] = w.texcoord_over_w[k];
    }
    return out;
  }

  // A vertex of a triangle the spec clips, in clip space rescaled so that
  // OpenGL's divide and V x V viewport give the spec's window coordinates
  // (up to rounding), x_w = (x/w + 1) * Vw/2 + Vx for the draw's viewport,
  // and its [0, w] z, through glDepthRange(near, far), the spec's z_w. The
  // varyings also go in the noperspective varyings with 1/w = 1, which
  // screen interpolation reads (set_mode): OpenGL's clipper then gives a cut
  // the varyings linear in window space (llvmpipe: t measured on the
  // projected x or y), and its rasterizer interpolates them without
  // perspective.
  GlVertex clip_vertex(const golden::ShadedVertex& v) const {
    const double half = viewport_side / 2;
    const double x = v.clip.x, y = v.clip.y, z = v.clip.z, w = v.clip.w;
    const double hw = vp.rect.width / 2.0, hh = vp.rect.height / 2.0;
    GlVertex out{};
    out.position[0] = static_cast<float>(x * hw / half + w * (hw + vp.rect.x - tx) / half);
    out.position[1] = static_cast<float>(y * hh / half + w * (hh + vp.rect.y - ty) / half);
    out.position[2] = static_cast<float>((z + w) * 0.5);
    out.position[3] = v.clip.w;
    for (int k = 0; k < 4; ++k) {
      out.color[k] = v.color[k];
      out.color_over_w[k] = v.color[k];
    }
    out.inv_w = 1.0f;
    for (int k = 0; k < 3; ++k) {
      out.normal[k] = v.normal[k];
      out.eye[k] = v.eye[k];
      out.normal_over_w[k] = v.normal[k];
      out.eye_over_w[k] = v.eye[k];
    }
    for (int k = 0; k < 2; ++k) {
      out.texcoord[k] = v.texcoord[k];
      out.texcoord_over_w[k] = v.texcoord[k];
    }
    return out;
  }

  // A point the spec keeps (section 4c), for the `origin` viewport: the
  // spec's float window coordinates (section 5, unsnapped: the point rule of
  // section 8c rounds x_w itself) divided by the power of two V/2, exact.
  GlVertex window_point_vertex(const golden::ShadedVertex& v) const {
    const golden::WindowVertex w = golden::to_window(v, vp);
    // The spec's float x_w, y_w before the snap.
    const glm::vec2 xy = golden::window_xy(v, vp.rect);
    const float half = static_cast<float>(viewport_side / 2);
    GlVertex out{};
    out.position[0] = xy.x / half;
    out.position[1] = xy.y / half;
    out.position[2] = w.z;
    out.position[3] = 1.0f;
    for (int k = 0; k < 4; ++k) out.color[k] = v.color[k];
    out.inv_w = 1.0f;
    // The spec's point samples its vertex's (s, t) everywhere (no point
    // sprites): OpenGL interpolates a constant over the point.
    for (int k = 0; k < 2; ++k) {
      out.texcoord[k] = v.texcoord[k];
      out.texcoord_over_w[k] = v.texcoord[k];
    }
    return out;
  }

  // A point the spec discards, for the `framebuffer` viewport (the draw's
  // own): plain clip coordinates (depth mapped to GL_ZERO_TO_ONE), so
  // OpenGL's own clipper must discard it too.
  static GlVertex framebuffer_clip_vertex(const golden::ShadedVertex& v) {
    GlVertex out{};
    out.position[0] = v.clip.x;
    out.position[1] = v.clip.y;
    out.position[2] = (v.clip.z + v.clip.w) * 0.5f;
    out.position[3] = v.clip.w;
    for (int k = 0; k < 4; ++k) out.color[k] = v.color[k];
    out.inv_w = 1.0f;
    // The spec's point samples its vertex's (s, t) everywhere (no point
    // sprites): OpenGL interpolates a constant over the point.
    for (int k = 0; k < 2; ++k) {
      out.texcoord[k] = v.texcoord[k];
      out.texcoord_over_w[k] = v.texcoord[k];
    }
    return out;
  }

  // A draw's state with its viewport and scissor in render-target pixels
  // (times `supersample`, as the spec's section 14 says).
  RenderState scaled_state(const RenderState& st) const {
    RenderState s = st;
    const int k = static_cast<int>(supersample);
    if (s.viewport) s.viewport = scaled(*s.viewport, k);
    if (s.scissor) s.scissor = scaled(*s.scissor, k);
    return s;
  }

  bool beyond_viewport(const GlVertex& v) const {
    return std::fabs(v.position[0]) > 1.0f || std::fabs(v.position[1]) > 1.0f;
  }

  void apply_state(const RenderState& st) {
    if (st.cull == CullMode::none) {
      gl.glDisable(GL_CULL_FACE);
    } else {
      gl.glEnable(GL_CULL_FACE);
      gl.glCullFace(st.cull == CullMode::back ? GL_BACK : GL_FRONT);
    }
    gl.glFrontFace(st.front_face == FrontFace::ccw ? GL_CCW : GL_CW);
    if (st.depth_test) {
      gl.glEnable(GL_DEPTH_TEST);
      gl.glDepthFunc(gl_compare(st.depth_func));
    } else {
      gl.glDisable(GL_DEPTH_TEST);  // GL: no test and no depth writes
    }
    gl.glDepthMask(st.depth_write ? GL_TRUE : GL_FALSE);
    if (st.offset_factor != 0.0f || st.offset_units != 0.0f) {
      gl.glEnable(GL_POLYGON_OFFSET_FILL);
      gl.glPolygonOffset(st.offset_factor, st.offset_units);
    } else {
      gl.glDisable(GL_POLYGON_OFFSET_FILL);
    }
    if (st.blend) {
      gl.glEnable(GL_BLEND);
      gl.glBlendFunc(gl_blend_factor(st.blend_src), gl_blend_factor(st.blend_dst));
      gl.glBlendEquation(gl_blend_equation(st.blend_equation));
    } else {
      gl.glDisable(GL_BLEND);
    }
    gl.glColorMask(st.color_mask[0], st.color_mask[1], st.color_mask[2], st.color_mask[3]);
    gl.glProvokingVertex(st.provoking_vertex == ProvokingVertex::first ? GL_FIRST_VERTEX_CONVENTION
                                                                       : GL_LAST_VERTEX_CONVENTION);
    // Only triangles look at the polygon mode. The default EGL core context
    // is not forward-compatible, so llvmpipe accepts wide lines (up to 255).
    gl.glPolygonMode(GL_FRONT_AND_BACK, st.polygon_mode == PolygonMode::line    ? GL_LINE
                                        : st.polygon_mode == PolygonMode::point ? GL_POINT
                                                                                : GL_FILL);
    // Supersampling (spec section 14): widths and sizes times k, a float
    // product, so that they keep their size in output pixels.
    gl.glLineWidth(st.line_width * static_cast<float>(supersample));
    gl.glPointSize(st.point_size * static_cast<float>(supersample));
    check("render state");
  }

  void set_mode(bool window_space, Shading shading, Interpolation interpolation,
                const Material* phong, const Draw* textured) {
    const bool noperspective = window_space || interpolation == Interpolation::screen;
    int mode = shading == Shading::flat ? kModeFlat
                                        : (noperspective ? kModeWindowGouraud : kModeClipGouraud);
    const bool lit_per_fragment = mode != kModeFlat && phong != nullptr;
    const int variant =
        (lit_per_fragment ? kProgramPhong : 0) | (textured != nullptr ? kProgramTextured : 0);
    if (variant != program_in_use) use_program(variant);
    if (textured != nullptr) {
      const size_t t = static_cast<size_t>(textured->texture);
      gl.glActiveTexture(GL_TEXTURE0);
      gl.glBindTexture(GL_TEXTURE_2D, textures[t]);
      gl.glUniform1i(uniform("u_texture"), 0);
      gl.glUniform1i(uniform("u_base_format"), gl_texture_format(texture_formats[t]).base);
      gl.glUniform1i(uniform("u_env_mode"), shader_env_mode(textured->texture_env.mode));
      gl.glUniform4fv(uniform("u_env_color"), 1, &textured->texture_env.color[0]);
      // The texture coordinate goes the colour's way (window_vertex,
      // clip_vertex), also when the colour is flat.
      gl.glUniform1i(uniform("u_texcoord_window"), noperspective ? 1 : 0);
    }
    if (lit_per_fragment) {
      mode = noperspective ? kModeWindowPhong : kModeClipPhong;
      gl.glUniform4fv(uniform("u_emission"), 1, &phong->emission[0]);
      gl.glUniform4fv(uniform("u_ambient"), 1, &phong->ambient[0]);
      gl.glUniform4fv(uniform("u_diffuse"), 1, &phong->diffuse[0]);
      gl.glUniform4fv(uniform("u_specular"), 1, &phong->specular[0]);
      gl.glUniform1f(uniform("u_shininess"), phong->shininess);
    }
    gl.glUniform1i(mode_locations[program_in_use], mode);
    // Window-space triangles are not clipped in z (the spec does not clip
    // them); clip-space ones are, by OpenGL's near and far planes.
    if (window_space) {
      gl.glEnable(GL_DEPTH_CLAMP);
    } else {
      gl.glDisable(GL_DEPTH_CLAMP);
    }
  }

  // Every scene texture as a texture object with all of its levels (level 0
  // alone for a texture without mipmaps; GL_TEXTURE_MAX_LEVEL, the last
  // level, makes it complete either way), with its sampler's wrap modes,
  // filters, level-of-detail bias and clamps. The stored rows run from
  // t = 0 up, which is the order glTexImage2D takes them in: no flip.
  void upload_textures(const Scene& scene) {
    gl.glActiveTexture(GL_TEXTURE0);
    gl.glPixelStorei(GL_UNPACK_ALIGNMENT, 1);  // rows tightly packed
    for (const Texture& t : scene.textures) {
      const GlTextureFormat f = gl_texture_format(t.format);
      GLuint texture = 0;
      gl.glGenTextures(1, &texture);
      textures.push_back(texture);
      texture_formats.push_back(t.format);
      gl.glBindTexture(GL_TEXTURE_2D, texture);
      for (size_t l = 0; l < t.levels.size(); ++l) {
        const TextureImage& level = t.levels[l];
        gl.glTexImage2D(GL_TEXTURE_2D, static_cast<GLint>(l), f.internal, level.width,
                        level.height, 0, f.format, f.type, level.texels.data());
      }
      gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_BASE_LEVEL, 0);
      gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL,
                         static_cast<GLint>(t.levels.size()) - 1);
      gl.glTexParameteriv(GL_TEXTURE_2D, GL_TEXTURE_SWIZZLE_RGBA, f.swizzle);
      gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, gl_wrap(t.sampler.wrap_s));
      gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, gl_wrap(t.sampler.wrap_t));
      gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, gl_filter(t.sampler.min_filter));
      gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, gl_filter(t.sampler.mag_filter));
      gl.glTexParameterf(GL_TEXTURE_2D, GL_TEXTURE_LOD_BIAS, t.sampler.lod_bias);
      gl.glTexParameterf(GL_TEXTURE_2D, GL_TEXTURE_MIN_LOD, t.sampler.min_lod);
      gl.glTexParameterf(GL_TEXTURE_2D, GL_TEXTURE_MAX_LOD, t.sampler.max_lod);
      check("texture upload");
    }
    gl.glBindTexture(GL_TEXTURE_2D, 0);
  }

  // A new buffer object holding `bytes` bytes of `data`, owned by the render.
  GLuint upload(GLenum target, const void* data, size_t bytes) {
    GLuint buffer = 0;
    gl.glGenBuffers(1, &buffer);
    batch_buffers.push_back(buffer);
    gl.glBindBuffer(target, buffer);
    gl.glBufferData(target, static_cast<GLsizeiptr>(bytes), data, GL_STATIC_DRAW);
    return buffer;
  }

  void add_batch(const RenderState& state, bool window_space, GLenum primitive,
                 const std::vector<GlVertex>& vertices, GLsizei count,
                 const std::vector<uint32_t>* indices, Viewport viewport = Viewport::centered,
                 bool flat = false) {
    Batch b;
    b.state = &state;
    b.vp = vp;
    b.bounds = draw_bounds(scaled_state(state), width, height);
    b.window_space = window_space;
    b.viewport = viewport;
    b.flat = flat;
    b.phong = m_phong_material;
    b.textured = m_textured_draw;
    b.primitive = primitive;
    b.count = count;
    b.vertex_buffer = upload(GL_ARRAY_BUFFER, vertices.data(), vertices.size() * sizeof(GlVertex));
    if (indices != nullptr) {
      b.indexed = true;
      b.index_buffer =
          upload(GL_ELEMENT_ARRAY_BUFFER, indices->data(), indices->size() * sizeof(uint32_t));
    }
    batches.push_back(b);
  }

  void draw_batch(const Batch& b) {
    const int half = viewport_side / 2;
    switch (b.viewport) {
      case Viewport::centered:
        gl.glViewport(tx - half, ty - half, viewport_side, viewport_side);
        break;
      case Viewport::origin:
        gl.glViewport(-half, -half, viewport_side, viewport_side);
        break;
      case Viewport::framebuffer:
        gl.glViewport(b.vp.rect.x, b.vp.rect.y, b.vp.rect.width, b.vp.rect.height);
        break;
    }
    // Window-space vertices carry the spec's z_w, already in the depth
    // range; clip-space ones get it from OpenGL's viewport transform.
    if (b.window_space) {
      gl.glDepthRange(0.0, 1.0);
    } else {
      gl.glDepthRange(b.vp.near, b.vp.far);
    }
    // The draw rectangle: OpenGL clips to its own viewport, which for
    // window-space vertices is the large V x V one, so the scene's viewport
    // and scissor become one scissor rectangle (a per-pixel test, as the
    // spec's).
    const PixelBounds& r = b.bounds;
    if (r == PixelBounds{0, 0, width - 1, height - 1}) {
      gl.glDisable(GL_SCISSOR_TEST);
    } else {
      gl.glEnable(GL_SCISSOR_TEST);
      gl.glScissor(r.x0, r.y0, std::max(0, r.x1 - r.x0 + 1), std::max(0, r.y1 - r.y0 + 1));
    }
    apply_state(*b.state);
    set_mode(b.window_space, b.flat ? Shading::flat : b.state->shading, b.state->interpolation,
             b.phong, b.textured);
    gl.glBindBuffer(GL_ARRAY_BUFFER, b.vertex_buffer);
    set_attribute_pointers();
    if (b.indexed) {
      gl.glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, b.index_buffer);
      gl.glDrawElements(b.primitive, b.count, GL_UNSIGNED_INT, nullptr);
    } else {
      gl.glDrawArrays(b.primitive, 0, b.count);
    }
    check("draw");
  }

  // The vertex behind slot `slot` of the draw, or -1 when the slot's index
  // is out of range or its clip coordinates are not finite (an invalid
  // primitive, section 3).
  static int64_t valid_vertex(const Draw& draw, const std::vector<golden::ShadedVertex>& shaded,
                              uint32_t slot) {
    const uint32_t vi = draw.indices.empty() ? slot : draw.indices[slot];
    if (vi >= shaded.size() || !finite4(shaded[vi].clip)) return -1;
    return vi;
  }

  // Points (sections 4c, 8c). A point the spec keeps is handed over in
  // window space through the `origin` viewport, so llvmpipe's point rule
  // starts from the spec's float x_w, y_w; one it discards is handed over in
  // clip space through the scene's own viewport, where OpenGL must discard
  // it as well (llvmpipe drops a point whose centre is outside the
  // viewport). Flat colour: a point takes its vertex's colour (section 9).
  void prepare_points(const Draw& draw, const std::vector<golden::ShadedVertex>& shaded) {
    std::vector<GlVertex> kept, discarded;
    for (uint32_t slot = 0; slot < draw.vertex_count(); ++slot) {
      ++stats.points;
      const int64_t vi = valid_vertex(draw, shaded, slot);
      if (vi < 0) {
        ++stats.points_invalid;
        continue;
      }
      const glm::vec4& c = shaded[vi].clip;
      const bool inside = c.w - golden::kMinClipW >= 0.0f && c.x + c.w >= 0.0f &&
                          c.w - c.x >= 0.0f && c.y + c.w >= 0.0f && c.w - c.y >= 0.0f &&
                          c.z + c.w >= 0.0f && c.w - c.z >= 0.0f;
      if (inside) {
        ++stats.points_exact;
        kept.push_back(window_point_vertex(shaded[vi]));
      } else {
        ++stats.points_discarded;
        discarded.push_back(framebuffer_clip_vertex(shaded[vi]));
      }
    }
    // Two batches, each in API order: the kept points, then the discarded
    // ones (which draw nothing unless OpenGL disagrees about discarding).
    if (!kept.empty()) {
      add_batch(draw.state, true, GL_POINTS, kept, static_cast<GLsizei>(kept.size()), nullptr,
                Viewport::origin, true);
    }
    if (!discarded.empty()) {
      add_batch(draw.state, false, GL_POINTS, discarded, static_cast<GLsizei>(discarded.size()),
                nullptr, Viewport::framebuffer, true);
    }
    check("point upload");
  }

  // Lines (sections 3, 4b, 8b). A line the spec does not clip (both ends
  // inside all seven planes) is handed over in window space like a
  // triangle; one it clips in clip space, and OpenGL clips it. When every
  // line of the draw is unclipped, the draw goes over natively
  // (GL_LINE_STRIP, GL_LINE_LOOP, its index list) so that OpenGL assembles
  // the lines itself; otherwise line by line as GL_LINES, each line's
  // vertices in the spec's order (a loop's closing line ends at vertex 0),
  // so glProvokingVertex picks the spec's provoking vertex either way.
  void prepare_lines(const Draw& draw, const std::vector<golden::ShadedVertex>& shaded,
                     const golden::GuardBand& gb) {
    enum class Kind { invalid, window, clip };
    const auto lines = assemble_lines(draw.primitive, draw.vertex_count());
    std::vector<Kind> kinds(lines.size());
    std::vector<std::array<uint32_t, 2>> ids(lines.size());
    bool all_window = true;
    for (size_t l = 0; l < lines.size(); ++l) {
      Kind kind = Kind::window;
      for (int k = 0; k < 2 && kind == Kind::window; ++k) {
        const int64_t vi = valid_vertex(draw, shaded, lines[l][k]);
        if (vi < 0) {
          kind = Kind::invalid;
        } else {
          ids[l][k] = static_cast<uint32_t>(vi);
        }
      }
      for (int plane = 0; plane < golden::kClipPlaneCount && kind == Kind::window; ++plane) {
        for (int k = 0; k < 2; ++k) {
          if (!(golden::clip_distance(plane, shaded[ids[l][k]].clip, gb) >= 0.0f)) {
            kind = Kind::clip;
            break;
          }
        }
      }
      kinds[l] = kind;
      all_window = all_window && kind == Kind::window;
      ++stats.lines;
      if (kind == Kind::invalid) ++stats.lines_invalid;
      if (kind == Kind::window) ++stats.lines_exact;
      if (kind == Kind::clip) ++stats.lines_clipped;
    }
    if (lines.empty()) return;
    if (all_window) {
      ++stats.native_draws;
      std::vector<GlVertex> vertices(shaded.size(), GlVertex{});
      for (const auto& pair : ids) {
        for (uint32_t vi : pair) vertices[vi] = window_vertex(shaded[vi], draw.state.interpolation);
      }
      for (const auto& pair : ids) {
        if (beyond_viewport(vertices[pair[0]]) || beyond_viewport(vertices[pair[1]])) {
          ++stats.lines_beyond_viewport;
        }
      }
      add_batch(draw.state, true, gl_primitive(draw.primitive), vertices,
                static_cast<GLsizei>(draw.vertex_count()),
                draw.indices.empty() ? nullptr : &draw.indices);
      check("native line upload");
      return;
    }
    ++stats.expanded_draws;
    size_t l = 0;
    while (l < lines.size()) {
      if (kinds[l] == Kind::invalid) {
        ++l;
        continue;
      }
      const Kind kind = kinds[l];
      std::vector<GlVertex> vertices;
      for (; l < lines.size() && kinds[l] == kind; ++l) {
        for (int k = 0; k < 2; ++k) {
          const golden::ShadedVertex& v = shaded[ids[l][k]];
          vertices.push_back(kind == Kind::window ? window_vertex(v, draw.state.interpolation)
                                                  : clip_vertex(v));
        }
      }
      add_batch(draw.state, kind == Kind::window, GL_LINES, vertices,
                static_cast<GLsizei>(vertices.size()), nullptr);
      check("expanded line upload");
    }
  }

  // The untimed part of a draw: the spec's vertex stage, the classification
  // of its primitives, and the upload of what OpenGL draws (add_batch).
  // Triangles in polygon mode line or point are classified and handed over
  // as filled ones are; OpenGL's glPolygonMode (apply_state) then culls and
  // draws their edges or vertices, with the edge flags of its own clipper.
  void prepare_draw(const Scene& scene, const Draw& draw) {
    // Phong draws: every batch of the draw carries its material (points are
    // flat and ignore it).
    m_phong_material = golden::lit_per_pixel(draw) ? &draw.material : nullptr;
    m_textured_draw = draw.texture >= 0 ? &draw : nullptr;
    std::vector<golden::ShadedVertex> shaded(draw.positions.size());
    for (uint32_t i = 0; i < shaded.size(); ++i) shaded[i] = golden::shade_vertex(scene, draw, i);
    const RenderState st = scaled_state(draw.state);
    vp = golden::ViewportTransform{viewport_of(st, width, height), st.depth_near, st.depth_far};
    const golden::GuardBand gb = golden::guard_band_for(vp.rect);
    switch (primitive_kind_of(draw.primitive)) {
      case PrimitiveKind::point:
        prepare_points(draw, shaded);
        return;
      case PrimitiveKind::line:
        prepare_lines(draw, shaded, gb);
        return;
      case PrimitiveKind::triangle:
        break;
    }
    if (draw.state.polygon_mode != PolygonMode::fill) ++stats.unfilled_draws;

    // Classify every assembled triangle: invalid, unclipped by the spec
    // (window space), or clipped by the spec (clip space).
    enum class Kind { invalid, window, clip };
    const auto triangles = golden::assemble_triangles(draw.primitive, draw.vertex_count());
    std::vector<Kind> kinds(triangles.size());
    std::vector<std::array<uint32_t, 3>> vertex_ids(triangles.size());
    bool all_window = true;
    for (size_t t = 0; t < triangles.size(); ++t) {
      Kind kind = Kind::window;
      for (int k = 0; k < 3; ++k) {
        const uint32_t vi = draw.indices.empty() ? triangles[t][k] : draw.indices[triangles[t][k]];
        vertex_ids[t][k] = vi;
        if (vi >= shaded.size() || !finite4(shaded[vi].clip)) {
          kind = Kind::invalid;
          break;
        }
      }
      if (kind == Kind::window) {
        for (int plane = 0; plane < golden::kClipPlaneCount && kind == Kind::window; ++plane) {
          for (int k = 0; k < 3; ++k) {
            if (!(golden::clip_distance(plane, shaded[vertex_ids[t][k]].clip, gb) >= 0.0f)) {
              kind = Kind::clip;
              break;
            }
          }
        }
      }
      kinds[t] = kind;
      all_window = all_window && kind == Kind::window;
      ++stats.triangles;
      if (kind == Kind::invalid) ++stats.triangles_invalid;
      if (kind == Kind::window) ++stats.triangles_exact;
      if (kind == Kind::clip) ++stats.triangles_clipped;
    }
    if (triangles.empty()) return;

    if (all_window) {
      // Native: the draw's own primitive type and index list, so OpenGL does
      // primitive assembly (strip order, fan, provoking vertex) itself.
      ++stats.native_draws;
      std::vector<char> used(shaded.size(), 0);
      for (const auto& ids : vertex_ids) {
        for (uint32_t vi : ids) used[vi] = 1;
      }
      std::vector<GlVertex> vertices(shaded.size(), GlVertex{});
      for (size_t i = 0; i < shaded.size(); ++i) {
        if (used[i]) vertices[i] = window_vertex(shaded[i], draw.state.interpolation);
      }
      for (const auto& ids : vertex_ids) {
        if (beyond_viewport(vertices[ids[0]]) || beyond_viewport(vertices[ids[1]]) ||
            beyond_viewport(vertices[ids[2]])) {
          ++stats.triangles_beyond_viewport;
        }
      }
      add_batch(draw.state, true, gl_primitive(draw.primitive), vertices,
                static_cast<GLsizei>(draw.vertex_count()),
                draw.indices.empty() ? nullptr : &draw.indices);
      check("native draw upload");
      return;
    }

    // Expanded: runs of consecutive triangles of one kind as GL_TRIANGLES,
    // each triangle's vertices in assembled order, rotated (winding kept) so
    // that the spec's provoking vertex (golden::provoking_position) is where
    // GL_TRIANGLES takes it: third, or first under the first-vertex
    // convention.
    ++stats.expanded_draws;
    size_t t = 0;
    while (t < triangles.size()) {
      if (kinds[t] == Kind::invalid) {
        ++t;
        continue;
      }
      const Kind kind = kinds[t];
      std::vector<GlVertex> vertices;
      for (; t < triangles.size() && kinds[t] == kind; ++t) {
        bool beyond = false;
        const bool first = draw.state.provoking_vertex == ProvokingVertex::first;
        const int provoking = golden::provoking_position(draw.primitive, static_cast<uint32_t>(t),
                                                         draw.state.provoking_vertex);
        const int start = (provoking + (first ? 0 : 1)) % 3;
        for (int k = 0; k < 3; ++k) {
          const golden::ShadedVertex& v = shaded[vertex_ids[t][(start + k) % 3]];
          vertices.push_back(kind == Kind::window ? window_vertex(v, draw.state.interpolation)
                                                  : clip_vertex(v));
          beyond = beyond || (kind == Kind::window && beyond_viewport(vertices.back()));
        }
        if (beyond) ++stats.triangles_beyond_viewport;
      }
      add_batch(draw.state, kind == Kind::window, GL_TRIANGLES, vertices,
                static_cast<GLsizei>(vertices.size()), nullptr);
      check("expanded draw upload");
    }
  }

  ReferenceResult render(const Scene& scene, int repeat) {
    for (size_t d = 0; d < scene.draws.size(); ++d) {
      const Draw& draw = scene.draws[d];
      const bool draws_lines = primitive_kind_of(draw.primitive) == PrimitiveKind::line ||
                               (primitive_kind_of(draw.primitive) == PrimitiveKind::triangle &&
                                draw.state.polygon_mode == PolygonMode::line);
      if (golden::lit_per_pixel(draw) && scene.lights.size() > kMaxPhongLights) {
        throw NotRenderable("draw " + std::to_string(d) + " is lit per pixel with " +
                            std::to_string(scene.lights.size()) +
                            " lights: the reference's fragment shader takes at most " +
                            std::to_string(kMaxPhongLights));
      }
      if (draws_lines && draw.state.line_rasterization == LineRasterization::bresenham) {
        throw NotRenderable("draw " + std::to_string(d) +
                            " asks for line_rasterization \"bresenham\", which OpenGL has no "
                            "equivalent of: the scene is not rendered by the reference");
      }
    }
    for (const Texture& t : scene.textures) {
      const TextureSampler& sm = t.sampler;
      if (sm.wrap_s == TextureWrap::clamp || sm.wrap_t == TextureWrap::clamp) {
        throw NotRenderable("texture \"" + t.name +
                            "\" wraps with clamp (GL_CLAMP), which a core profile does not have");
      }
    }
    const FramebufferDesc& desc = scene.framebuffer;
    // Antialiasing (spec section 14). llvmpipe multisamples with 1 or 4
    // samples only (PIPE_MAX_SAMPLES 4 in Mesa 22.3); anything else would be
    // some other count, so it is refused. Supersampling renders the render
    // target and box-filters it here (read_back); combined with 4 samples
    // that would be two resolves with two roundings (llvmpipe's, then ours),
    // not the spec's one box filter over k^2 * N samples: refused too.
    samples = desc.samples;
    supersample = desc.supersample;
    if (samples != 1 && samples != 4) {
      throw NotRenderable("framebuffer.samples " + std::to_string(samples) +
                          ": llvmpipe multisamples with 1 or 4 samples only");
    }
    if (samples != 1 && supersample != 1) {
      throw NotRenderable("framebuffer.samples " + std::to_string(samples) + " with supersample " +
                          std::to_string(supersample) +
                          ": the reference supersamples single-sampled frames only");
    }
    width = desc.width * static_cast<int>(supersample);
    height = desc.height * static_cast<int>(supersample);
    tx = width / 2;
    ty = height / 2;
    stats = ReferenceStats{};

    GLenum depth_internal = GL_DEPTH_COMPONENT24;
    if (desc.depth_format == DepthFormat::unorm16) depth_internal = GL_DEPTH_COMPONENT16;
    if (desc.depth_format == DepthFormat::float32) depth_internal = GL_DEPTH_COMPONENT32F;
    const GLenum color_internal = desc.color_format == ColorFormat::rgba8 ? GL_RGBA8 : GL_RGBA16F;
    // The framebuffer drawn into (multisampled when samples > 1) and, when
    // multisampled, the single-sample one it is resolved into and read from.
    Fbo draw_fbo, resolve_fbo;
    struct Cleanup {
      Impl* self;
      Fbo* fbos[2];
      ~Cleanup() {
        self->gl.glBindFramebuffer(GL_FRAMEBUFFER, 0);
        for (Fbo* f : fbos) self->delete_fbo(*f);
        if (!self->batch_buffers.empty()) {
          self->gl.glDeleteBuffers(static_cast<GLsizei>(self->batch_buffers.size()),
                                   self->batch_buffers.data());
        }
        self->batch_buffers.clear();
        self->batches.clear();
        if (!self->textures.empty()) {
          self->gl.glDeleteTextures(static_cast<GLsizei>(self->textures.size()),
                                    self->textures.data());
        }
        self->textures.clear();
        self->texture_formats.clear();
      }
    } cleanup{this, {&draw_fbo, &resolve_fbo}};
    draw_fbo = make_fbo(color_internal, depth_internal, samples);
    if (samples > 1) resolve_fbo = make_fbo(color_internal, depth_internal, 1);
    gl.glBindFramebuffer(GL_FRAMEBUFFER, draw_fbo.fbo);
    check("framebuffer set-up");

    // Fixed state for the whole frame (each batch sets its viewport).
    gl.glViewport(tx - viewport_side / 2, ty - viewport_side / 2, viewport_side, viewport_side);
    // No smoothing; the point size from glPointSize (GL_PROGRAM_POINT_SIZE
    // off). Multisampling on exactly when the buffer has samples: then lines
    // are rectangles and points squares tested at the samples (section 14).
    gl.glDisable(GL_LINE_SMOOTH);
    gl.glDisable(GL_POLYGON_SMOOTH);
    gl.glDisable(GL_PROGRAM_POINT_SIZE);
    gl.glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    gl.glDepthRange(0.0, 1.0);
    gl.glDisable(GL_DITHER);
    gl.glDisable(GL_SCISSOR_TEST);
    if (samples > 1) {
      gl.glEnable(GL_MULTISAMPLE);
    } else {
      gl.glDisable(GL_MULTISAMPLE);
    }
    gl.glDisable(GL_SAMPLE_ALPHA_TO_COVERAGE);
    gl.glDisable(GL_SAMPLE_COVERAGE);
    gl.glDisable(GL_FRAMEBUFFER_SRGB);
    check("frame state");

    using Clock = std::chrono::steady_clock;
    auto seconds_since = [](Clock::time_point start) {
      return std::chrono::duration<double>(Clock::now() - start).count();
    };
    ReferenceResult result;

    // Untimed for render_seconds: the spec's vertex stage on the CPU and the
    // upload of the textures and of every draw call's vertices and indices,
    // finished.
    const Clock::time_point prepare_start = Clock::now();
    upload_textures(scene);
    // Batches [first_batch[i], first_batch[i + 1]) draw scene.draws[i].
    std::vector<size_t> first_batch;
    for (const Draw& draw : scene.draws) {
      first_batch.push_back(batches.size());
      prepare_draw(scene, draw);
    }
    first_batch.push_back(batches.size());
    set_lights(scene);
    gl.glFinish();
    result.prepare_seconds = seconds_since(prepare_start);

    // Timed: the clear, every draw call and glFinish() (llvmpipe rasterizes
    // in its own thread; glFinish returns when the frame is complete). Each
    // repetition redraws the same frame from the clear.
    for (int r = 0; r < std::max(1, repeat); ++r) {
      const Clock::time_point start = Clock::now();
      gl.glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
      gl.glDepthMask(GL_TRUE);
      gl.glDisable(GL_SCISSOR_TEST);  // the spec's clear is the whole frame
      const glm::vec4& c = desc.clear_color;
      gl.glClearColor(c.r, c.g, c.b, c.a);
      gl.glClearDepth(desc.clear_depth);
      gl.glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
      check("clear");
      // The draw list's clears with glClear at their places (spec section
      // 15): every sample of the buffer, whatever the draws' masks were.
      size_t next_clear = 0;
      for (size_t i = 0; i <= scene.draws.size(); ++i) {
        for (; next_clear < scene.clears.size() && scene.clears[next_clear].before_draw == i;
             ++next_clear) {
          const ClearState& mid = scene.clears[next_clear];
          GLbitfield bits = 0;
          if (mid.color) {
            gl.glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
            const glm::vec4& v = mid.color_value;
            gl.glClearColor(v.r, v.g, v.b, v.a);
            bits |= GL_COLOR_BUFFER_BIT;
          }
          if (mid.depth) {
            gl.glDepthMask(GL_TRUE);
            gl.glClearDepth(mid.depth_value);
            bits |= GL_DEPTH_BUFFER_BIT;
          }
          gl.glDisable(GL_SCISSOR_TEST);  // a clear covers the whole buffer (spec section 15)
          gl.glClear(bits);
          check("mid-frame clear");
        }
        if (i == scene.draws.size()) break;
        for (size_t b = first_batch[i]; b < first_batch[i + 1]; ++b) draw_batch(batches[b]);
      }
      // The multisample resolve's blit below honours the scissor too.
      gl.glDisable(GL_SCISSOR_TEST);
      gl.glFinish();
      result.render_seconds.push_back(seconds_since(start));
    }

    result.stats = stats;
    if (samples > 1) {
      // The resolve: colour is the box filter of the samples (llvmpipe sums
      // them in float and multiplies by 1/N, then rounds: exact .5 ties go
      // either way, docs/validation.md); depth is one sample per pixel,
      // which llvmpipe's blit takes from sample 0 (measured:
      // docs/validation.md, "Multisampling") -- the spec's output depth.
      gl.glBindFramebuffer(GL_READ_FRAMEBUFFER, draw_fbo.fbo);
      gl.glBindFramebuffer(GL_DRAW_FRAMEBUFFER, resolve_fbo.fbo);
      gl.glBlitFramebuffer(0, 0, width, height, 0, 0, width, height, GL_COLOR_BUFFER_BIT,
                           GL_NEAREST);
      gl.glBlitFramebuffer(0, 0, width, height, 0, 0, width, height, GL_DEPTH_BUFFER_BIT,
                           GL_NEAREST);
      check("multisample resolve");
      gl.glBindFramebuffer(GL_FRAMEBUFFER, resolve_fbo.fbo);
    }
    const Framebuffer target = read_back(desc);
    result.framebuffer = supersample == 1 ? target : downsample(target, desc);
    return result;
  }

  // The bound framebuffer's colour and depth (width x height) in the scene's
  // formats.
  Framebuffer read_back(const FramebufferDesc& desc) {
    Framebuffer fb(width, height, desc.color_format, desc.depth_format);
    gl.glPixelStorei(GL_PACK_ALIGNMENT, 1);
    const size_t pixels = static_cast<size_t>(width) * height;
    if (desc.color_format == ColorFormat::rgba8) {
      std::vector<uint8_t> rgba(pixels * 4);
      gl.glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
      for (size_t i = 0; i < rgba.size(); ++i) fb.color[i] = rgba[i];
    } else {
      gl.glReadPixels(0, 0, width, height, GL_RGBA, GL_HALF_FLOAT, fb.color.data());
    }
    check("colour read-back");
    switch (desc.depth_format) {
      case DepthFormat::unorm16: {
        std::vector<uint16_t> d(pixels);
        gl.glReadPixels(0, 0, width, height, GL_DEPTH_COMPONENT, GL_UNSIGNED_SHORT, d.data());
        for (size_t i = 0; i < pixels; ++i) fb.depth[i] = d[i];
        break;
      }
      case DepthFormat::unorm24: {
        // 24-bit values arrive scaled to 32 bits by bit replication
        // (v << 8 | v >> 16); the top 24 bits are the stored value.
        std::vector<uint32_t> d(pixels);
        gl.glReadPixels(0, 0, width, height, GL_DEPTH_COMPONENT, GL_UNSIGNED_INT, d.data());
        for (size_t i = 0; i < pixels; ++i) fb.depth[i] = d[i] >> 8;
        break;
      }
      case DepthFormat::float32: {
        std::vector<float> d(pixels);
        gl.glReadPixels(0, 0, width, height, GL_DEPTH_COMPONENT, GL_FLOAT, d.data());
        for (size_t i = 0; i < pixels; ++i) fb.depth[i] = bits_from_float(d[i]);
        break;
      }
    }
    check("depth read-back");
    return fb;
  }

  // Supersampling's resolve on the CPU, exactly as spec section 14 says
  // (single-sampled render target, so n = k^2): rgba8 floor((2 sum + n) /
  // (2n)); rgba16f the halves summed in float in the order j, then i, then
  // half(sum / n). Depth: render-target pixel (kx, ky).
  Framebuffer downsample(const Framebuffer& rt, const FramebufferDesc& desc) const {
    const int k = static_cast<int>(supersample);
    const uint32_t n = static_cast<uint32_t>(k * k);
    Framebuffer out(desc.width, desc.height, desc.color_format, desc.depth_format);
    for (int y = 0; y < desc.height; ++y) {
      for (int x = 0; x < desc.width; ++x) {
        for (int c = 0; c < 4; ++c) {
          if (desc.color_format == ColorFormat::rgba8) {
            uint32_t sum = 0;
            for (int j = 0; j < k; ++j) {
              for (int i = 0; i < k; ++i) sum += rt.color_at(k * x + i, k * y + j)[c];
            }
            out.color_at(x, y)[c] = static_cast<ColorChannel>((2 * sum + n) / (2 * n));
          } else {
            // The sum starts from the first value (so that -0 stays -0).
            float sum = decode_half(rt.color_at(k * x, k * y)[c]);
            for (int j = 0; j < k; ++j) {
              for (int i = (j == 0 ? 1 : 0); i < k; ++i) {
                sum += decode_half(rt.color_at(k * x + i, k * y + j)[c]);
              }
            }
            out.color_at(x, y)[c] = encode_half(sum / static_cast<float>(n));
          }
        }
        out.depth[out.pixel_index(x, y)] = rt.depth[rt.pixel_index(k * x, k * y)];
      }
    }
    return out;
  }

  struct Fbo {
    GLuint fbo = 0, color_rb = 0, depth_rb = 0;
  };

  // A complete framebuffer object of width x height with a colour and a
  // depth renderbuffer, multisampled when samples > 1.
  Fbo make_fbo(GLenum color_internal, GLenum depth_internal, unsigned sample_count) {
    Fbo f;
    gl.glGenFramebuffers(1, &f.fbo);
    gl.glBindFramebuffer(GL_FRAMEBUFFER, f.fbo);
    auto storage = [&](GLuint& rb, GLenum internal, GLenum attachment) {
      gl.glGenRenderbuffers(1, &rb);
      gl.glBindRenderbuffer(GL_RENDERBUFFER, rb);
      if (sample_count > 1) {
        gl.glRenderbufferStorageMultisample(GL_RENDERBUFFER, static_cast<GLsizei>(sample_count),
                                            internal, width, height);
      } else {
        gl.glRenderbufferStorage(GL_RENDERBUFFER, internal, width, height);
      }
      gl.glFramebufferRenderbuffer(GL_FRAMEBUFFER, attachment, GL_RENDERBUFFER, rb);
    };
    storage(f.color_rb, color_internal, GL_COLOR_ATTACHMENT0);
    storage(f.depth_rb, depth_internal, GL_DEPTH_ATTACHMENT);
    if (gl.glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
      delete_fbo(f);
      throw ReferenceError("the framebuffer object is incomplete (" + std::to_string(sample_count) +
                           " samples)");
    }
    if (sample_count > 1) {
      GLint got = 0;
      gl.glGetIntegerv(GL_SAMPLES, &got);
      if (got != static_cast<GLint>(sample_count)) {
        delete_fbo(f);
        throw ReferenceError("asked for " + std::to_string(sample_count) +
                             " samples per pixel, OpenGL gave " + std::to_string(got));
      }
    }
    return f;
  }

  void delete_fbo(Fbo& f) {
    if (f.fbo != 0) gl.glDeleteFramebuffers(1, &f.fbo);
    if (f.color_rb != 0) gl.glDeleteRenderbuffers(1, &f.color_rb);
    if (f.depth_rb != 0) gl.glDeleteRenderbuffers(1, &f.depth_rb);
    f = Fbo{};
  }
};

GlReference::GlReference() : m_impl(std::make_unique<Impl>()) {
  m_impl->init();
}
GlReference::~GlReference() = default;

ReferenceResult GlReference::render(const Scene& scene, int repeat) {
  return m_impl->render(scene, repeat);
}
std::string GlReference::renderer() const {
  return m_impl->renderer;
}
std::string GlReference::version() const {
  return m_impl->version;
}
int GlReference::viewport_side() const {
  return m_impl->viewport_side;
}

}  // namespace gpusim::reference
