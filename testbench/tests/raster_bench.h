// The raster front of a unit group as a testbench, shared by the chain tests
// of triangles (stages_raster_test.cpp) and of lines and points
// (stages_lines_test.cpp) and by primitive setup's
// (stages_primitive_setup_test.cpp); with the window-space triangles and
// control tokens they feed it; the counter lookup they read it with is
// stage_host.h's.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <systemc>
#include <utility>
#include <vector>

#include "hw/fifo.h"
#include "hw/gpu_config.h"
#include "hw/packets.h"
#include "stages/primitive_setup.h"
#include "stages/tile_distributor.h"
#include "stages/tile_rasterizer.h"
#include "testbench/tests/stage_host.h"

namespace gpusim {
namespace test {

// Testbench: source -> Fifo -> PrimitiveSetup -> Fifo [-> tap -> Fifo] ->
// TileDistributor -> Fifo per unit -> TileRasterizer -> Fifo -> sink. The
// tap records every setup packet and forwards it in the same instant (it adds
// no time, but one delta; timing tests run without it).

struct RasterBench {
  GpuConfig config = GpuConfig::baseline();
  FrameState frame;
  Fifo<ClippedPrimitive> input;
  PrimitiveSetup setup;
  Fifo<SetupPacket> setup_out;
  Fifo<SetupPacket> tapped;
  TileDistributor distributor;
  std::vector<std::unique_ptr<Fifo<SetupPacket>>> jobs;
  std::vector<std::unique_ptr<TileRasterizer>> units;
  std::vector<std::unique_ptr<Fifo<StampBatch>>> stamps;

  std::vector<SetupPacket> setup_packets;        // with the tap
  std::vector<std::vector<StampBatch>> out;      // per unit
  std::vector<std::vector<uint64_t>> out_cycle;  // per unit, when the sink read each

  static std::string n(const std::string& prefix, const std::string& what) {
    return prefix + "_" + what;
  }

  RasterBench(const std::string& p, const GpuConfig& c, const FrameState& f, bool tap)
      : config(c),
        frame(f),
        input(n(p, "input").c_str(), config.fifo_depth),
        setup(n(p, "setup").c_str(), config, frame),
        setup_out(n(p, "setup_out").c_str(), config.fifo_depth),
        tapped(n(p, "tapped").c_str(), config.fifo_depth),
        distributor(n(p, "distributor").c_str(), config, frame),
        out(config.units),
        out_cycle(config.units) {
    setup.in(input);
    setup.out(setup_out);
    distributor.in(tap ? tapped : setup_out);
    if (tap) {
      sc_core::sc_spawn([this] {
        for (;;) {
          SetupPacket pk = setup_out.read();
          setup_packets.push_back(pk);
          tapped.write(pk);
        }
      });
    }
    for (unsigned u = 0; u < config.units; ++u) {
      const std::string s = std::to_string(u);
      jobs.push_back(
          std::make_unique<Fifo<SetupPacket>>(n(p, "jobs" + s).c_str(), config.fifo_depth));
      units.push_back(
          std::make_unique<TileRasterizer>(n(p, "rasterizer" + s).c_str(), config, frame, u));
      stamps.push_back(
          std::make_unique<Fifo<StampBatch>>(n(p, "stamps" + s).c_str(), config.fifo_depth));
      distributor.out[u](*jobs[u]);
      units[u]->in(*jobs[u]);
      units[u]->out(*stamps[u]);
      sc_core::sc_spawn([this, u] {
        for (;;) {
          StampBatch b = stamps[u]->read();
          out[u].push_back(std::move(b));
          out_cycle[u].push_back(
              static_cast<uint64_t>(std::llround(sc_core::sc_time_stamp() / config.cycle())));
        }
      });
    }
  }

  void feed(const std::vector<ClippedPrimitive>& tokens) {
    sc_core::sc_spawn([this, tokens] {
      for (const ClippedPrimitive& t : tokens) input.write(t);
    });
  }

  // Every covered pixel of primitive `id`, over all units, as (x, y); a pixel
  // produced twice shows as a count above 1.
  std::map<std::pair<int, int>, int> pixels(int64_t id) const {
    std::map<std::pair<int, int>, int> got;
    const int sw = static_cast<int>(config.stamp[0]);
    for (const auto& unit : out) {
      for (const StampBatch& b : unit) {
        if (b.kind != PacketKind::work || b.primitive->primitive_id != id) continue;
        for (const Stamp& s : b.stamps) {
          for (int bit = 0; bit < 64; ++bit) {
            if (s.mask >> bit & 1) ++got[{s.x + bit % sw, s.y + bit / sw}];
          }
        }
      }
    }
    return got;
  }

  void stall_everything(uint64_t seed) {
    const sc_core::sc_time c = config.cycle();
    input.set_stalls(RandomStalls(input.basename(), seed + 1, 0.3, 7, c));
    setup_out.set_stalls(RandomStalls(setup_out.basename(), seed + 2, 0.3, 7, c));
    tapped.set_stalls(RandomStalls(tapped.basename(), seed + 3, 0.3, 7, c));
    for (unsigned u = 0; u < config.units; ++u) {
      jobs[u]->set_stalls(RandomStalls(jobs[u]->basename(), seed + 10 + u, 0.3, 9, c));
      stamps[u]->set_stalls(RandomStalls(stamps[u]->basename(), seed + 100 + u, 0.4, 13, c));
    }
  }
};

// A triangle in window coordinates, as the clipper sends it: vertex i at
// (xy[2i], xy[2i + 1]), with depths, 1/w and varyings distinct per vertex.
inline ClippedPrimitive window_triangle(int64_t id, uint32_t draw, std::array<float, 6> xy) {
  ClippedPrimitive t;
  t.draw_id = draw;
  t.primitive_id = id;
  for (int i = 0; i < 3; ++i) {
    t.v[i].x = xy[2 * i];
    t.v[i].y = xy[2 * i + 1];
    t.v[i].z = 0.1f * static_cast<float>(i + 1) + 0.01f * static_cast<float>(id % 7);
    t.v[i].inv_w = 1.0f + static_cast<float>(i);
    // Colour (components 0-3) and three more, distinct per vertex, so a
    // vertex swapped without its varyings shows; setup passes them all.
    const std::array<float, 7> v = {0.1f * i, 0.2f,      0.3f,    static_cast<float>(id),
                                    1.0f * i, -2.0f * i, 0.5f + i};
    std::copy(v.begin(), v.end(), t.v[i].varyings_over_w.begin());
  }
  t.flat_varyings[0] = 0.5f;
  t.flat_varyings[1] = 0.25f;
  t.flat_varyings[2] = 0.125f;
  t.flat_varyings[3] = 1.0f;
  t.flat_varyings[6] = 3.0f;
  return t;
}

// A control token (clear, end of frame). Not `control`: hw/packet_fields.h
// puts a `control` in gpusim.
inline ClippedPrimitive control_primitive(PacketKind k) {
  ClippedPrimitive t;
  t.kind = k;
  return t;
}

}  // namespace test
}  // namespace gpusim
