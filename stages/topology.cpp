#include "stages/topology.h"

#include <algorithm>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>

namespace gpusim {

int Topology::stage_index(PipelineStage& stage) {
  for (size_t i = 0; i < m_stages.size(); ++i) {
    if (m_stages[i].stage == &stage) return static_cast<int>(i);
  }
  m_stages.push_back({&stage, {}, {}, 0});
  return static_cast<int>(m_stages.size() - 1);
}

void Topology::add_fifo(FifoNode node, std::shared_ptr<FifoChannel> fifo, PipelineStage* writer,
                        PipelineStage& reader) {
  if (m_finished) throw std::logic_error("Topology: connect() after finish()");
  // A FIFO belongs to its reader: its kind is one the reader's spec declares.
  const std::vector<std::string>& inputs = reader.spec().inputs;
  if (std::find(inputs.begin(), inputs.end(), node.kind) == inputs.end()) {
    throw std::logic_error("Topology: FIFO '" + node.kind + "' is not an input of '" +
                           reader.stage_kind() + "' (hw/stage_spec.h)");
  }
  if (find_fifo(node.name) != nullptr) {
    throw std::logic_error("Topology: FIFO '" + node.name + "' connected twice");
  }
  const size_t index = m_fifos.size();
  node.writer = writer != nullptr ? stage_index(*writer) : kHost;
  node.reader = stage_index(reader);
  if (node.writer != kHost) m_stages[node.writer].outputs.push_back(index);
  m_stages[node.reader].inputs.push_back(index);
  m_fifos.push_back(std::move(node));
  m_owned.push_back(std::move(fifo));
}

void Topology::connect_memory(PipelineStage& stage, MemoryPort& port, Memory& memory) {
  if (m_finished) throw std::logic_error("Topology: connect_memory() after finish()");
  port.bind(memory);
  m_memory_clients.push_back({port.client_name(), &stage, &memory});
}

void Topology::reset() {
  if (!m_finished) throw std::logic_error("Topology: reset() before finish()");
  const uint64_t start = sc_core::sc_time_stamp().value();
  // The channels first: a stage's restarted thread runs until it waits,
  // which may be on a read of the new frame's first item.
  for (const FifoNode& f : m_fifos) f.channel->reset(start);
  for (const LinkEdge& l : m_links) l.reset();
  std::vector<Memory*> memories;
  for (const MemoryEdge& m : m_memory_clients) {
    if (std::find(memories.begin(), memories.end(), m.memory) != memories.end()) continue;
    memories.push_back(m.memory);
    m.memory->reset(start);
  }
  for (const StageNode& s : m_stages) s.stage->reset();
}

int Topology::index_of(const PipelineStage* stage) const {
  for (size_t i = 0; i < m_stages.size(); ++i) {
    if (m_stages[i].stage == stage) return static_cast<int>(i);
  }
  throw std::logic_error("Topology: stage '" + std::string(stage->basename()) +
                         "' has a memory port or link but no FIFO");
}

void Topology::finish() {
  if (m_finished) throw std::logic_error("Topology: finish() called twice");
  m_finished = true;

  // Rank: the longest chain of FIFOs from the host (the netlist is acyclic;
  // a cycle would never settle, so stop after as many rounds as stages).
  for (size_t round = 0; round <= m_stages.size(); ++round) {
    bool changed = false;
    for (StageNode& s : m_stages) {
      int rank = 0;
      for (size_t f : s.inputs) {
        const int w = m_fifos[f].writer;
        rank = std::max(rank, w == kHost ? 1 : m_stages[w].rank + 1);
      }
      changed = changed || rank != s.rank;
      s.rank = rank;
    }
    if (!changed) break;
    if (round == m_stages.size()) throw std::logic_error("Topology: the FIFOs form a cycle");
  }

  // Pipeline order: (unit, rank), front end (unit -1) first; then renumber
  // the FIFOs' endpoints and the stages' FIFO lists.
  std::vector<size_t> order(m_stages.size());
  std::iota(order.begin(), order.end(), size_t{0});
  // A shared stage fed by the units (the resolve) comes after them.
  const auto fed_by_units = [&](const StageNode& s) {
    for (size_t f : s.inputs) {
      const int w = m_fifos[f].writer;
      if (w != kHost && m_stages[w].stage->unit() >= 0) return true;
    }
    return false;
  };
  const auto key = [&](size_t i) {
    const StageNode& s = m_stages[i];
    const bool back_end = s.stage->unit() < 0 && fed_by_units(s);
    return std::make_pair(back_end ? std::numeric_limits<int>::max() : s.stage->unit(), s.rank);
  };
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return key(a) < key(b); });
  std::vector<int> new_index(m_stages.size());
  for (size_t i = 0; i < order.size(); ++i) new_index[order[i]] = static_cast<int>(i);
  const auto fifo_key = [&](const FifoNode& f) { return new_index[f.reader]; };
  std::vector<size_t> fifo_order(m_fifos.size());
  std::iota(fifo_order.begin(), fifo_order.end(), size_t{0});
  std::stable_sort(fifo_order.begin(), fifo_order.end(),
                   [&](size_t a, size_t b) { return fifo_key(m_fifos[a]) < fifo_key(m_fifos[b]); });
  std::vector<size_t> new_fifo(m_fifos.size());
  for (size_t i = 0; i < fifo_order.size(); ++i) new_fifo[fifo_order[i]] = i;

  std::vector<StageNode> stages;
  for (size_t i : order) stages.push_back(std::move(m_stages[i]));
  for (StageNode& s : stages) {
    for (size_t& f : s.inputs) f = new_fifo[f];
    for (size_t& f : s.outputs) f = new_fifo[f];
    std::sort(s.inputs.begin(), s.inputs.end());
    std::sort(s.outputs.begin(), s.outputs.end());
  }
  std::vector<FifoNode> fifos;
  std::vector<std::shared_ptr<FifoChannel>> owned;
  for (size_t i : fifo_order) {
    fifos.push_back(std::move(m_fifos[i]));
    owned.push_back(std::move(m_owned[i]));
  }
  for (FifoNode& f : fifos) {
    if (f.writer != kHost) f.writer = new_index[f.writer];
    f.reader = new_index[f.reader];
  }
  m_stages = std::move(stages);
  m_fifos = std::move(fifos);
  m_owned = std::move(owned);

  // The configuration (the registered stages) and the netlist name the same
  // stages and FIFOs, but for the optional kinds a frame may leave out.
  const auto same = [](std::vector<std::string> a, std::vector<std::string> b) {
    const std::vector<std::string> optional = StageRegistry::optional_kinds();
    for (const std::string& k : optional) {
      if (std::find(a.begin(), a.end(), k) == a.end()) {
        b.erase(std::remove(b.begin(), b.end(), k), b.end());
      }
    }
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    return a == b;
  };
  const auto joined = [](const std::vector<std::string>& v) {
    std::string s;
    for (const std::string& n : v) s += (s.empty() ? "" : ", ") + n;
    return s;
  };
  if (!same(stage_kinds(), GpuConfig::stage_names())) {
    throw std::logic_error("Topology: the netlist's stages (" + joined(stage_kinds()) +
                           ") differ from the configuration's (" +
                           joined(GpuConfig::stage_names()) + ")");
  }
  if (!same(fifo_kinds(), GpuConfig::fifo_names())) {
    throw std::logic_error("Topology: the netlist's FIFOs (" + joined(fifo_kinds()) +
                           ") differ from the configuration's (" + joined(GpuConfig::fifo_names()) +
                           ")");
  }

  // Stalled: blocked writing a full output; starved: blocked reading an
  // empty (or not yet ready) input. The FIFOs measure both.
  const sc_core::sc_time cycle = m_config.cycle();
  for (FifoNode& f : m_fifos) f.channel->set_cycle(cycle);
  for (StageNode& s : m_stages) {
    std::vector<const FifoChannel*> outputs, inputs;
    for (size_t f : s.outputs) outputs.push_back(m_fifos[f].channel);
    for (size_t f : s.inputs) inputs.push_back(m_fifos[f].channel);
    s.stage->stats().formula("stalled_cycles", "cycles",
                             "cycles blocked writing a full output FIFO", [outputs, cycle] {
                               double c = 0.0;
                               for (const FifoChannel* f : outputs)
                                 c += f->stats().writer_blocked / cycle;
                               return c;
                             });
    s.stage->stats().formula("starved_cycles", "cycles",
                             "cycles blocked reading an empty or not yet ready input FIFO",
                             [inputs, cycle] {
                               double c = 0.0;
                               for (const FifoChannel* f : inputs)
                                 c += f->stats().reader_blocked / cycle;
                               return c;
                             });
  }
}

const Topology::FifoNode* Topology::find_fifo(const std::string& name) const {
  for (const FifoNode& f : m_fifos) {
    if (f.name == name) return &f;
  }
  return nullptr;
}

std::vector<std::string> Topology::stage_kinds() const {
  std::vector<std::string> kinds;
  for (const StageNode& s : m_stages) {
    if (std::find(kinds.begin(), kinds.end(), s.stage->stage_kind()) == kinds.end())
      kinds.push_back(s.stage->stage_kind());
  }
  return kinds;
}

std::vector<std::string> Topology::fifo_kinds() const {
  std::vector<std::string> kinds;
  for (const FifoNode& f : m_fifos) {
    if (std::find(kinds.begin(), kinds.end(), f.kind) == kinds.end()) kinds.push_back(f.kind);
  }
  return kinds;
}

NetlistTables Topology::trace_tables() const {
  NetlistTables t;
  for (const FifoNode& n : m_fifos) {
    NetlistTables::Fifo f;
    f.name = n.name;
    f.kind = n.kind;
    f.depth = n.channel->capacity();
    f.writer = n.writer;
    f.reader = n.reader;
    f.unit = n.unit;
    t.fifos.push_back(f);
  }
  for (const StageNode& n : m_stages) {
    NetlistTables::Stage s;
    s.name = n.stage->basename();
    s.kind = n.stage->stage_kind();
    s.unit = n.stage->unit();
    for (size_t f : n.inputs) s.inputs.push_back(static_cast<int>(f));
    for (size_t f : n.outputs) s.outputs.push_back(static_cast<int>(f));
    const StageTrace& trace = n.stage->spec().trace;
    s.item = to_string(trace.item);
    for (PrimitiveKind k : {PrimitiveKind::point, PrimitiveKind::line, PrimitiveKind::triangle}) {
      const char* why = trace.drops[static_cast<size_t>(k)];
      if (why != nullptr) {
        std::ostringstream word;
        word << k;
        s.drops[word.str()] = why;
      }
    }
    s.fragments = to_string(trace.fragments);
    t.stages.push_back(std::move(s));
  }
  for (const MemoryEdge& e : m_memory_clients)
    t.memory_clients.push_back({e.name, index_of(e.stage)});
  // Links in pipeline order, by their reader, whatever order the units
  // were elaborated in.
  for (const LinkEdge& e : m_links) {
    t.links.push_back({e.name, e.kind, index_of(e.writer), index_of(e.reader), e.unit});
  }
  std::stable_sort(t.links.begin(), t.links.end(),
                   [](const NetlistTables::Link& a, const NetlistTables::Link& b) {
                     return a.reader < b.reader;
                   });
  return t;
}

void Topology::attach_trace(TraceProbes& probes) const {
  for (size_t i = 0; i < m_fifos.size(); ++i) m_fifos[i].attach_probe(probes, i);
  for (const StageNode& s : m_stages) {
    if (s.stage->spec().trace.fragments != FragmentSite::none) {
      s.stage->set_fragment_probe(probes.fragment_probe());
    }
  }
}

size_t Topology::decouple() {
  size_t n = 0;
  for (StageNode& s : m_stages) {
    if (s.stage->decouplable()) {
      s.stage->set_decoupled();
      ++n;
    }
  }
  const auto clock = [&](int stage) -> const SuperdenseTime* {
    if (stage < 0 || !m_stages[static_cast<size_t>(stage)].stage->decoupled()) return nullptr;
    return &m_stages[static_cast<size_t>(stage)].stage->local_clock();
  };
  for (FifoNode& f : m_fifos) {
    const SuperdenseTime* writer = clock(f.writer);
    const SuperdenseTime* reader = clock(f.reader);
    if (writer != nullptr || reader != nullptr) f.channel->set_stamped(writer, reader);
  }
  return n;
}

uint64_t Topology::items_moved() const {
  uint64_t n = 0;
  for (const FifoNode& f : m_fifos) {
    const FifoStats s = f.channel->stats();
    n += s.written + s.read;
  }
  return n;
}

void Topology::add_stats(StatGroup& root) const {
  StatCollection& stages =
      root.collection("stages", StatGroup::Layout::object, StatGroup::Describe::by_kind);
  for (const StageNode& s : m_stages) stages.add(s.stage->stats());
  StatCollection& fifos =
      root.collection("fifos", StatGroup::Layout::object, StatGroup::Describe::merged);
  for (const FifoNode& f : m_fifos) fifos.add(f.channel->stat_group());
}

}  // namespace gpusim
