// Reads a trace directory written by `gpusim run --trace DIR`
// (docs/traces.md): manifest.json, stats.json and the binary record files
// transactions.bin and fragments.bin. signals.vcd has its own reader
// (traces/vcd_reader.h).
//
// Opening a trace validates everything that can be checked without reading
// the records: the manifest's fields, and each binary file's magic, version,
// record size and length against the manifest's record count. A bad or
// truncated file is an InputError, one line naming the file, so every tool
// fails before printing half an answer. The records themselves are streamed
// in chunks: a 1080p frame's fragments need not fit in memory.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "traces/trace_records.h"

namespace gpusim {

// One entry of manifest.json's `stages`.
struct TraceStage {
  size_t index = 0;
  std::string name;                          // "tile_rasterizer_2"
  std::string kind;                          // "tile_rasterizer"
  int unit = -1;                             // -1: a front-end stage
  std::vector<std::string> inputs, outputs;  // FIFO names
  // How the trace shows it (hw/netlist_tables.h): what a record of it is,
  // why a primitive ending here went no further by its kind, and whose
  // fragment records come from it. Traces written before the fields: a
  // primitive, no reasons, none.
  std::string item = "primitive";
  std::map<std::string, std::string> drops;
  std::string fragments;
};

// One entry of manifest.json's `fifos`.
struct TraceFifo {
  size_t index = 0;
  std::string name;
  std::string kind;  // "rasterizer_to_depth": the configuration's name (fifo_depths)
  uint64_t depth = 0;
  std::string writer;  // a stage name, or "host"
  std::string reader;
  int unit = -1;
};

// manifest.json's `filters`: each absent (null) when not given.
struct TraceFilters {
  std::optional<std::vector<std::string>> stages;
  // [start, end): either side open.
  std::optional<std::pair<std::optional<uint64_t>, std::optional<uint64_t>>> window;
  std::optional<std::pair<int64_t, int64_t>> prims;  // [a, b], inclusive

  bool any() const { return stages || window || prims; }
  // "--trace-stages primitive_setup,rop --trace-window 1000:", or "none".
  std::string describe() const;
  bool keeps_stage(const std::string& name) const;
};

struct TraceManifest {
  std::string scene;
  // The formats written (--trace-formats), of vcd, timeline, transactions,
  // fragments; all four in traces written before the choice existed.
  std::vector<std::string> formats;
  nlohmann::json config;
  double clock_mhz = 0.0;
  uint64_t cycle_ps = 0;
  uint64_t cycles = 0;  // the frame's length
  int width = 0, height = 0, tile_size = 0, tiles_x = 0, tiles_y = 0;
  unsigned units = 0;
  TraceFilters filters;
  std::vector<TraceStage> stages;  // by index
  std::vector<TraceFifo> fifos;    // by index
  struct Draw {
    int64_t first_primitive_id = 0;
    uint64_t primitives = 0;
    // The draw's primitive type and polygon mode as in the scene file; ""
    // in traces written before lines and points (all triangles, filled).
    std::string primitive, polygon_mode;
  };

  std::vector<Draw> draws;
  bool recorded(const std::string& format) const;
  uint64_t transaction_records = 0;
  uint64_t fragment_records = 0;

  // The traced window [start, end) in cycles: the window filter clamped to
  // the frame, or the whole frame.
  std::pair<uint64_t, uint64_t> window() const;
  uint64_t primitives() const;  // primitive ids are 0 .. primitives() - 1
  // The draw holding primitive `prim` (its index in `draws`), or -1.
  int64_t draw_of(int64_t prim) const;
  // "triangle", "line" or "point": what the draw holding `prim` assembles
  // (a polygon-mode triangle is a triangle); "primitive" when not known.
  std::string prim_word(int64_t prim) const;
  const TraceStage* stage(const std::string& name) const;
  // The pipeline position of a stage kind: where its first stage comes in
  // `stages` (which the recorder writes in pipeline order); unknown kinds
  // sort last.
  int pipeline_rank(const std::string& kind) const;
  // The kinds of a raster unit's stages, in pipeline order.
  std::vector<std::string> unit_kinds() const;
  const TraceFifo* fifo(const std::string& name) const;
};

// The stages and FIFOs of `netlist` ({"stages": [...], "fifos": [...]}, as
// hw/netlist_tables.h writes them) appended to m.stages and m.fifos; a
// malformed table throws InputError "<source>: <where>.stages[i].name: ...".
void read_netlist(const nlohmann::json& netlist, const std::string& source,
                  const std::string& where, TraceManifest& m);

class TraceReader {
 public:
  // Reads manifest.json and checks the headers and lengths of
  // transactions.bin and fragments.bin, those recorded; throws InputError on
  // any problem.
  explicit TraceReader(const std::string& dir);

  const std::string& dir() const { return m_dir; }
  std::string path(const std::string& file) const { return m_dir + "/" + file; }
  const TraceManifest& manifest() const { return m_manifest; }

  // Throws InputError when the trace was recorded without `format` (one of
  // vcd, timeline, transactions, fragments): "<dir>: fragments.bin was not
  // recorded (--trace-formats vcd,timeline); rerun gpusim run --trace with
  // fragments in --trace-formats".
  void require(const std::string& format) const;

  // Every record in file order (transactions: by cycle_out). A record naming
  // a stage the manifest does not have is an InputError, as is a trace
  // recorded without the file (require).
  void for_each_transaction(const std::function<void(const TransactionRecord&)>& fn) const;
  void for_each_fragment(const std::function<void(const FragmentRecord&)>& fn) const;

  // stats.json, parsed (InputError when missing or malformed).
  nlohmann::json stats() const;

 private:
  // Streams `count` records of `size` bytes after the 16-byte header.
  void for_each_record(const std::string& file, uint64_t count, size_t size,
                       const std::function<void(const uint8_t*, uint64_t)>& fn) const;

  std::string m_dir;
  TraceManifest m_manifest;
};

}  // namespace gpusim
