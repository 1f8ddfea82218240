// The OpenGL and GLX/EGL enumerant values the fixed-function driver reads
// from trace calls (values from the OpenGL registry's gl.xml). Only the ones
// the driver tests for are here: a trace names every other by its value.
#pragma once

#include <cstdint>

namespace gpusim::gl::en {

// Primitives (glBegin, glDrawArrays, glDrawElements).
constexpr uint32_t POINTS = 0x0000, LINES = 0x0001, LINE_LOOP = 0x0002, LINE_STRIP = 0x0003,
                   TRIANGLES = 0x0004, TRIANGLE_STRIP = 0x0005, TRIANGLE_FAN = 0x0006,
                   QUADS = 0x0007, QUAD_STRIP = 0x0008, POLYGON = 0x0009;

// Data types.
constexpr uint32_t BYTE = 0x1400, UNSIGNED_BYTE = 0x1401, SHORT = 0x1402, UNSIGNED_SHORT = 0x1403,
                   INT = 0x1404, UNSIGNED_INT = 0x1405, FLOAT = 0x1406, DOUBLE = 0x140A;

// Faces, comparison functions, blend factors and equations.
constexpr uint32_t FRONT = 0x0404, BACK = 0x0405, FRONT_AND_BACK = 0x0408;
constexpr uint32_t CW = 0x0900, CCW = 0x0901;
constexpr uint32_t NEVER = 0x0200, LESS = 0x0201, EQUAL = 0x0202, LEQUAL = 0x0203, GREATER = 0x0204,
                   NOTEQUAL = 0x0205, GEQUAL = 0x0206, ALWAYS = 0x0207;
constexpr uint32_t ZERO = 0, ONE = 1, SRC_COLOR = 0x0300, ONE_MINUS_SRC_COLOR = 0x0301,
                   SRC_ALPHA = 0x0302, ONE_MINUS_SRC_ALPHA = 0x0303, DST_ALPHA = 0x0304,
                   ONE_MINUS_DST_ALPHA = 0x0305, DST_COLOR = 0x0306, ONE_MINUS_DST_COLOR = 0x0307,
                   SRC_ALPHA_SATURATE = 0x0308;
constexpr uint32_t FUNC_ADD = 0x8006, FUNC_SUBTRACT = 0x800A, FUNC_REVERSE_SUBTRACT = 0x800B;
constexpr uint32_t FLAT = 0x1D00, SMOOTH = 0x1D01;
constexpr uint32_t FIRST_VERTEX_CONVENTION = 0x8E4D, LAST_VERTEX_CONVENTION = 0x8E4E;
constexpr uint32_t POINT = 0x1B00, LINE = 0x1B01, FILL = 0x1B02;

// Capabilities (glEnable).
constexpr uint32_t LIGHTING = 0x0B50, LIGHT0 = 0x4000, COLOR_MATERIAL = 0x0B57, NORMALIZE = 0x0BA1,
                   RESCALE_NORMAL = 0x803A, CULL_FACE = 0x0B44, DEPTH_TEST = 0x0B71, BLEND = 0x0BE2,
                   SCISSOR_TEST = 0x0C11, POLYGON_OFFSET_FILL = 0x8037,
                   POLYGON_OFFSET_LINE = 0x2A02, POLYGON_OFFSET_POINT = 0x2A01, DITHER = 0x0BD0,
                   MULTISAMPLE = 0x809D, LINE_SMOOTH = 0x0B20, POINT_SMOOTH = 0x0B10,
                   POLYGON_SMOOTH = 0x0B41, ALPHA_TEST = 0x0BC0, TEXTURE_1D = 0x0DE0,
                   TEXTURE_2D = 0x0DE1, TEXTURE_3D = 0x806F, TEXTURE_CUBE_MAP = 0x8513;

// Client arrays (glEnableClientState).
constexpr uint32_t VERTEX_ARRAY = 0x8074, NORMAL_ARRAY = 0x8075, COLOR_ARRAY = 0x8076,
                   INDEX_ARRAY = 0x8077, TEXTURE_COORD_ARRAY = 0x8078, EDGE_FLAG_ARRAY = 0x8079;

// Lights, materials and the light model.
constexpr uint32_t AMBIENT = 0x1200, DIFFUSE = 0x1201, SPECULAR = 0x1202, POSITION = 0x1203,
                   SPOT_DIRECTION = 0x1204, SPOT_EXPONENT = 0x1205, SPOT_CUTOFF = 0x1206,
                   CONSTANT_ATTENUATION = 0x1207, LINEAR_ATTENUATION = 0x1208,
                   QUADRATIC_ATTENUATION = 0x1209, EMISSION = 0x1600, SHININESS = 0x1601,
                   AMBIENT_AND_DIFFUSE = 0x1602, COLOR_INDEXES = 0x1603;
constexpr uint32_t LIGHT_MODEL_LOCAL_VIEWER = 0x0B51, LIGHT_MODEL_TWO_SIDE = 0x0B52,
                   LIGHT_MODEL_AMBIENT = 0x0B53, LIGHT_MODEL_COLOR_CONTROL = 0x81F8,
                   SINGLE_COLOR = 0x81F9, SEPARATE_SPECULAR_COLOR = 0x81FA;

// Matrix modes, display lists, clear bits.
constexpr uint32_t MODELVIEW = 0x1700, PROJECTION = 0x1701, TEXTURE = 0x1702;
constexpr uint32_t MODELVIEW_MATRIX = 0x0BA6, PROJECTION_MATRIX = 0x0BA7;
constexpr uint32_t COMPILE = 0x1300, COMPILE_AND_EXECUTE = 0x1301;
constexpr uint32_t DEPTH_BUFFER_BIT = 0x0100, STENCIL_BUFFER_BIT = 0x0400,
                   ACCUM_BUFFER_BIT = 0x0200, COLOR_BUFFER_BIT = 0x4000;
// glCallLists' name types beyond the data types above.
constexpr uint32_t TWO_BYTES = 0x1407, THREE_BYTES = 0x1408, FOUR_BYTES = 0x1409;

}  // namespace gpusim::gl::en
