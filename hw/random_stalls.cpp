#include "hw/random_stalls.h"

#include <stdexcept>

namespace gpusim {

uint64_t stall_seed_of(const std::string& fifo, uint64_t seed) {
  // FNV-1a over the name, then splitmix64's finalizer over it and the seed.
  uint64_t h = 0xCBF29CE484222325ull;
  for (const char c : fifo) h = (h ^ static_cast<unsigned char>(c)) * 0x100000001B3ull;
  uint64_t z = h + seed * 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

RandomStalls::RandomStalls(const std::string& fifo, uint64_t seed, double probability,
                           unsigned max_cycles, sc_core::sc_time cycle)
    : m_probability(probability), m_max_cycles(max_cycles), m_cycle(cycle) {
  if (!(probability >= 0.0 && probability <= 1.0) || max_cycles == 0 ||
      cycle == sc_core::SC_ZERO_TIME) {
    throw std::invalid_argument("Fifo " + fifo +
                                ": random stalls need probability in [0, 1], "
                                "max_cycles >= 1 and a non-zero cycle");
  }
  m_writer.state = seed;
  m_reader.state = seed ^ 0xD1B54A32D192ED03ull;
}

}  // namespace gpusim
