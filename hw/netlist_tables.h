// The GPU's netlist (stages/topology.h) as the trace files and stats.json
// number it: stats.json's names, in pipeline order (the front end, then
// each unit's stages, then a stage the units feed).
#pragma once

#include <cstddef>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace gpusim {

struct NetlistTables {
  static constexpr int kHost = -1;  // the writer of "commands"
  struct Stage {
    std::string name;                  // "primitive_setup", "depth_test_2"
    std::string kind;                  // the name without the unit suffix
    int unit = -1;                     // -1: front end
    std::vector<int> inputs, outputs;  // indices into fifos
    // How a trace shows it (StageTrace, hw/stage_spec.h): what a record of
    // it is ("draw", "batch", "primitive", "tile job", "stamp batch"), why a
    // primitive ending here went no further by its kind ("point", "line",
    // "triangle"; "" when it ended where it should), and which fragment
    // records come from it ("": none, "test": depth-tested, "write":
    // written to the colour buffer).
    std::string item = "primitive";
    std::map<std::string, std::string> drops;
    std::string fragments;
  };
  struct Fifo {
    std::string name;
    std::string kind;  // the name without the unit suffix
    size_t depth = 0;
    int writer = kHost;  // index into stages, or kHost
    int reader = -1;
    int unit = -1;
  };
  // A client of the memory, in client number order (its place on the
  // arbiter's round-robin, hw/memory.h).
  struct MemoryClient {
    std::string name;  // the memory's name for it, its stage's
    int stage = -1;    // index into stages
  };
  // A side channel that is not a FIFO (the hierarchical-Z updates from a
  // unit's depth test to its rasterizer, hw/hierarchical_z.h).
  struct Link {
    std::string name;              // "hz_update_0"
    std::string kind;              // the name without the unit suffix
    int writer = -1, reader = -1;  // indices into stages
    int unit = -1;
  };
  std::vector<Stage> stages;
  std::vector<Fifo> fifos;
  std::vector<MemoryClient> memory_clients;
  std::vector<Link> links;
};

// {"stages": [{index, name, kind, unit, inputs, outputs, item, drops,
// fragments}], "fifos": [{index, name, kind, depth, writer, reader, unit}],
// "memory_clients": [{index, name, stage}], "links": [{index, name, kind,
// writer, reader, unit}]}: names for the endpoints, null for a front-end
// unit, "host" for the host. The tables of
// a trace's manifest.json and of stats.json's timing.netlist
// (docs/traces.md), read back by traces/trace_reader.h.
nlohmann::ordered_json to_json(const NetlistTables& t);

}  // namespace gpusim
