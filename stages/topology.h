// The GPU's netlist as data: every stage and every FIFO is registered once,
// by Topology::connect(), with its kind, its unit and its endpoints. Whatever
// needs the pipeline's shape walks this instead of a list of its own:
// stats.json (stats_json), trace tables and probes (trace_tables,
// attach_trace), the testbench's random stalls and fault injection (fifos(),
// find_fifo), the watchdog and its hang report, the progress count, and the
// conservation rules that follow from producer -> FIFO -> consumer edges
// (testbench/sim/). Adding a stage means one connect() per FIFO it touches.
//
// Names: a FIFO of kind `k` is named k (front end) or k_<unit>, like stages
// (PipelineStage::instance_name); the kind is the key of its depth in the
// configuration (fifo_depths.k), the stage's kind the key of its cost.
//
// Order: stages are listed in pipeline order whatever order they were
// registered in: front end first, then unit by unit, each by its distance
// from the host along the FIFOs, then a shared stage the units feed (the
// resolve); a FIFO comes where its reader does.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "hw/fifo.h"
#include "hw/gpu_config.h"
#include "hw/pipeline_stage.h"
#include "hw/trace_probe.h"

namespace gpusim {

class Topology {
 public:
  static constexpr int kHost = -1;  // the writer of the FIFOs the host feeds

  struct StageNode {
    PipelineStage* stage = nullptr;
    std::vector<size_t> inputs, outputs;  // indices into fifos()
    int rank = 0;                         // FIFOs between the host and the stage
  };
  struct FifoNode {
    std::string name;  // "rasterizer_to_depth_2"
    std::string kind;  // "rasterizer_to_depth"
    int unit = -1;
    FifoChannel* channel = nullptr;
    int writer = kHost;  // index into stages(), or kHost
    int reader = -1;
    std::function<void(TraceProbes&, size_t)> attach_probe;  // the probe for its packet type
  };

  explicit Topology(const GpuConfig& config) : m_config(config) {}
  Topology(const Topology&) = delete;
  Topology& operator=(const Topology&) = delete;

  // Creates the FIFO `kind` of `unit` (-1: front end) with its configured
  // depth, owned here, and binds `writer`'s port `out` and `reader`'s port
  // `in` to it; a null writer is the host. Stages are registered on first
  // use. Elaboration only; finish() when every FIFO is connected.
  template <typename T>
  Fifo<T>& connect(const std::string& kind, int unit, PipelineStage* writer,
                   sc_core::sc_port_b<FifoOutIf<T>>* out, PipelineStage& reader,
                   FifoInPort<T>& in) {
    auto fifo = std::make_unique<Fifo<T>>(PipelineStage::instance_name(kind, unit).c_str(),
                                          m_config.fifo_depth_of(kind));
    Fifo<T>& f = *fifo;
    if (out != nullptr) (*out)(f);
    in(f);
    FifoNode n;
    n.name = f.basename();
    n.kind = kind;
    n.unit = unit;
    n.channel = &f;
    n.attach_probe = [&f](TraceProbes& probes, size_t index) {
      f.set_probe(probes.fifo_probe(index, ProbeTag<T>{}));
    };
    add_fifo(std::move(n), std::move(fifo), writer, reader);
    return f;
  }

  // Sorts the netlist into pipeline order, checks it against the
  // configuration (every stage and FIFO kind of the topology has a cost and
  // a depth there, and the configuration names nothing the topology lacks:
  // std::logic_error otherwise), and adds each stage's stalled_cycles and
  // starved_cycles to its statistics. Call once, after the last connect().
  void finish();

  const std::vector<StageNode>& stages() const { return m_stages; }
  const std::vector<FifoNode>& fifos() const { return m_fifos; }
  const FifoNode* find_fifo(const std::string& name) const;
  // Distinct kinds in pipeline order.
  std::vector<std::string> stage_kinds() const;
  std::vector<std::string> fifo_kinds() const;

  // The tables the trace files index (docs/traces.md), and the probes of a
  // recorder attached to every FIFO by those indices.
  NetlistTables trace_tables() const;
  void attach_trace(TraceProbes& probes) const;

  // Temporal decoupling (hw/pipeline_stage.h): sets every decouplable()
  // stage decoupled and puts each FIFO one of them touches in stamped mode
  // (hw/fifo.h) with the clocks of its decoupled sides. Before the
  // simulation starts, on a netlist with no trace probe attached; the
  // frames and statistics are the same bits either way. Returns the number
  // of stages decoupled.
  size_t decouple();

  // Items written and read so far over every FIFO.
  uint64_t items_moved() const;

  // {"stages": {name: counters}, "fifos": {name: figures}}, times in cycles.
  nlohmann::json stats_json() const;
  // What every counter means: {"stages": {kind: {counter: {unit,
  // description}}}, "fifos": {field: {unit, description}}}.
  nlohmann::json descriptions() const;

 private:
  void add_fifo(FifoNode node, std::shared_ptr<FifoChannel> fifo, PipelineStage* writer,
                PipelineStage& reader);
  int stage_index(PipelineStage& stage);

  const GpuConfig& m_config;
  std::vector<StageNode> m_stages;
  std::vector<FifoNode> m_fifos;
  std::vector<std::shared_ptr<FifoChannel>> m_owned;
  bool m_finished = false;
};

}  // namespace gpusim
