#include "stages/resolve.h"

#include <algorithm>
#include <cstring>
#include <string>

#include "hw/pixel_formats.h"

namespace gpusim {

namespace {

// Conservation (testbench/sim/conservation.h): how its counters balance.
void conserve(ConservationLedger& l) {
  const ConservationLedger::Frame& f = l.frame();
  // One token per unit per control token; forwards nothing.
  l.equal("tokens_in", l.get("tokens_in"), "control tokens x units", f.control * f.units);
  l.equal("frames", l.get("frames"), "frames run", 1);
}

}  // namespace

const StageSpec& Resolve::spec() {
  static const StageSpec s{
      "resolve",
      StagePlacement::shared,
      /*optional=*/true,
      {/*ii=*/1, /*latency=*/4},
      "output stamp",
      "multisampled or supersampled frames only: the box filter at the end of "
      "the frame, one output stamp per pass of `samples_per_pass` samples; "
      "reading the samples and writing the image go through the memory",
      "control tokens read (one per unit and token)",
      "tokens forwarded (none)",
      {"rop_to_resolve"},
      &conserve,
      StageTrace{},
      {{"",
        "per output tile: read stall + `ii` × output stamps × passes; at the end, the last writes",
        "Multisampled or supersampled frames only: starts when every unit's `end_of_frame` has "
        "arrived, filters the output tile by tile (below), and reports the frame done when its "
        "last write completes. A clear costs `ii`."}}};
  return s;
}
GPUSIM_REGISTER_STAGE(Resolve);

Resolve::Resolve(sc_core::sc_module_name name, const GpuConfig& config, const FrameState& frame)
    : PipelineStage(name, spec(), -1, config, frame), in("in", config.units), mem("mem") {
  SC_HAS_PROCESS(Resolve);
  SC_THREAD(run);
}

void Resolve::reset_state() {
  m_frame_done = false;
  m_surface = SurfaceLayout{};
}

void Resolve::run() {
  const FramebufferDesc& fb = m_frame.framebuffer;
  const int k = static_cast<int>(fb.supersample);
  const int tile = static_cast<int>(m_config.tile_size);
  const int tiles_x = (fb.width / k + tile - 1) / tile, tiles_y = (fb.height / k + tile - 1) / tile;
  m_surface =
      SurfaceLayout(m_config.surfaces.tiled, fb.width, fb.height,
                    color_bytes_per_pixel(fb.color_format) * fb.samples, tile, m_config.units);
  for (;;) {
    // Every unit passes on the same tokens in the same order.
    PacketKind kind = PacketKind::work;
    for (auto& port : in) kind = receive(port).kind;
    m_frame_done = false;
    if (kind != PacketKind::end_of_frame) {
      work(m_cost.ii);  // a clear: the ROPs cleared the samples
      continue;
    }
    for (int ty = 0; ty < tiles_y; ++ty) {
      for (int tx = 0; tx < tiles_x; ++tx) work(resolve_tile(tx, ty));
    }
    // The last tiles' writes.
    const sc_core::sc_time writes = mem.wait_round().writes;
    const sc_core::sc_time now = sc_core::sc_time_stamp();
    const uint64_t stall = writes > now ? ((writes - now).value() + m_cycle - 1) / m_cycle : 0;
    m_memory_stall_cycles += stall;
    work(stall);
    ++m_frames;
    m_frame_done = true;
    m_frame_done_event.notify(sc_core::SC_ZERO_TIME);
  }
}

uint64_t Resolve::resolve_tile(int tx, int ty) {
  const FramebufferDesc& fb = m_frame.framebuffer;
  const int k = static_cast<int>(fb.supersample);
  const unsigned samples = fb.samples;
  const int width = fb.width / k, height = fb.height / k;  // the output
  const int tile = static_cast<int>(m_config.tile_size);
  const int x0 = tx * tile, y0 = ty * tile;
  const int tw = std::min(tile, width - x0), th = std::min(tile, height - y0);
  const bool half = fb.color_format == ColorFormat::rgba16f;
  const size_t sample_bytes = color_bytes_per_pixel(fb.color_format);
  const size_t pixel_bytes = sample_bytes * samples;
  const size_t row_bytes = static_cast<size_t>(k) * static_cast<size_t>(tw) * pixel_bytes;

  // The k render-target rows of every output row, one request each.
  m_rows.resize(static_cast<size_t>(k) * static_cast<size_t>(th) * row_bytes);
  if (m_surface.tiled()) {
    read_tiles(k * tx, k * ty, k, row_bytes);
  } else {
    for (int j = 0; j < th * k; ++j) {
      const uint64_t y =
          static_cast<uint64_t>(k) * static_cast<uint64_t>(y0) + static_cast<uint64_t>(j);
      const uint64_t addr =
          m_frame.color_address +
          (y * static_cast<uint64_t>(fb.width) + static_cast<uint64_t>(k * x0)) * pixel_bytes;
      mem.read(addr, m_rows.data() + static_cast<size_t>(j) * row_bytes, row_bytes);
    }
  }
  const sc_core::sc_time reads = mem.wait_round().reads;
  const sc_core::sc_time now = sc_core::sc_time_stamp();
  const uint64_t stall = reads > now ? ((reads - now).value() + m_cycle - 1) / m_cycle : 0;
  m_memory_stall_cycles += stall;

  // The box filter (section 14), per output pixel and channel.
  const uint32_t n = static_cast<uint32_t>(k * k) * samples;
  m_out.resize(static_cast<size_t>(tw) * static_cast<size_t>(th) * sample_bytes);
  for (int j = 0; j < th; ++j) {
    for (int i = 0; i < tw; ++i) {
      uint8_t* out = m_out.data() + (static_cast<size_t>(j) * tw + i) * sample_bytes;
      for (int ch = 0; ch < 4; ++ch) {
        uint32_t sum = 0;
        float sum_f = 0.0f;
        bool first = true;
        for (int r = 0; r < k; ++r) {
          const uint8_t* row = m_rows.data() + static_cast<size_t>(j * k + r) * row_bytes;
          for (int c = 0; c < k; ++c) {
            const uint8_t* pixel = row + static_cast<size_t>(i * k + c) * pixel_bytes;
            for (unsigned s = 0; s < samples; ++s) {
              const uint8_t* v = pixel + s * sample_bytes;
              if (!half) {
                sum += v[ch];
              } else {
                const auto bits = static_cast<ColorChannel>(v[2 * ch] | v[2 * ch + 1] << 8);
                const float f = decode_color(ColorFormat::rgba16f, bits);
                sum_f = first ? f : sum_f + f;
                first = false;
              }
            }
          }
        }
        if (!half) {
          out[ch] = static_cast<uint8_t>((2 * sum + n) / (2 * n));
        } else {
          const ColorChannel h = encode_color(ColorFormat::rgba16f, sum_f / static_cast<float>(n));
          out[2 * ch] = static_cast<uint8_t>(h);
          out[2 * ch + 1] = static_cast<uint8_t>(h >> 8);
        }
      }
    }
  }
  const uint64_t stamps = static_cast<uint64_t>((tw + static_cast<int>(m_config.stamp[0]) - 1) /
                                                static_cast<int>(m_config.stamp[0])) *
                          static_cast<uint64_t>((th + static_cast<int>(m_config.stamp[1]) - 1) /
                                                static_cast<int>(m_config.stamp[1]));
  const uint64_t cycles = stall + m_cost.ii * stamps * m_config.sample_passes(n);

  // The output rows, posted: they leave when the tile is done.
  for (int j = 0; j < th; ++j) {
    const uint64_t addr =
        m_frame.resolve_address +
        (static_cast<uint64_t>(y0 + j) * static_cast<uint64_t>(width) + static_cast<uint64_t>(x0)) *
            sample_bytes;
    mem.write(addr, m_out.data() + static_cast<size_t>(j) * tw * sample_bytes, tw * sample_bytes,
              clock_cycles(cycles));
  }
  ++m_tiles;
  m_pixels += static_cast<uint64_t>(tw) * static_cast<uint64_t>(th);
  m_samples += static_cast<uint64_t>(tw) * static_cast<uint64_t>(th) * n;
  return cycles;
}

// Tiled colour buffer: render-target tiles [rx0, rx0 + k) x [ry0, ry0 + k)
// (those inside it), each one block in bursts, copied into m_rows' rows.
void Resolve::read_tiles(int rx0, int ry0, int k, size_t row_bytes) {
  const int tile = static_cast<int>(m_config.tile_size);
  const size_t pixel_bytes =
      color_bytes_per_pixel(m_frame.framebuffer.color_format) * m_frame.framebuffer.samples;
  const uint64_t burst = m_config.surfaces.max_burst_bytes;
  size_t total = 0;
  for (int j = 0; j < k && ry0 + j < m_surface.tiles_y(); ++j) {
    for (int i = 0; i < k && rx0 + i < m_surface.tiles_x(); ++i) {
      total += static_cast<size_t>(m_surface.tile_width(rx0 + i)) *
               static_cast<size_t>(m_surface.tile_height(ry0 + j)) * pixel_bytes;
    }
  }
  m_block.resize(total);
  size_t at = 0;
  for (int j = 0; j < k && ry0 + j < m_surface.tiles_y(); ++j) {
    for (int i = 0; i < k && rx0 + i < m_surface.tiles_x(); ++i) {
      const int w = m_surface.tile_width(rx0 + i), h = m_surface.tile_height(ry0 + j);
      const uint64_t bytes = static_cast<uint64_t>(w) * static_cast<uint64_t>(h) * pixel_bytes;
      const uint64_t addr = m_frame.color_address + m_surface.tile_offset(rx0 + i, ry0 + j);
      for (uint64_t off = 0; off < bytes; off += burst)
        mem.read(addr + off, m_block.data() + at + off, std::min(burst, bytes - off));
      // Row r of this tile is row j * tile + r of the output tile's rows, at
      // column i * tile.
      for (int r = 0; r < h; ++r) {
        std::memcpy(m_rows.data() + static_cast<size_t>(j * tile + r) * row_bytes +
                        static_cast<size_t>(i * tile) * pixel_bytes,
                    m_block.data() + at + static_cast<size_t>(r) * w * pixel_bytes,
                    static_cast<size_t>(w) * pixel_bytes);
      }
      at += bytes;
    }
  }
}

}  // namespace gpusim
