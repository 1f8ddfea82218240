// Vertex fetch: turns a draw command into batches of vertex slots with their
// attributes read from memory, and owns the tags of the post-transform vertex
// cache (hw/vertex_packets.h explains the split with the clipper).
//
// Per draw, the `slot_count` slots are walked in batches of kVertexBatchSlots.
// For each batch:
// - indexed draws read the batch's indices (uint32) in one request;
// - each slot's vertex index is classified: an index >= vertex_count is
//   invalid (nothing is read; the clipper drops its primitives); otherwise,
//   for indexed draws with a cache, a tag hit is a `cached` slot and a miss
//   takes the next entry in FIFO order (the oldest, once full) and becomes a
//   `fetched` slot; non-indexed draws bypass the cache, every slot is fetched.
//   The tags are flushed at the start of every draw (new arrays, new matrices);
// - the attributes of the fetched vertices are read: position (16 B), normal
//   (12 B) when the draw is lit and has normals, colour (16 B) when it has
//   colours. Fetched vertices whose indices are consecutive (k, k+1, ...) in
//   slot order form one burst: one request per attribute array per burst, so
//   a non-indexed batch costs three requests at most.
//
// Cost model, per batch: the stage is busy ii(vertex_fetch) x slots cycles
// generating addresses; its reads stay in flight meanwhile (the next batch's
// requests queue behind them on the shared bus, so bandwidth still limits).
// The memory time runs from the batch's start to the completion of its last
// read: the index read (none when not indexed), then the attribute reads,
// issued together once the indices are back. Each is one group on the
// memory's arbiter (hw/memory.h), so a batch costs two rounds (one delta
// each, no simulated time), or one when not indexed. The batch is
// readable by the shader max(ii x slots, memory time) + latency(vertex_fetch)
// cycles after the batch started; the output FIFO's depth bounds the batches
// in flight. Control tokens cost ii and are forwarded in order.
#pragma once

#include <systemc>
#include <vector>

#include "hw/draw_state.h"
#include "hw/fifo.h"
#include "hw/gpu_config.h"
#include "hw/memory.h"
#include "hw/packets.h"
#include "hw/pipeline_stage.h"
#include "hw/stats.h"
#include "hw/vertex_packets.h"

namespace gpusim {

class VertexFetch : public PipelineStage {
 public:
  // Its kind, cost and FIFOs (hw/stage_spec.h).
  static const StageSpec& spec();

  FifoInPort<Command> in;
  FifoOutPort<VertexBatch> out;
  MemoryPort mem;

  VertexFetch(sc_core::sc_module_name name, const GpuConfig& config, const FrameState& frame);

 private:
  void run();
  void reset_state() override;
  void fetch_draw(uint32_t draw_id);
  // Fills slots, indices and attributes of `batch`; returns the memory time.
  sc_core::sc_time fetch_batch(const DrawState& draw, VertexBatch& batch);
  // Cache tags: the entry now holding vertex `index`, or the one it takes.
  bool cache_lookup(uint32_t index, uint32_t& entry);
  void cache_flush();

  const uint32_t m_cache_entries;

  // FIFO replacement: entries are filled in order 0, 1, ... and then reused
  // from the oldest, which is the one m_next points to.
  std::vector<uint32_t> m_tag;       // per entry: vertex index, kNoTag when empty
  std::vector<uint32_t> m_entry_of;  // per vertex index of the draw: entry or kNoCacheEntry
  uint32_t m_next = 0;
  std::array<uint32_t, kVertexBatchSlots> m_indices{};
  std::array<uint32_t, kVertexBatchSlots> m_fetch_index{};  // per fetched vertex
  VertexBatch m_batch;

  uint64_t& m_draws = m_stats.counter("draws", "commands", "draw commands");
  uint64_t& m_batches = m_stats.counter("batches", "batches", "vertex batches written");
  uint64_t& m_slots = m_stats.counter("slots", "slots", "vertex slots walked");
  uint64_t& m_invalid =
      m_stats.counter("invalid_slots", "slots", "slots whose index is not below the vertex count");
  uint64_t& m_lookups =
      m_stats.counter("cache_lookups", "lookups", "indexed slots looked up in the vertex cache");
  uint64_t& m_hits = m_stats.counter("cache_hits", "lookups", "lookups that hit");
  uint64_t& m_misses = m_stats.counter("cache_misses", "lookups", "lookups that missed");
  uint64_t& m_fetched =
      m_stats.counter("vertices_fetched", "vertices",
                      "vertices read from memory (cache misses and non-indexed slots)");
  uint64_t& m_requests = m_stats.counter("memory_requests", "requests",
                                         "memory reads: index blocks and attribute bursts");
  uint64_t& m_bytes = m_stats.counter("bytes_read", "bytes", "bytes read from memory");
  uint64_t& m_memory_cycles = m_stats.counter(
      "memory_wait_cycles", "cycles", "memory time of the batches (overlapping busy_cycles)");
};

}  // namespace gpusim
