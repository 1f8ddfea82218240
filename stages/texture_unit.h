// Texture unit, one per raster unit, between the interpolator and the ROP
// (docs/pipeline-spec.md, section 9c), elaborated only in frames with a
// textured draw. For every covered pixel of a textured draw it turns the
// texture coordinate into texel addresses, reads the texels through its
// texture cache (hw/texture_cache.h) and filters them in 8-bit fixed point,
// then applies the draw's texture environment to the pixel's colour. Other
// draws' batches and control tokens pass through.
//
// Level of detail, per pixel from its quad's texture coordinate derivatives
// (which the interpolator computes when the texture's filters need them):
// the pixel is magnified (level 0, the MAG filter) or minified (the MIN
// filter, on one mipmap level or blending two); pick_level() in the .cpp
// has the arithmetic, spec section 9c the rule.
//
// Sampling, per axis of a level of `size` texels (the spec's rules, in the
// unit's own datapath):
//   NEAREST  i = floor(s * size), wrapped;
//   LINEAR   REPEAT on a side that is not a power of two first takes
//            s - floor(s); then u = round(s * size * 256) - 128, a 24.8
//            fixed-point texel coordinate: texels i = u >> 8 and i + 1,
//            wrapped, weight u & 255. The four texels are combined by two
//            8.8 lerps along s and one along t.
// Wrapping: REPEAT is a mask (power-of-two sides) or a remainder;
// CLAMP_TO_EDGE clamps to [0, size - 1]. Texels are stored linearly, row by
// row from t = 0, at the level's address (hw/texture_state.h).
//
// The datapath is Igehy, Eldridge and Proudfoot's prefetching texture unit
// (1998): an address stage looks every pixel's texels up in the cache and
// sends the misses to memory at once; a fragment FIFO of
// texture.prefetch_fragments entries holds the pixels until their lines have
// arrived; a filter stage takes one pass per level a pixel reads (a bilinear
// sample: four texels a clock; a pixel blending two levels takes two).
// Cost model, per textured batch of n pixels read at time t, in cycles from
// t, with passes(i) 1 or 2 and pixel indices running on across batches (the
// address stage and the filter are a pipeline: the fragment FIFO spans
// batches):
//   address(i) = max(address(i - 1) + 1, filter(i - D))  (D the FIFO depth)
//   filter(i)  = max(filter(i - 1) + passes(i - 1), address(i) + 1,
//                    arrival of its lines)
// where a line's arrival is its fill's completion (the memory model's), or
// that of the earlier fill still in flight for it, and lines present are
// there already. busy = max(ii * stamps, address(last) + 1 - t): the
// address stage, which waits for fragment FIFO entries; the batch is
// readable `latency` cycles after its last filter pass, and never before a
// token read before it. An untextured batch or a control token: busy = ii
// * stamps (at least ii), a pass-through, in order behind the filter.
// memory_stall_cycles counts the cycles the filter waits for fills.
#pragma once

#include <cstdint>
#include <deque>
#include <systemc>
#include <vector>

#include "hw/draw_state.h"
#include "hw/fifo.h"
#include "hw/gpu_config.h"
#include "hw/memory.h"
#include "hw/packets.h"
#include "hw/pipeline_stage.h"
#include "hw/stats.h"
#include "hw/texture_cache.h"

namespace gpusim {

class TextureUnit : public PipelineStage {
 public:
  static const StageSpec& spec();

  FifoInPort<ShadedStampBatch> in;
  FifoOutPort<ShadedStampBatch> out;
  MemoryPort mem;

  TextureUnit(sc_core::sc_module_name name, const GpuConfig& config, const FrameState& frame,
              unsigned unit);
  bool decouplable() const override { return true; }

 private:
  void run();
  void reset_state() override;
  // Textures every pixel of a textured draw's batch: how long its address
  // stage takes (cycles from now) and when the filter finishes it.
  struct Timing {
    uint64_t address_cycles = 0;
    sc_core::sc_time filtered;
  };
  Timing texture(ShadedStampBatch& batch, const TextureBinding& binding);

  // Per pixel of the batch being textured: its texels, their weights, and
  // what its lines wait for.
  struct Footprint {
    unsigned texels = 1;  // 1 (nearest) or 4 (bilinear: x0y0, x1y0, x0y1, x1y1)
    unsigned weight_s = 0, weight_t = 0;
    // The fills of this round it waits for (indices into m_fills; -1: none),
    // and the latest arrival of the lines it found filled earlier.
    std::array<int32_t, 16> fill{};  // 2 levels x 4 texels of at most 2 lines each
    uint64_t ready = 0;
  };
  std::vector<Footprint> m_pixels;
  std::vector<MemoryArbiter::Sink> m_fills;  // this batch's line fills
  TextureCache m_cache;
  // The filter across batches (SystemC time values): when it finishes the
  // last pass it was given, and when each of the last D pixels started
  // (its fragment FIFO entry freed then). The address stage runs ahead of
  // the filter by up to D pixels whatever batches they belong to.
  uint64_t m_filter_free = 0;
  std::deque<uint64_t> m_filter_starts;
  sc_core::sc_time m_last_ready;  // the last token's readiness: tokens leave in order

  uint64_t& m_fragments =
      m_stats.counter("fragments", "fragments", "pixels textured (of textured draws)");
  uint64_t& m_texels = m_stats.counter("texels", "texels", "texels read from the cache");
  uint64_t& m_bilinear =
      m_stats.counter("bilinear_samples", "samples", "levels filtered with LINEAR (4 texels)");
  uint64_t& m_nearest =
      m_stats.counter("nearest_samples", "samples", "levels sampled with NEAREST (1 texel)");
  uint64_t& m_two_level = m_stats.counter("two_level_fragments", "fragments",
                                          "pixels that blend two mipmap levels (two passes)");
  uint64_t& m_hits = m_stats.counter("cache_hits", "lines", "texture cache lookups that hit");
  uint64_t& m_misses =
      m_stats.counter("cache_misses", "lines", "texture cache lookups that missed (line fills)");
  uint64_t& m_memory_stall_cycles = m_stats.counter(
      "memory_stall_cycles", "cycles", "cycles the filter waited for texture cache fills");
};

}  // namespace gpusim
