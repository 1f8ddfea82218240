// One of OpenGL's matrix stacks (modelview, projection, texture) and the
// operations that edit its top: glLoadIdentity, glLoadMatrix, glMultMatrix,
// glRotate, glTranslate, glScale, glFrustum, glOrtho, glPushMatrix,
// glPopMatrix. Matrices are float, column-major (glm), built as the OpenGL
// 1.x specification writes them (section 2.11.2) and multiplied on the right
// of the top, C = C * M, as GL does.
#pragma once

#include <cstddef>
#include <glm/glm.hpp>
#include <vector>

namespace gpusim::gl {

class MatrixStack {
 public:
  // max_depth: GL_MAX_*_STACK_DEPTH (Mesa: 32 modelview, 32 projection, 10 texture).
  explicit MatrixStack(size_t max_depth) : m_max_depth(max_depth), m_stack(1, glm::mat4(1.0f)) {}

  const glm::mat4& top() const { return m_stack.back(); }
  size_t depth() const { return m_stack.size(); }

  void load_identity() { m_stack.back() = glm::mat4(1.0f); }
  void load(const glm::mat4& m) { m_stack.back() = m; }
  void multiply(const glm::mat4& m) { m_stack.back() = m_stack.back() * m; }
  // Degrees about (x, y, z), normalised first; a zero axis leaves the top as
  // it is (Mesa ignores such a rotation).
  void rotate(float degrees, float x, float y, float z);
  void translate(float x, float y, float z);
  void scale(float x, float y, float z);
  void frustum(float l, float r, float b, float t, float n, float f);
  void ortho(float l, float r, float b, float t, float n, float f);
  // false (and nothing changes) on GL_STACK_OVERFLOW / GL_STACK_UNDERFLOW.
  bool push();
  bool pop();

 private:
  size_t m_max_depth;
  std::vector<glm::mat4> m_stack;
};

}  // namespace gpusim::gl
