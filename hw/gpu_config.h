// The one configuration of the cycle model: clock, unit count, tile and stamp
// sizes, FIFO depths, per-stage costs, memory timing. Loaded from a JSON file
// (docs/gpu-config.md), passed by const reference to every module, and dumped
// with the results (to_json) so statistics always carry the configuration
// that produced them.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <systemc>
#include <utility>
#include <vector>

#include "hw/input_error.h"

namespace gpusim {

// Cost of a pipelined stage: it accepts a new item every `ii` cycles
// (initiation interval) and its result leaves `latency` cycles after the item
// was accepted.
struct StageCost {
  unsigned ii = 1;
  unsigned latency = 0;

  bool operator==(const StageCost& o) const { return ii == o.ii && latency == o.latency; }
  bool operator!=(const StageCost& o) const { return !(*this == o); }
};

// The one memory shared by every client (see hw/memory.h for the model).
struct MemoryConfig {
  unsigned latency = 20;             // cycles from the end of the bus transfer to completion
  unsigned bytes_per_cycle = 32;     // data bus width of one channel, shared by all clients
  unsigned channels = 4;             // independent buses, addresses interleaved across them
  unsigned interleave_bytes = 1024;  // bytes on one channel before the next (power of two, >= 32)

  bool operator==(const MemoryConfig& o) const {
    return latency == o.latency && bytes_per_cycle == o.bytes_per_cycle && channels == o.channels &&
           interleave_bytes == o.interleave_bytes;
  }
  bool operator!=(const MemoryConfig& o) const { return !(*this == o); }
};

// Framebuffer surfaces: layout and transfers of the colour and depth tiles
// (hw/surface_layout.h, docs/architecture.md "Memory").
struct SurfaceConfig {
  bool tiled = true;                  // each screen tile one contiguous block
  unsigned max_burst_bytes = 1024;    // a tiled tile transfer splits into bursts of at most this
  bool skip_overwritten_fill = true;  // no read for a miss on a tile the batch overwrites

  bool operator==(const SurfaceConfig& o) const {
    return tiled == o.tiled && max_burst_bytes == o.max_burst_bytes &&
           skip_overwritten_fill == o.skip_overwritten_fill;
  }
  bool operator!=(const SurfaceConfig& o) const { return !(*this == o); }
};

// Lossless tile compression in the tile caches (hw/tile_codec.h); needs tiled surfaces.
struct CompressionConfig {
  bool depth = true;
  bool colour = true;
  unsigned compressor_latency = 8;    // cycles before an encoded write-back leaves
  unsigned decompressor_latency = 8;  // cycles after a compressed fill arrives

  bool operator==(const CompressionConfig& o) const {
    return depth == o.depth && colour == o.colour && compressor_latency == o.compressor_latency &&
           decompressor_latency == o.decompressor_latency;
  }
  bool operator!=(const CompressionConfig& o) const { return !(*this == o); }
};

// Hierarchical Z (stages/tile_rasterizer.h, "Hierarchical Z"): a per-unit
// [min, max] of the stored depth per screen tile, tested by the rasterizer
// before it walks a tile and kept exact by updates from the depth test.
struct HierarchicalZConfig {
  bool enabled = true;
  unsigned access_latency = 5;  // cycles of latency the HZ test adds to a tile's batch (pipelined)
  unsigned update_latency = 4;  // cycles before a depth test update is visible to the rasterizer

  bool operator==(const HierarchicalZConfig& o) const {
    return enabled == o.enabled && access_latency == o.access_latency &&
           update_latency == o.update_latency;
  }
  bool operator!=(const HierarchicalZConfig& o) const { return !(*this == o); }
};

// Texture units (stages/texture_unit.h): each unit's texture cache and the
// fragment FIFO between its address and filter stages. The cache's defaults
// are GPGPU-Sim's L1 texture cache (32 sets x 4 ways x 128-byte lines, 16
// KiB), the FIFO's depth the order of Igehy, Eldridge and Proudfoot's
// (1998) fragment FIFO, which hides a memory latency of about as many
// fragments.
struct TextureConfig {
  unsigned cache_sets = 32;
  unsigned cache_ways = 4;
  unsigned cache_line_bytes = 128;
  unsigned prefetch_fragments = 64;  // fragments addressed ahead of the filter

  bool operator==(const TextureConfig& o) const {
    return cache_sets == o.cache_sets && cache_ways == o.cache_ways &&
           cache_line_bytes == o.cache_line_bytes && prefetch_fragments == o.prefetch_fragments;
  }
  bool operator!=(const TextureConfig& o) const { return !(*this == o); }
};

struct GpuConfig {
  double clock_mhz = 1000.0;
  unsigned units = 4;                   // tile rasterizer units
  unsigned tile_size = 16;              // square screen tile owned by one unit, in pixels
  std::array<unsigned, 2> stamp{4, 4};  // pixels (x, y) evaluated per cycle by one unit
  unsigned fifo_depth = 16;             // depth of every FIFO without an override
  // Per-FIFO overrides of fifo_depth, keyed by a name of fifo_names(). Only
  // overrides are stored; fifo_depth_of() resolves.
  std::map<std::string, unsigned, std::less<>> fifo_depths;
  // Cost of every stage of stage_names(); a default-constructed config holds
  // every registered stage at the default its spec declares.
  std::map<std::string, StageCost, std::less<>> stages = default_stage_costs();
  MemoryConfig memory;
  SurfaceConfig surfaces;
  CompressionConfig compression;
  HierarchicalZConfig hierarchical_z;
  TextureConfig texture;
  unsigned vertex_cache_entries = 32;  // post-transform vertex cache; 0 disables it
  unsigned tile_cache_entries = 16;    // framebuffer tiles cached per unit, per buffer
  // Multisampling: samples of a pixel the rasterizer's edge core, the depth
  // test and the ROP handle in one pass over a stamp (a stamp of N samples
  // per pixel costs ii * ceil(N / samples_per_pass)), and the resolve per
  // output stamp.
  unsigned samples_per_pass = 4;
  // The tile rasterizer's tile test runs one tile ahead of its stamp
  // evaluation (a coarse stage in front of the fine one), so a tile whose
  // stamps take cycles costs only those; off: 1 cycle per tile visited plus
  // its stamps (stages/tile_rasterizer.h, cost model).
  bool tile_test_overlap = true;
  // Phong shading (docs/pipeline-spec.md, section 9b): each interpolator's
  // per-pixel lighting unit spends, per lit pixel, cycles_per_pixel on
  // renormalising the normal and clamping the colour, plus cycles_per_light
  // per light (direction, attenuation, half vector, pow), one pixel at a time.
  unsigned lighting_cycles_per_pixel = 1;
  unsigned lighting_cycles_per_light = 2;
  uint64_t watchdog_cycles = 1000000;  // no stage progress for this long stops the run

  // The configurable stages and FIFOs: the kinds the registered stages
  // declare (hw/stage_spec.h), sorted; the netlist (stages/topology.h)
  // checks them when the GPU is elaborated, and gives their pipeline order.
  static std::vector<std::string> stage_names();
  static std::vector<std::string> fifo_names();
  static std::map<std::string, StageCost, std::less<>> default_stage_costs();
  // Passes over a stamp of n samples per pixel: ceil(n / samples_per_pass).
  unsigned sample_passes(unsigned n) const { return (n + samples_per_pass - 1) / samples_per_pass; }

  // Every mechanism of the memory system and the rasterizer that issue #11
  // added, off: one memory channel, row-major surfaces moved a row per
  // request, fills for overwritten tiles, no compression, no hierarchical Z,
  // a serial tile test. The model as it was before them, whose costs many
  // cycle tests derive by hand; the defaults above are the realistic
  // configuration (docs/gpu-config.md, "The default configuration").
  static GpuConfig baseline();

  // Lookups by a name of stage_names() / fifo_names(); an unknown name is a
  // programming error and throws std::invalid_argument.
  const StageCost& stage(std::string_view name) const;
  unsigned fifo_depth_of(std::string_view name) const;

  // The clock period, rounded to the SystemC time resolution (1 ps unless the
  // testbench changes it), and n periods as an exact multiple of it.
  sc_core::sc_time cycle() const;
  sc_core::sc_time cycles(uint64_t n) const;

  // Equality of the resolved configurations: a FIFO left at the default depth
  // equals one overridden with the same depth, so a config equals its round
  // trip through to_json().
  bool operator==(const GpuConfig& o) const;
  bool operator!=(const GpuConfig& o) const { return !(*this == o); }
};

// Strict: unknown keys, wrong types and out-of-range values throw InputError
// with one line "<source_name>: <json path>: <problem>"; absent keys keep
// their defaults.
GpuConfig gpu_config_from_json(const nlohmann::json& j, const std::string& source_name);

// Reads and validates a file. Malformed JSON throws InputError
// "<path>: line L, column C: <message>". Comments (// and /* */) are allowed.
// The path "-" reads standard input, named "standard input" in messages.
GpuConfig load_gpu_config(const std::string& path);

// The parsed JSON of a configuration file (the same reading and errors as
// load_gpu_config, without the validation).
nlohmann::json load_gpu_config_json(const std::string& path);

// One command-line override, `KEY=VALUE` (gpusim run --set): KEY is a dotted
// path into the configuration object (stages.primitive_setup.ii), VALUE is
// JSON when it parses as JSON, else a string. Sets the value in `j`, creating
// the objects on the way (an intermediate value that is not an object is
// replaced by one; validation then reports it). A malformed assignment (no
// '=', an empty key or key segment) throws InputError "<source>: <problem>".
void apply_config_override(nlohmann::json& j, const std::string& assignment,
                           const std::string& source);

// The file's JSON (`base`, already valid) with each override applied in
// order, validated: an invalid result throws InputError
// "<source>: <json path>: <problem>" where <source> is the override whose
// key is the JSON path at fault or holds it ("--set stages.clipper.ii=0"),
// the last of them when several are, else every override given ("--set a=1
// --set b=2", as together they made the configuration invalid). Each
// override is "--set KEY=VALUE" or any other source name paired with its
// assignment (the --units shorthand is {"--units 2", "units=2"}).
struct ConfigOverride {
  std::string source;      // "--set units=2", "--units 2"
  std::string assignment;  // "units=2"
};
GpuConfig gpu_config_with_overrides(nlohmann::json base,
                                    const std::vector<ConfigOverride>& overrides);

// Every value resolved: all stages and the depth of every FIFO.
nlohmann::json to_json(const GpuConfig& c);
// The same with the keys in the file format's order (clock_mhz first), for
// files people read.
nlohmann::ordered_json to_ordered_json(const GpuConfig& c);

}  // namespace gpusim
