// The simulation-speed mechanisms of the channels and packets, which must not
// change any result: moving writes and reads into a packet object recycle the
// packets' buffers instead of allocating, give the same schedule and
// statistics as copies, and skipping event notifications nobody waits on
// never loses a wake-up. Clock: 1 ns. ctest runs each TEST in its own process.
#define SC_INCLUDE_DYNAMIC_PROCESSES
#include <gtest/gtest.h>

#include <functional>
#include <memory>
#include <set>
#include <stdexcept>
#include <vector>

#include "hw/fifo.h"
#include "hw/packets.h"

namespace gpusim {
namespace {

using sc_core::sc_time;
using sc_core::wait;

const sc_time kCycle(1, sc_core::SC_NS);

void spawn(std::function<void()> body) {
  sc_core::sc_spawn(std::move(body));
}

// Batch i of a stream: three stamps whose x values identify it.
void fill(StampBatch& b, int i, const std::shared_ptr<const RasterPrimitive>& tri) {
  b.kind = PacketKind::work;
  b.primitive = tri;
  b.stamps.clear();
  for (int k = 0; k < 3; ++k) b.stamps.push_back(Stamp{10 * i + k, 0, 1, {}});
}

// A writer that moves one packet object in and a reader that reads into one:
// the values arrive intact and, once every slot has been used, no buffer is
// ever allocated again: only the depth + 2 buffers in circulation are seen.
TEST(FifoRecycling, MovingWritesAndReadsIntoCirculateBuffers) {
  constexpr int kItems = 50;
  Fifo<StampBatch> f("f", 2);
  auto tri = std::make_shared<RasterPrimitive>();
  std::vector<int> first_x;
  std::set<const Stamp*> buffers;
  spawn([&] {
    StampBatch b;
    for (int i = 0; i < kItems; ++i) {
      fill(b, i, tri);
      f.write(std::move(b), sc_core::sc_time_stamp() + kCycle);
    }
  });
  spawn([&] {
    StampBatch r;
    for (int i = 0; i < kItems; ++i) {
      f.read(r);
      ASSERT_EQ(r.stamps.size(), 3u);
      EXPECT_EQ(r.primitive, tri);
      first_x.push_back(r.stamps[0].x);
      buffers.insert(r.stamps.data());
      wait(kCycle);
    }
  });
  sc_core::sc_start();
  ASSERT_EQ(first_x.size(), static_cast<size_t>(kItems));
  for (int i = 0; i < kItems; ++i) EXPECT_EQ(first_x[i], 10 * i);
  EXPECT_LE(buffers.size(), f.depth() + 2);
}

// The same stream written by copy into one FIFO and by move into another, each
// read by the same slow consumer: identical arrival times and statistics.
TEST(FifoRecycling, CopyAndMoveGiveTheSameSchedule) {
  constexpr int kItems = 12;
  Fifo<StampBatch> copied("copied", 2), moved("moved", 2);
  auto tri = std::make_shared<RasterPrimitive>();
  spawn([&] {
    StampBatch b;
    for (int i = 0; i < kItems; ++i) {
      fill(b, i, tri);
      copied.write(b, sc_core::sc_time_stamp() + 2 * kCycle);
    }
  });
  spawn([&] {
    StampBatch b;
    for (int i = 0; i < kItems; ++i) {
      fill(b, i, tri);
      moved.write(std::move(b), sc_core::sc_time_stamp() + 2 * kCycle);
    }
  });
  std::vector<double> t_copied, t_moved;
  const auto consumer = [](Fifo<StampBatch>& f, std::vector<double>& times, bool into) {
    spawn([&f, &times, into] {
      StampBatch r;
      for (int i = 0; i < kItems; ++i) {
        if (into) {
          f.read(r);
        } else {
          r = f.read();
        }
        EXPECT_EQ(r.stamps.at(0).x, 10 * i);
        times.push_back(sc_core::sc_time_stamp() / kCycle);
        wait(3 * kCycle);
      }
    });
  };
  consumer(copied, t_copied, false);
  consumer(moved, t_moved, true);
  sc_core::sc_start();
  EXPECT_EQ(t_copied, t_moved);
  const FifoStats a = copied.stats(), b = moved.stats();
  EXPECT_EQ(a.written, b.written);
  EXPECT_EQ(a.read, b.read);
  EXPECT_EQ(a.max_occupancy, b.max_occupancy);
  EXPECT_EQ(a.mean_occupancy, b.mean_occupancy);
  EXPECT_EQ(a.full, b.full);
  EXPECT_EQ(a.empty, b.empty);
  EXPECT_EQ(a.writer_blocked, b.writer_blocked);
  EXPECT_EQ(a.reader_blocked, b.reader_blocked);
}

// A reader that blocks in the same instant as a write it cannot see yet (the
// item becomes readable in the next delta), and a writer that blocks on a
// full FIFO just after a read it cannot use yet: both are woken, whatever
// order the kernel runs the processes of the delta in.
TEST(FifoRecycling, LateBlockersAreWoken) {
  Fifo<int> data("data", 1), full("full", 1);
  int got = -1;
  double read_at = -1, wrote_at = -1;
  spawn([&] { data.write(7); });
  spawn([&] {
    got = data.read();
    read_at = sc_core::sc_time_stamp() / kCycle;
  });
  spawn([&] {
    full.write(1);
    wait(kCycle);
    full.write(2);  // full until the read below is committed
    wrote_at = sc_core::sc_time_stamp() / kCycle;
  });
  spawn([&] {
    wait(kCycle);
    full.read();
  });
  sc_core::sc_start();
  EXPECT_EQ(got, 7);
  EXPECT_EQ(read_at, 0);
  EXPECT_EQ(wrote_at, 1);
  EXPECT_EQ(full.stats().written, 2u);
}

TEST(Log2Side, PowersOfTwoOnly) {
  EXPECT_EQ(log2_side(1), 0);
  EXPECT_EQ(log2_side(8), 3);
  EXPECT_EQ(log2_side(256), 8);
  EXPECT_THROW(log2_side(0), std::invalid_argument);
  EXPECT_THROW(log2_side(3), std::invalid_argument);
  EXPECT_THROW(log2_side(24), std::invalid_argument);
}

}  // namespace
}  // namespace gpusim
