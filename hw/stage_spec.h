// What a pipeline stage is, declared once in the stage's own files (gem5's
// SimObject params, VCML's properties): its kind, where it sits, its default
// cost and why, what its token counters count, and the FIFOs it reads. The
// stage's .cpp registers the spec at static initialisation:
//
//   const StageSpec& Clipper::spec() {
//     static const StageSpec s{"clipper", StagePlacement::front_end, ...};
//     return s;
//   }
//   GPUSIM_REGISTER_STAGE(Clipper);
//
// and everything that lists the pipeline's parts follows from the registry:
// the configuration's stage and FIFO keys and their defaults
// (hw/gpu_config.h), `gpusim config --defaults`, the generated tables of
// docs/gpu-config.md and testbench/configs/default.json, and the netlist's
// check that it elaborated what the configuration names. Nothing in hw/
// names a stage; the order of the pipeline is the elaborated netlist's
// (stages/topology.h), the registry's is by kind.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "hw/gpu_config.h"

namespace gpusim {

enum class StagePlacement {
  front_end,  // one instance, before the units
  per_unit,   // one instance per raster unit, named <kind>_<unit>
  shared,     // one instance the units feed (the resolve)
};

// What a stage's conservation rule sees (testbench/sim/conservation.h
// implements it over a run's statistics): its own counters and those of the
// stages and FIFOs around it, the frame's totals, and the two checks, each
// violation collected with where it happened.
class ConservationLedger {
 public:
  struct Frame {
    uint64_t draws = 0;      // in the frame
    uint64_t slots = 0;      // vertex slots of its draws
    uint64_t triangles = 0;  // assembled from them, by kind
    uint64_t lines = 0;
    uint64_t points = 0;
    uint64_t control = 0;  // control tokens every stage forwards (clears + the end of frame)
    uint64_t units = 0;
    // The frame's clears (the frame clear and the draw list's), and of them
    // those of the colour and of the depth buffer.
    uint64_t clears = 0, color_clears = 0, depth_clears = 0;
  };
  struct Output {
    std::string fifo, reader;  // names: "distributor_to_rasterizer_1", "tile_rasterizer_1"
    int unit = -1;
  };
  virtual ~ConservationLedger() = default;

  virtual const std::string& name() const = 0;  // the stage's: "depth_test_2"
  virtual const Frame& frame() const = 0;
  virtual uint64_t get(const std::string& counter) = 0;  // the stage's own
  virtual uint64_t stage(const std::string& stage, const std::string& counter) = 0;
  virtual uint64_t fifo(const std::string& fifo, const std::string& field) = 0;
  // The nearest stage of `kind` before this one along the first inputs,
  // whatever stages were put between them; "host" when there is none.
  virtual std::string upstream(const std::string& kind) const = 0;
  virtual std::vector<Output> outputs() const = 0;
  // "<where>: <a> = <va>, but <b> = <vb>" unless they are equal; "... exceeds
  // ..." unless va <= vb. `where` is the stage unless given.
  virtual void check_equal(const std::string& where, const std::string& a, uint64_t va,
                           const std::string& b, uint64_t vb) = 0;
  virtual void check_at_most(const std::string& where, const std::string& a, uint64_t va,
                             const std::string& b, uint64_t vb) = 0;
  void equal(const std::string& a, uint64_t va, const std::string& b, uint64_t vb) {
    check_equal(name(), a, va, b, vb);
  }
  void at_most(const std::string& a, uint64_t va, const std::string& b, uint64_t vb) {
    check_at_most(name(), a, va, b, vb);
  }
};
// A stage's own conservation rules: how its counters must balance with its
// FIFOs', its neighbours' and the frame's when a run ends.
using ConservationRule = void (*)(ConservationLedger&);

// How a trace shows a stage (docs/traces.md): what one transactions.bin
// record of it is, why a primitive whose last record is at it went no
// further, and which fragment probe calls come from it.
enum class TraceItem : uint8_t {
  draw,         // a draw and the primitives it assembles
  slot_batch,   // a batch of vertex slots and the primitives they assemble
  primitive,    // one primitive after clipping
  tile_job,     // a primitive in a unit: its record counts the stamps it produced
  stamp_batch,  // the stamps one primitive covers in one tile
};
// "draw", "batch", "primitive", "tile job", "stamp batch"; a new enumerator
// adds its name there.
const char* to_string(TraceItem item);
// Which fragment records a stage makes (fragments.bin): none; `test`, the
// fragments it depth-tests, each with its outcome; `write`, the fragments it
// writes to the colour buffer.
enum class FragmentSite : uint8_t { none, test, write };
const char* to_string(FragmentSite site);  // "", "test", "write"
struct StageTrace {
  TraceItem item = TraceItem::primitive;
  // By the primitive's kind (point, line, triangle): nullptr says only that
  // it left the pipeline here; "" that it ended where it should.
  std::array<const char*, 3> drops{nullptr, nullptr, nullptr};
  FragmentSite fragments = FragmentSite::none;
};

// A row of docs/architecture.md's "Cost of each stage" (`gpusim config
// --markdown costs`): what a token costs the stage, in what case.
struct StageCostRow {
  std::string when;   // the case ("Bresenham line"); empty: every token
  std::string busy;   // busy cycles per token: "`ii` × stamps + memory stall"
  std::string notes;  // how, and what it leaves out
};

struct StageSpec {
  std::string kind;  // configuration key, stats.json and trace name: "tile_rasterizer"
  StagePlacement placement = StagePlacement::front_end;
  // Elaborated only in frames that need it; its keys are accepted always.
  bool optional = false;
  StageCost cost;           // the default ii and latency
  std::string item;         // what one ii is spent on: "stamp"
  std::string cost_reason;  // why the default cost, one line
  std::string tokens_in;    // what the tokens_in counter counts: "setup packets read"
  std::string tokens_out;
  // The FIFO kinds the stage reads, by the name of its input port's FIFO
  // (the key of fifo_depths): a FIFO belongs to its reader, so putting a
  // stage in front of another renames nothing.
  std::vector<std::string> inputs;
  // Its rules beyond the ones every stage obeys (tokens in and out equal its
  // FIFOs' items); none when it has no counters of its own to balance.
  ConservationRule conservation = nullptr;
  StageTrace trace;
  std::vector<StageCostRow> cost_table;
  // Kinds it was called before ("triangle_setup"): read for one release in
  // configuration keys, --trace-stages and stats diff, with a deprecation
  // warning (StageRegistry::current_name).
  std::vector<std::string> former_kinds = {};
};

class StageRegistry {
 public:
  // Registers a spec; a kind or FIFO kind registered twice is a programming
  // error (std::logic_error).
  static void add(const StageSpec& spec);
  // nullptr when no stage of that kind is linked in.
  static const StageSpec* find(std::string_view kind);
  // Every registered spec, by kind.
  static std::vector<const StageSpec*> all();
  // Every FIFO kind some stage reads, sorted.
  static std::vector<std::string> fifo_kinds();
  // Stage kinds and FIFO kinds that a frame may leave out: the optional
  // stages and the FIFOs they read. Sorted.
  static std::vector<std::string> optional_kinds();
  // A stage kind or instance name under a renamed stage's former kind
  // ("triangle_setup", or a unit's "<former>_2") under its current one;
  // empty when `name` is no former name.
  static std::string current_name(std::string_view name);
};

// The one-line warning that `where` ("stages", "--trace-stages") gave a
// former stage name and the current one was read instead, on stderr once
// per former name and place in a process.
void warn_former_name(const std::string& where, const std::string& former,
                      const std::string& current);

// Registers a stage's spec when the program starts.
struct StageRegistration {
  explicit StageRegistration(const StageSpec& spec) { StageRegistry::add(spec); }
};

#define GPUSIM_REGISTER_STAGE(Class)                                           \
  static const ::gpusim::StageRegistration gpusim_stage_registration_##Class { \
    Class::spec()                                                              \
  }

}  // namespace gpusim
