// The GPU's netlist as data: every stage and every FIFO is registered once,
// by Topology::connect(), with its kind, its unit and its endpoints. Whatever
// needs the pipeline's shape walks this instead of a list of its own:
// stats.json (add_stats), trace tables and probes (trace_tables,
// attach_trace), the testbench's random stalls and fault injection (fifos(),
// find_fifo), the watchdog and its hang report, the progress count, and the
// conservation rules that follow from producer -> FIFO -> consumer edges
// (testbench/sim/). Adding a stage means one connect() per FIFO it touches,
// and connect_memory() for a memory port; a side channel that is not a FIFO
// (the hierarchical-Z link) is connect_link().
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
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <typeindex>
#include <typeinfo>
#include <vector>

#include "hw/fifo.h"
#include "hw/gpu_config.h"
#include "hw/pipeline_stage.h"
#include "hw/trace_probe.h"

namespace gpusim {

// Stages put in the place of FIFOs when the GPU is elaborated: the FIFO's
// writer writes the new stage instead, and the new stage writes the FIFO
// (its own input is the FIFO kind its spec names). For tests and
// experiments (a pass-through, a delay line, a checker) that change the
// pipeline without editing stages/gpu.cpp.
class Interposers {
 public:
  template <typename T>
  struct Made {
    std::unique_ptr<PipelineStage> stage;
    FifoInPort<T>* in = nullptr;
    FifoOutPort<T>* out = nullptr;
  };
  // Makes the stage of one unit (-1: front end) for the GPU's configuration
  // and frame.
  template <typename T>
  using Factory = std::function<Made<T>(int unit, const GpuConfig&, const FrameState&)>;

  // Puts the stage `make` makes in the place of every FIFO of kind `fifo_kind`.
  template <typename T>
  void add(const std::string& fifo_kind, Factory<T> make) {
    m_factories.insert_or_assign(fifo_kind,
                                 Entry{typeid(T), std::make_shared<Factory<T>>(std::move(make))});
  }
  // The factory for `fifo_kind`, or nullptr; one whose items are not T is a
  // programming error (std::logic_error).
  template <typename T>
  const Factory<T>* find(const std::string& fifo_kind) const {
    const auto it = m_factories.find(fifo_kind);
    if (it == m_factories.end()) return nullptr;
    if (it->second.type != std::type_index(typeid(T))) {
      throw std::logic_error("Interposers: the stage for FIFO '" + fifo_kind +
                             "' carries another packet type");
    }
    return static_cast<const Factory<T>*>(it->second.factory.get());
  }

 private:
  struct Entry {
    std::type_index type;
    std::shared_ptr<void> factory;
  };
  std::map<std::string, Entry> m_factories;
};

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

  // `interposers` (optional) must outlive the elaboration.
  Topology(const GpuConfig& config, const FrameState& frame,
           const Interposers* interposers = nullptr)
      : m_config(config), m_frame(frame), m_interposers(interposers) {}
  Topology(const Topology&) = delete;
  Topology& operator=(const Topology&) = delete;

  // Creates the FIFO `kind` of `unit` (-1: front end) with its configured
  // depth, owned here, and binds `writer`'s port `out` and `reader`'s port
  // `in` to it; a null writer is the host. `kind` must be an input of the
  // reader's spec. Stages are registered on first use. An interposed stage
  // (Interposers) goes between the two, on two FIFOs; the FIFO returned is
  // the one `writer` writes. Elaboration only; finish() when every FIFO is
  // connected.
  template <typename T>
  Fifo<T>& connect(const std::string& kind, int unit, PipelineStage* writer,
                   sc_core::sc_port_b<FifoOutIf<T>>* out, PipelineStage& reader,
                   FifoInPort<T>& in) {
    const Interposers::Factory<T>* make =
        m_interposers != nullptr ? m_interposers->find<T>(kind) : nullptr;
    if (make == nullptr) return connect_fifo(kind, unit, writer, out, reader, in);
    Interposers::Made<T> made = (*make)(unit, m_config, m_frame);
    PipelineStage& stage = *made.stage;
    m_owned_stages.push_back(std::move(made.stage));
    if (stage.spec().inputs.size() != 1) {
      throw std::logic_error("Topology: interposed stage '" + stage.stage_kind() +
                             "' must read one FIFO kind");
    }
    Fifo<T>& first = connect_fifo(stage.spec().inputs.front(), unit, writer, out, stage, *made.in);
    connect_fifo(kind, unit, &stage, made.out, reader, in);
    return first;
  }

  // Binds `stage`'s memory port to `memory`: a client numbered in the
  // order of these calls (its round-robin place, hw/memory.h).
  // Elaboration only.
  void connect_memory(PipelineStage& stage, MemoryPort& port, Memory& memory);
  // A side channel of kind `kind` from `writer` to `reader` (unit -1: front
  // end) that is not a FIFO: made here from `args`, owned here, handed to
  // both stages by the caller; its reset() empties it between frames.
  // Elaboration only.
  template <typename Link, typename... Args>
  Link& connect_link(const std::string& kind, int unit, PipelineStage& writer,
                     PipelineStage& reader, Args&&... args) {
    if (m_finished) throw std::logic_error("Topology: connect_link() after finish()");
    auto link = std::make_shared<Link>(std::forward<Args>(args)...);
    m_links.push_back({PipelineStage::instance_name(kind, unit), kind, unit, &writer, &reader, link,
                       [l = link.get()] { l->reset(); }});
    return *link;
  }

  // Sorts the netlist into pipeline order, checks it against the
  // configuration (every stage and FIFO kind of the topology has a cost and
  // a depth there, and the configuration names nothing the topology lacks:
  // std::logic_error otherwise), and adds each stage's stalled_cycles and
  // starved_cycles to its statistics. Call once, after the last connect().
  void finish();

  // Between frames, from a process at the new frame's first instant (the
  // GPU's reset, Gpu::reset): every FIFO, link and memory, then every stage
  // as elaborated (PipelineStage::reset), so that the next frame's cycles
  // and statistics are those of a freshly elaborated netlist. The kernel
  // must be idle but for the caller: the previous frame complete, no
  // process runnable, no event pending.
  void reset();

  const std::vector<StageNode>& stages() const { return m_stages; }
  const std::vector<FifoNode>& fifos() const { return m_fifos; }
  const FifoNode* find_fifo(const std::string& name) const;
  // Distinct kinds in pipeline order.
  std::vector<std::string> stage_kinds() const;
  std::vector<std::string> fifo_kinds() const;

  // The tables the trace files index (docs/traces.md), and the probes of a
  // recorder attached to every FIFO by those indices and to every stage with
  // a fragment site (StageTrace::fragments).
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

  // Adds the collections "stages" (each stage's group by its name,
  // described by kind) and "fifos" (each FIFO's group, times in cycles) to
  // `root`, in pipeline order. After finish().
  void add_stats(StatGroup& root) const;

 private:
  template <typename T>
  Fifo<T>& connect_fifo(const std::string& kind, int unit, PipelineStage* writer,
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
  void add_fifo(FifoNode node, std::shared_ptr<FifoChannel> fifo, PipelineStage* writer,
                PipelineStage& reader);
  int stage_index(PipelineStage& stage);
  int index_of(const PipelineStage* stage) const;  // after finish()

  const GpuConfig& m_config;
  const FrameState& m_frame;  // for interposed stages
  const Interposers* m_interposers;
  std::vector<StageNode> m_stages;
  std::vector<FifoNode> m_fifos;
  std::vector<std::shared_ptr<FifoChannel>> m_owned;
  struct MemoryEdge {
    std::string name;
    PipelineStage* stage;
    Memory* memory;
  };
  std::vector<MemoryEdge> m_memory_clients;  // in client number order
  struct LinkEdge {
    std::string name, kind;
    int unit;
    PipelineStage *writer, *reader;
    std::shared_ptr<void> link;
    std::function<void()> reset;  // Link::reset()
  };
  std::vector<LinkEdge> m_links;
  // Interposed stages, destroyed before the FIFOs they are bound to.
  std::vector<std::unique_ptr<PipelineStage>> m_owned_stages;
  bool m_finished = false;
};

}  // namespace gpusim
