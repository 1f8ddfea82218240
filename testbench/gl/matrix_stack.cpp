#include "testbench/gl/matrix_stack.h"

#include <cmath>

namespace gpusim::gl {

void MatrixStack::rotate(float degrees, float x, float y, float z) {
  const float len = std::sqrt(x * x + y * y + z * z);
  if (!(len > 0.0f)) return;
  x /= len, y /= len, z /= len;
  // The angle converted in double, as Mesa's glRotatef does.
  const float radians = static_cast<float>(degrees * M_PI / 180.0);
  const float c = std::cos(radians), s = std::sin(radians), k = 1.0f - c;
  glm::mat4 r(1.0f);  // r[column][row]
  // About a coordinate axis the general formula's 1 - c + c may round away
  // from 1: write those rotations exactly, as Mesa does.
  if (y == 0.0f && z == 0.0f) {
    const float sx = x > 0.0f ? s : -s;
    r[1][1] = c, r[2][1] = -sx, r[1][2] = sx, r[2][2] = c;
  } else if (x == 0.0f && z == 0.0f) {
    const float sy = y > 0.0f ? s : -s;
    r[0][0] = c, r[2][0] = sy, r[0][2] = -sy, r[2][2] = c;
  } else if (x == 0.0f && y == 0.0f) {
    const float sz = z > 0.0f ? s : -s;
    r[0][0] = c, r[1][0] = -sz, r[0][1] = sz, r[1][1] = c;
  } else {
    r[0][0] = x * x * k + c, r[1][0] = x * y * k - z * s, r[2][0] = x * z * k + y * s;
    r[0][1] = y * x * k + z * s, r[1][1] = y * y * k + c, r[2][1] = y * z * k - x * s;
    r[0][2] = x * z * k - y * s, r[1][2] = y * z * k + x * s, r[2][2] = z * z * k + c;
  }
  multiply(r);
}

void MatrixStack::translate(float x, float y, float z) {
  glm::mat4 t(1.0f);
  t[3] = glm::vec4(x, y, z, 1.0f);
  multiply(t);
}

void MatrixStack::scale(float x, float y, float z) {
  glm::mat4 s(1.0f);
  s[0][0] = x, s[1][1] = y, s[2][2] = z;
  multiply(s);
}

void MatrixStack::frustum(float l, float r, float b, float t, float n, float f) {
  glm::mat4 m(0.0f);
  m[0][0] = 2.0f * n / (r - l);
  m[1][1] = 2.0f * n / (t - b);
  m[2][0] = (r + l) / (r - l);
  m[2][1] = (t + b) / (t - b);
  m[2][2] = -(f + n) / (f - n);
  m[2][3] = -1.0f;
  m[3][2] = -(2.0f * f * n) / (f - n);
  multiply(m);
}

void MatrixStack::ortho(float l, float r, float b, float t, float n, float f) {
  glm::mat4 m(1.0f);
  m[0][0] = 2.0f / (r - l);
  m[1][1] = 2.0f / (t - b);
  m[2][2] = -2.0f / (f - n);
  m[3][0] = -(r + l) / (r - l);
  m[3][1] = -(t + b) / (t - b);
  m[3][2] = -(f + n) / (f - n);
  multiply(m);
}

bool MatrixStack::push() {
  if (m_stack.size() >= m_max_depth) return false;
  m_stack.push_back(m_stack.back());
  return true;
}

bool MatrixStack::pop() {
  if (m_stack.size() <= 1) return false;
  m_stack.pop_back();
  return true;
}

}  // namespace gpusim::gl
