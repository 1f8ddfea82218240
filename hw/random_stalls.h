// A FIFO's stall policy (after MatchLib's rand_stall): installed from
// outside, it delays a FIFO's reads and writes at random, to prove that
// results do not depend on timing. Each FIFO draws from its own streams,
// seeded by its name, so a stage added elsewhere in the netlist changes no
// other FIFO's stalls.
#pragma once

#include <cstdint>
#include <string>
#include <systemc>

namespace gpusim {

// splitmix64: tiny, fast and fully specified, so a seed gives the same stall
// pattern with every compiler and standard library.
struct SplitMix64 {
  uint64_t state = 0;
  uint64_t next() {
    uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)
};

// The seed of FIFO `fifo`'s stalls in a run seeded `seed`: a function of
// the name alone, not of the FIFO's place in the netlist.
uint64_t stall_seed_of(const std::string& fifo, uint64_t seed);

class RandomStalls {
 public:
  // No stalls.
  RandomStalls() = default;
  // Every blocking read and write first waits, with `probability`, a
  // uniformly drawn 1..max_cycles cycles of `cycle`. Readers and writers
  // draw from separate streams derived from `seed`. std::invalid_argument
  // (naming `fifo`) unless probability is in [0, 1], max_cycles >= 1 and
  // the cycle is not zero.
  RandomStalls(const std::string& fifo, uint64_t seed, double probability, unsigned max_cycles,
               sc_core::sc_time cycle);

  // Whether any operation can stall: the FIFO's one test per operation
  // when none can.
  bool active() const { return m_probability > 0.0; }

  enum class Side { writer, reader };
  // The next operation's stall on `side`, an sc_time value: 0 (most often)
  // or a delay. Only when active().
  uint64_t draw(Side side) {
    SplitMix64& rng = side == Side::writer ? m_writer : m_reader;
    if (rng.uniform() >= m_probability) return 0;
    return m_cycle.value() * (1 + rng.next() % m_max_cycles);
  }

 private:
  double m_probability = 0.0;
  unsigned m_max_cycles = 0;
  sc_core::sc_time m_cycle;
  SplitMix64 m_writer;
  SplitMix64 m_reader;
};

}  // namespace gpusim
