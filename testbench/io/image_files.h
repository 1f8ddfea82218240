// Frame dumps: OpenEXR (R, G, B, A as half, Z as float) and an 8-bit PNG
// preview, both stored top row first so pictures are upright. Writers write to
// a temporary name in the target directory and rename, so a failed write never
// leaves a half-written file or destroys an existing one. Both are
// compressed losslessly and favour speed (a 4K frame is written in under a
// second): the EXR's ZIP at zlib level 2, the PNG at level 4 with the Up
// filter; the files' bytes depend on these settings, their pixels do not.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "hw/framebuffer.h"

namespace gpusim {

// Write fb as EXR: channels R, G, B, A (HALF) decoded from the colour buffer
// and Z (FLOAT) decoded from the depth buffer; header attributes record the
// buffer formats. Throws InputError (hw/input_error.h) on failure.
void write_frame_exr(const Framebuffer& fb, const std::string& path);

// Write an 8-bit RGBA PNG preview: each channel clamped to [0, 1] (NaN -> 0)
// and rounded, round(v * 255), halves away from zero.
void write_frame_png(const Framebuffer& fb, const std::string& path);

// Write 8-bit RGBA pixels (rgba[(y * width + x) * 4 + c], row 0 = top row) as
// a PNG, via a temporary and rename. Throws InputError "<path>: <problem>".
void write_png_rgba8(const std::string& path, int width, int height,
                     const std::vector<uint8_t>& rgba);

// An image file as float channels, in file order (top row first).
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::string> channel_names;    // as the file lists them
  std::vector<std::vector<float>> channels;  // channels[c][y * width + x]
  bool png = false;                          // read from a PNG file
  const std::vector<float>* find(const std::string& name) const;
};
// Any EXR file (channels sorted as the file lists them). Throws InputError
// naming the file and the problem.
Image read_exr(const std::string& path);
// An 8-bit PNG file as channels R, G, B (grey is expanded to RGB) and A when
// the file has alpha (a colour key included), each value v / 255. 16-bit
// PNGs are refused. Throws InputError naming the file and the problem.
Image read_png(const std::string& path);
// read_png for a file that starts with the PNG signature, read_exr for an
// OpenEXR file; anything else is an InputError "PATH: not an OpenEXR or PNG
// file".
Image read_image(const std::string& path);

}  // namespace gpusim
