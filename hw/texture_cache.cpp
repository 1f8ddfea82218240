#include "hw/texture_cache.h"

#include <algorithm>

namespace gpusim {

TextureCache::TextureCache(const TextureConfig& config)
    : m_sets(config.cache_sets),
      m_ways(config.cache_ways),
      m_line_bytes(config.cache_line_bytes),
      m_line_shift(static_cast<unsigned>(__builtin_ctz(config.cache_line_bytes))),
      m_tag(size_t{m_sets} * m_ways, kInvalid),
      m_last_use(m_tag.size(), 0),
      m_ready(m_tag.size(), 0),
      m_data(m_tag.size() * m_line_bytes) {}

void TextureCache::reset() {
  std::fill(m_tag.begin(), m_tag.end(), kInvalid);
  std::fill(m_last_use.begin(), m_last_use.end(), 0);
  std::fill(m_ready.begin(), m_ready.end(), 0);
  m_tick = 0;
}

TextureCache::Lookup TextureCache::lookup(uint64_t addr) {
  const uint64_t line = addr >> m_line_shift;
  const uint32_t first = static_cast<uint32_t>(line & (m_sets - 1)) * m_ways;
  uint32_t victim = first;
  for (uint32_t slot = first; slot < first + m_ways; ++slot) {
    if (m_tag[slot] == line) {
      m_last_use[slot] = ++m_tick;
      return {slot, true};
    }
    // An empty way (last use 0) before any used one, else the least recent.
    if (m_last_use[slot] < m_last_use[victim]) victim = slot;
  }
  m_tag[victim] = line;
  m_last_use[victim] = ++m_tick;
  return {victim, false};
}

}  // namespace gpusim
