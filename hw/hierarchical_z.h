// Hierarchical Z (issue #11): the pieces the tile rasterizer and the depth
// test of one unit share. The buffer itself, its test and its cost model are
// described with the rasterizer that owns it (stages/tile_rasterizer.h,
// "Hierarchical Z"); the exact updates with the depth test
// (stages/depth_test.h).
//
//   HzRange            a conservative [min, max] of encoded depth values
//   hz_primitive_range the range every depth value a triangle can store lies in
//   HzUpdate           depth test -> rasterizer: a tile's exact range after a batch
//   HzUpdateLink       the side channel carrying updates, with its visibility rule
//
// Bit widths: depth values are DepthValue (32 bits: unorm16, unorm24 or the
// bits of a float32 in [0, 1], which order like the floats). A block's
// sequence number counts the depth-writing batches emitted to it; the model
// keeps 32 bits, hardware needs only enough to tell the batches in flight
// between the rasterizer and the depth test apart (FIFO depth + 2: 16 bits
// with wrap-around comparison are ample).
#pragma once

#include <cstdint>
#include <deque>
#include <ostream>
#include <systemc>

#include "hw/packets.h"
#include "hw/pixel_formats.h"
#include "hw/superdense_time.h"

namespace gpusim {

struct HzRange {
  DepthValue min = 0;
  DepthValue max = ~DepthValue{0};  // default: nothing known

  static constexpr const char* kPacketName = "HzRange";
  template <typename V>
  static constexpr void fields(V& v) {
    v("min", &HzRange::min);
    v("max", &HzRange::max);
  }
};

// A triangle's depth range in the buffer's encoding: every value the depth
// test can compute for one of its covered pixels or samples (interpolation,
// polygon offset, clamp, encoding) lies in it. The proof is at the
// definition (hw/hierarchical_z.cpp).
HzRange hz_primitive_range(const RasterPrimitive& t, DepthFormat format);

// Depth test -> rasterizer: tile `tile`'s exact range after the batch with
// sequence number `seq` of clear epoch `epoch`, sent at the depth test's time
// `sent`.
struct HzUpdate {
  sc_core::sc_time sent;
  uint32_t tile = 0;  // screen tile index ty * tiles_x + tx
  uint32_t seq = 0;
  uint32_t epoch = 0;
  HzRange range;

  static constexpr const char* kPacketName = "HzUpdate";
  template <typename V>
  static constexpr void fields(V& v) {
    using namespace packet_fields;
    v("sent", &HzUpdate::sent, model_only);  // the link's visibility rule, not a signal
    v("tile", &HzUpdate::tile);
    v("seq", &HzUpdate::seq);
    v("epoch", &HzUpdate::epoch);
    v("range", &HzUpdate::range);
  }
};
static_assert(packet_bits<HzUpdate>() == 3 * 32 + 2 * 32);

// A unit's update channel: a plain C++ queue (no SystemC channel, no event:
// the rasterizer polls it when it tests a tile). Visibility makes it
// independent of process order: an update stamped t_u (the depth test's
// local_time()) is taken only when t_u + latency < now, now being the
// reader's time. The writer sends in an activation at kernel time S <= t_u,
// so every update stamped before the kernel's time has been sent; so has
// every one stamped before a decoupled writer's clock, which its later
// sends cannot precede. A decoupled reader looks only once either has
// passed now - latency (TileRasterizer::hz_culls), whatever the order of
// processes within a time. The one writer sends in time order, so the
// queue is in stamp order.
class HzUpdateLink {
 public:
  explicit HzUpdateLink(uint64_t latency_cycles, sc_core::sc_time cycle)
      : m_latency(sc_core::sc_time::from_value(cycle.value() * latency_cycles)) {}

  void send(const HzUpdate& u) { m_queue.push_back(u); }
  // Between frames (Topology::reset): no update in flight.
  void reset() { m_queue.clear(); }
  const sc_core::sc_time& latency() const { return m_latency; }

  // A decoupled writer's clock (before the simulation starts; null: the
  // writer is in the kernel's time).
  void set_writer_clock(const SuperdenseTime* clock) { m_writer_clock = clock; }
  // Whether every update stamped before `t` has been sent.
  bool sent_before(const sc_core::sc_time& t) const {
    return sc_core::sc_time_stamp() >= t || (m_writer_clock && m_writer_clock->t >= t.value());
  }

  // Calls f(update) for every update visible at `now`, oldest first.
  template <typename F>
  void take_visible(const sc_core::sc_time& now, F&& f) {
    while (!m_queue.empty() && m_queue.front().sent + m_latency < now) {
      f(m_queue.front());
      m_queue.pop_front();
    }
  }

 private:
  sc_core::sc_time m_latency;
  std::deque<HzUpdate> m_queue;
  const SuperdenseTime* m_writer_clock = nullptr;
};

}  // namespace gpusim
