// A texture unit's texture cache (stages/texture_unit.h): set-associative,
// least recently used replacement, read-only (textures do not change during
// a frame). Lines are filled by the texture unit from the GPU's memory; the
// cache keeps their bytes and, per line, when its fill arrives, so a hit
// on a line still in flight waits for it as a miss would.
#pragma once

#include <cstdint>
#include <vector>

#include "hw/gpu_config.h"

namespace gpusim {

class TextureCache {
 public:
  explicit TextureCache(const TextureConfig& config);

  unsigned line_bytes() const { return m_line_bytes; }
  // Every line invalid (between frames).
  void reset();

  struct Lookup {
    uint32_t slot = 0;  // the line's place in the cache: data(slot), ready(slot)
    bool hit = false;   // false: the line was allocated, the caller fills it
  };
  // The line of byte address `addr` (any byte in it), allocated in its
  // set's least recently used way when absent.
  Lookup lookup(uint64_t addr);
  uint8_t* data(uint32_t slot) { return &m_data[static_cast<size_t>(slot) * m_line_bytes]; }
  // When the line's fill arrives (SystemC time value), set by the caller.
  uint64_t& ready(uint32_t slot) { return m_ready[slot]; }

 private:
  static constexpr uint64_t kInvalid = ~uint64_t{0};
  const unsigned m_sets, m_ways, m_line_bytes;
  const unsigned m_line_shift;
  std::vector<uint64_t> m_tag;  // line address (addr >> line_shift), kInvalid when empty
  std::vector<uint64_t> m_last_use;
  std::vector<uint64_t> m_ready;
  std::vector<uint8_t> m_data;
  uint64_t m_tick = 0;
};

}  // namespace gpusim
