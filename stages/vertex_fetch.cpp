#include "stages/vertex_fetch.h"

#include <algorithm>

namespace gpusim {
namespace {

constexpr uint32_t kNoTag = ~uint32_t{0};
constexpr uint64_t kPositionBytes = 16;
constexpr uint64_t kNormalBytes = 12;
constexpr uint64_t kColorBytes = 16;
constexpr uint64_t kTexcoordBytes = 8;
// Bursts are read straight into the packet's arrays, which must therefore be
// laid out like memory: tightly packed float32.
static_assert(sizeof(glm::vec4) == kPositionBytes && sizeof(glm::vec3) == kNormalBytes &&
                  sizeof(glm::vec2) == kTexcoordBytes,
              "glm vectors must be tightly packed floats");

}  // namespace

namespace {

// Conservation (testbench/sim/conservation.h): how its counters balance.
void conserve(ConservationLedger& l) {
  const ConservationLedger::Frame& f = l.frame();
  // Draws become batches of slots; every slot is invalid, a cache hit
  // or fetched.
  l.equal("draws", l.get("draws"), "draws in the frame", f.draws);
  l.equal("tokens_in", l.get("tokens_in"), "draws + control tokens", f.draws + f.control);
  l.equal("tokens_out", l.get("tokens_out"), "batches + control tokens",
          l.get("batches") + f.control);
  l.equal("slots", l.get("slots"), "slots of the frame's draws", f.slots);
  l.equal("slots", l.get("slots"), "invalid_slots + cache_hits + vertices_fetched",
          l.get("invalid_slots") + l.get("cache_hits") + l.get("vertices_fetched"));
}

}  // namespace

const StageSpec& VertexFetch::spec() {
  static const StageSpec s{
      "vertex_fetch",
      StagePlacement::front_end,
      /*optional=*/false,
      {/*ii=*/1, /*latency=*/2},
      "vertex",
      "address generation and format conversion; the memory delay comes on top",
      "commands read",
      "batches and control tokens written",
      {"command_to_fetch"},
      &conserve,
      StageTrace{TraceItem::draw, {}, FragmentSite::none},
      {{"", "`ii` × slots, per batch of up to 32 slots",
        "Reads indices (one request per batch, 4 B each) and, per cache miss or non-indexed slot, "
        "the attributes (bursts over consecutive indices, one request per array). The reads stay "
        "in flight: the batch is readable `max(ii × slots, memory time) + latency` after it "
        "started, where memory time runs to the last read's completion."}}};
  return s;
}
GPUSIM_REGISTER_STAGE(VertexFetch);

VertexFetch::VertexFetch(sc_core::sc_module_name name, const GpuConfig& config,
                         const FrameState& frame)
    : PipelineStage(name, spec(), -1, config, frame),
      in("in"),
      out("out"),
      mem("mem"),
      m_cache_entries(config.vertex_cache_entries),
      m_tag(config.vertex_cache_entries, kNoTag) {
  m_stats.formula("cache_hit_rate", "ratio", "cache_hits / cache_lookups",
                  [this] { return static_cast<double>(m_hits) / static_cast<double>(m_lookups); });
  SC_HAS_PROCESS(VertexFetch);
  SC_THREAD(run);
}

void VertexFetch::reset_state() {
  std::fill(m_tag.begin(), m_tag.end(), kNoTag);
  m_entry_of.clear();
  m_next = 0;
  m_batch = VertexBatch{};
}

void VertexFetch::run() {
  for (;;) {
    const Command cmd = receive(in);
    if (cmd.kind == PacketKind::work) {
      fetch_draw(cmd.draw_id);
    } else {
      forward_control(out, cmd.kind);
    }
  }
}

void VertexFetch::fetch_draw(uint32_t draw_id) {
  ++m_draws;
  const DrawState& draw = m_frame.draws.at(draw_id);
  const DrawBuffers& b = draw.buffers;
  if (b.indices != kNoBuffer && m_cache_entries > 0) {
    cache_flush();
    if (m_entry_of.size() < b.vertex_count) m_entry_of.resize(b.vertex_count, kNoCacheEntry);
  }
  for (uint32_t first = 0; first < b.slot_count; first += kVertexBatchSlots) {
    VertexBatch& batch = m_batch;
    batch.kind = PacketKind::work;
    batch.draw_id = draw_id;
    batch.first_slot = first;
    batch.slot_count = std::min(kVertexBatchSlots, b.slot_count - first);
    const sc_core::sc_time memory = fetch_batch(draw, batch);
    // Every delay is a whole number of cycles: requests start at cycle
    // boundaries and the bus and the memory count in cycles.
    const uint64_t memory_cycles = (memory.value() + m_cycle - 1) / m_cycle;
    const uint64_t busy = uint64_t{m_cost.ii} * batch.slot_count;
    const sc_core::sc_time ready =
        sc_core::sc_time_stamp() + clock_cycles(std::max(busy, memory_cycles) + m_cost.latency);
    m_memory_cycles += memory_cycles;
    m_slots += batch.slot_count;
    work(busy);
    emit_at(out, batch, ready);
    ++m_batches;
  }
}

sc_core::sc_time VertexFetch::fetch_batch(const DrawState& draw, VertexBatch& batch) {
  const DrawBuffers& b = draw.buffers;
  const bool indexed = b.indices != kNoBuffer;
  const uint32_t n = batch.slot_count;
  const sc_core::sc_time now = sc_core::sc_time_stamp();
  sc_core::sc_time memory = sc_core::SC_ZERO_TIME;

  if (indexed) {
    // The indices are in m_indices at once; the round says when they arrive.
    mem.read(b.indices + uint64_t{batch.first_slot} * 4, m_indices.data(), uint64_t{n} * 4);
    memory = mem.wait_round().reads - now;
    ++m_requests;
    m_bytes += uint64_t{n} * 4;
  } else {
    for (uint32_t i = 0; i < n; ++i) m_indices[i] = batch.first_slot + i;
  }

  // Classify the slots.
  uint32_t fetched = 0;
  for (uint32_t i = 0; i < n; ++i) {
    VertexSlot& slot = batch.slots[i];
    const uint32_t index = m_indices[i];
    if (index >= b.vertex_count) {
      slot = {SlotKind::invalid, kNoCacheEntry, 0};
      ++m_invalid;
      continue;
    }
    uint32_t entry = kNoCacheEntry;
    if (indexed) {
      ++m_lookups;
      if (m_cache_entries > 0 && cache_lookup(index, entry)) {
        ++m_hits;
        slot = {SlotKind::cached, entry, 0};
        continue;
      }
      ++m_misses;
    }
    slot = {SlotKind::fetched, entry, fetched};
    m_fetch_index[fetched++] = index;
  }
  batch.vertex_count = fetched;
  m_fetched += fetched;

  // Attribute bursts, issued together once the indices are back (at
  // `issue`), one round; the memory time is when the last one completes.
  const sc_core::sc_time issue = memory;
  const bool normals = draw.lighting && b.normals != kNoBuffer;
  const bool colors = b.colors != kNoBuffer;
  const bool texcoords = b.texcoords != kNoBuffer;
  const auto read = [&](uint64_t base, uint32_t index, void* dst, uint64_t bytes, uint32_t count) {
    const uint64_t len = bytes * count;
    mem.read(base + bytes * index, dst, len, issue);
    ++m_requests;
    m_bytes += len;
  };
  for (uint32_t first = 0; first < fetched;) {
    uint32_t count = 1;
    while (first + count < fetched && m_fetch_index[first + count] == m_fetch_index[first] + count)
      ++count;
    const uint32_t index = m_fetch_index[first];
    read(b.positions, index, &batch.positions[first], kPositionBytes, count);
    if (normals) read(b.normals, index, &batch.normals[first], kNormalBytes, count);
    if (colors) read(b.colors, index, &batch.colors[first], kColorBytes, count);
    if (texcoords) read(b.texcoords, index, &batch.texcoords[first], kTexcoordBytes, count);
    first += count;
  }
  if (fetched > 0) memory = std::max(memory, mem.wait_round().reads - now);
  return memory;
}

bool VertexFetch::cache_lookup(uint32_t index, uint32_t& entry) {
  entry = m_entry_of[index];
  if (entry != kNoCacheEntry) return true;
  entry = m_next;
  m_next = m_next + 1 == m_cache_entries ? 0 : m_next + 1;
  if (m_tag[entry] != kNoTag) m_entry_of[m_tag[entry]] = kNoCacheEntry;
  m_tag[entry] = index;
  m_entry_of[index] = entry;
  return false;
}

void VertexFetch::cache_flush() {
  for (uint32_t& tag : m_tag) {
    if (tag != kNoTag) m_entry_of[tag] = kNoCacheEntry;
    tag = kNoTag;
  }
  m_next = 0;
}

}  // namespace gpusim
