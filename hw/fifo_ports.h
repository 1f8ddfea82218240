// The two sides of a FIFO (hw/fifo.h) as SystemC interfaces: a stage holds a
// port of one side and never sees the channel behind it, so a test can bind
// the port to a FIFO of its own and the netlist can put a stage in a FIFO's
// place (stages/topology.h, Interposers).
#pragma once

#include <cstddef>
#include <cstdint>
#include <systemc>

#include "hw/superdense_time.h"

namespace gpusim {

// The reader's side, for stages that reach their input through an sc_port.
template <typename T>
class FifoInIf : public virtual sc_core::sc_interface {
 public:
  virtual T read() = 0;
  // The same, into `item`: its previous value goes to the freed slot, for the
  // next writer to reuse its buffers (a reader that reads into one packet
  // object every time allocates nothing).
  virtual void read(T& item) = 0;
  virtual bool nb_read(T& item) = 0;
  virtual size_t size() const = 0;
  virtual const T& front() const = 0;
  virtual const sc_core::sc_event& data_written_event() const = 0;
  // Stamped mode only: the read a decoupled reader makes at its own time
  // `call` (which may be ahead of the kernel's); returns the read's time.
  virtual SuperdenseTime read_at(T& item, const SuperdenseTime& call) = 0;
  // The same, moving the item out of its slot (no swap: cheaper for packets
  // of fixed-size arrays); the read's time goes to `at`.
  virtual T read_at(const SuperdenseTime& call, SuperdenseTime& at) = 0;
};

// The writer's side.
template <typename T>
class FifoOutIf : public virtual sc_core::sc_interface {
 public:
  virtual void write(const T& item) = 0;
  // Write, but the reader sees the item only from `ready_at` on: a stage's
  // pipeline latency. The item holds its slot from when it enters; if the
  // write had to wait for a slot, `ready_at` moves later by that wait.
  // By value: a caller's sc_time_stamp() is a reference to the kernel's
  // time, which the wait would move too (counting the wait twice).
  virtual void write(const T& item, sc_core::sc_time ready_at) = 0;
  // Moving writes: `item` is left holding the slot's previous contents (a
  // stale packet whose buffers a writer may clear and refill).
  virtual void write(T&& item) = 0;
  virtual void write(T&& item, sc_core::sc_time ready_at) = 0;
  virtual bool nb_write(const T& item) = 0;
  virtual size_t num_free() const = 0;
  virtual size_t depth() const = 0;
  virtual const sc_core::sc_event& data_read_event() const = 0;
  // Stamped mode only: the write a decoupled writer makes at its own time
  // `call`; returns the write's time. `ready_at` (an sc_time value) moves
  // later by the wait.
  virtual SuperdenseTime write_at(const T& item, uint64_t ready_at, const SuperdenseTime& call) = 0;
  virtual SuperdenseTime write_at(T&& item, uint64_t ready_at, const SuperdenseTime& call) = 0;
};

template <typename T>
using FifoInPort = sc_core::sc_port<FifoInIf<T>>;
template <typename T>
using FifoOutPort = sc_core::sc_port<FifoOutIf<T>>;

}  // namespace gpusim
