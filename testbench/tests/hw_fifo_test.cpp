// Fifo timing and statistics against hand-derived schedules. Clock: 1 ns.
// A SystemC model elaborates once per process: ctest runs each TEST alone.
#define SC_INCLUDE_DYNAMIC_PROCESSES
#include <gtest/gtest.h>

#include <functional>
#include <vector>

#include "hw/fifo.h"

namespace gpusim {
namespace {

using sc_core::sc_time;
using sc_core::wait;

const sc_time kCycle(1, sc_core::SC_NS);
sc_time cycles(int n) {
  return kCycle * n;
}
double in_cycles(sc_time t) {
  return t / kCycle;
}

void spawn(std::function<void()> body) {
  sc_core::sc_spawn(std::move(body));
}

// Writes `n` items 0..n-1 back to back, recording when the last write returned.
void greedy_producer(Fifo<int>& f, int n, sc_time* done) {
  spawn([&f, n, done] {
    for (int i = 0; i < n; ++i) f.write(i);
    *done = sc_core::sc_time_stamp();
  });
}

// Waits `period`, then reads, `n` times; records values and read times.
void slow_consumer(Fifo<int>& f, int n, sc_time period, std::vector<int>* values,
                   std::vector<double>* times) {
  spawn([&f, n, period, values, times] {
    for (int i = 0; i < n; ++i) {
      wait(period);
      values->push_back(f.read());
      times->push_back(in_cycles(sc_core::sc_time_stamp()));
    }
  });
}

// Producer writes 6 items at once, consumer takes one every 5 cycles, so the
// FIFO fills and the producer stalls. For depth 2, by hand:
//   t=0   writes 0,1; blocks on 2           occupancy 2
//   t=5   reads 0; producer writes 2, blocks on 3   (back to 2 in the same instant)
//   t=10, 15 likewise; t=20 reads 3, producer writes 5 and is done
//   t=25  reads 4 -> occupancy 1;  t=30 reads 5 -> 0, simulation ends
// occupancy 2 on [0,25), 1 on [25,30): mean 55/30, full 25 cycles, producer
// blocked [0,20) = 20 cycles. Depth 1: occupancy 1 on [0,30), producer
// blocked until 25. Depth 16: all 6 written at t=0, occupancy 6,5,4,3,2,1 for
// 5 cycles each: mean 105/30, never full, never blocked.
TEST(Fifo, BackpressureDepth1Vs2Vs16) {
  Fifo<int> f1("f1", 1), f2("f2", 2), f16("f16", 16);
  sc_time done1, done2, done16;
  std::vector<int> v1, v2, v16;
  std::vector<double> t1, t2, t16;
  greedy_producer(f1, 6, &done1);
  greedy_producer(f2, 6, &done2);
  greedy_producer(f16, 6, &done16);
  slow_consumer(f1, 6, cycles(5), &v1, &t1);
  slow_consumer(f2, 6, cycles(5), &v2, &t2);
  slow_consumer(f16, 6, cycles(5), &v16, &t16);
  sc_core::sc_start();

  const std::vector<int> items{0, 1, 2, 3, 4, 5};
  const std::vector<double> read_times{5, 10, 15, 20, 25, 30};
  EXPECT_EQ(v1, items);
  EXPECT_EQ(v2, items);
  EXPECT_EQ(v16, items);
  EXPECT_EQ(t1, read_times);
  EXPECT_EQ(t2, read_times);
  EXPECT_EQ(t16, read_times);
  EXPECT_EQ(in_cycles(sc_core::sc_time_stamp()), 30);

  EXPECT_EQ(in_cycles(done1), 25);
  EXPECT_EQ(in_cycles(done2), 20);
  EXPECT_EQ(in_cycles(done16), 0);

  const FifoStats s1 = f1.stats(), s2 = f2.stats(), s16 = f16.stats();
  EXPECT_EQ(s1.written, 6u);
  EXPECT_EQ(s1.read, 6u);
  EXPECT_EQ(s1.max_occupancy, 1u);
  EXPECT_DOUBLE_EQ(s1.mean_occupancy, 1.0);
  EXPECT_EQ(in_cycles(s1.full), 30);
  EXPECT_EQ(in_cycles(s1.empty), 0);
  EXPECT_EQ(in_cycles(s1.writer_blocked), 25);
  EXPECT_EQ(in_cycles(s1.reader_blocked), 0);

  EXPECT_EQ(s2.max_occupancy, 2u);
  EXPECT_DOUBLE_EQ(s2.mean_occupancy, 55.0 / 30.0);
  EXPECT_EQ(in_cycles(s2.full), 25);
  EXPECT_EQ(in_cycles(s2.empty), 0);
  EXPECT_EQ(in_cycles(s2.writer_blocked), 20);
  EXPECT_EQ(in_cycles(s2.reader_blocked), 0);

  EXPECT_EQ(s16.max_occupancy, 6u);
  EXPECT_DOUBLE_EQ(s16.mean_occupancy, 105.0 / 30.0);
  EXPECT_EQ(in_cycles(s16.full), 0);
  EXPECT_EQ(in_cycles(s16.empty), 0);
  EXPECT_EQ(in_cycles(s16.writer_blocked), 0);
  EXPECT_EQ(in_cycles(s16.reader_blocked), 0);
  EXPECT_EQ(in_cycles(s16.observed), 30);

  // The stat group: null cycles until the period is set.
  EXPECT_TRUE(f2.stat_group().to_json()["full_cycles"].is_null());
  f2.set_cycle(kCycle);
  const nlohmann::json j = f2.stat_group().to_json();
  EXPECT_EQ(j["depth"], 2);
  EXPECT_EQ(j["written"], 6);
  EXPECT_EQ(j["read"], 6);
  EXPECT_EQ(j["max_occupancy"], 2);
  EXPECT_DOUBLE_EQ(j["mean_occupancy"].get<double>(), 55.0 / 30.0);
  EXPECT_EQ(j["full_cycles"], 25.0);
  EXPECT_EQ(j["empty_cycles"], 0.0);
  EXPECT_EQ(j["writer_blocked_cycles"], 20.0);
  EXPECT_EQ(j["reader_blocked_cycles"], 0.0);
  EXPECT_EQ(j["observed_cycles"], 30.0);
  // Cycles follow the given period: at 2 ns a cycle, 25 ns full is 12.5.
  f2.set_cycle(cycles(2));
  EXPECT_EQ(f2.stat_group().to_json()["full_cycles"], 12.5);
  // Every figure is described.
  for (const auto& field : j.items()) {
    EXPECT_TRUE(f2.stat_group().descriptions().contains(field.key())) << field.key();
  }
}

// Stamped mode (temporal decoupling): the backpressure schedule above with
// one side running ahead of the kernel on its own superdense clock, through
// write_at/read_at, and the other waiting in the kernel. Each decoupled side
// gets the times the kernel-timed FIFO gives (done at 25, 20, 0; reads every
// 5 cycles) and the statistics are the same numbers. A kernel timer runs to
// 30 so that every run observes the same window.
TEST(Fifo, StampedModeGivesTheKernelTimedSchedule) {
  Fifo<int> w1("w1", 1), w2("w2", 2), w16("w16", 16);  // decoupled writer
  Fifo<int> r1("r1", 1), r2("r2", 2), r16("r16", 16);  // decoupled reader
  SuperdenseTime wclock[3], rclock[3];
  Fifo<int>* writers[3] = {&w1, &w2, &w16};
  Fifo<int>* readers[3] = {&r1, &r2, &r16};
  double done[3] = {-1, -1, -1};
  sc_time producer_done[3];
  std::vector<int> wv[3], rv[3];
  std::vector<double> wt[3], rt[3];
  for (int k = 0; k < 3; ++k) {
    writers[k]->set_stamped(&wclock[k], nullptr);
    readers[k]->set_stamped(nullptr, &rclock[k]);
    Fifo<int>& w = *writers[k];
    SuperdenseTime& wc = wclock[k];
    double* d = &done[k];
    spawn([&w, &wc, d] {
      for (int i = 0; i < 6; ++i) wc = w.write_at(i, 0, wc);
      *d = static_cast<double>(wc.t) / static_cast<double>(kCycle.value());
    });
    slow_consumer(w, 6, cycles(5), &wv[k], &wt[k]);
    greedy_producer(*readers[k], 6, &producer_done[k]);
    Fifo<int>& r = *readers[k];
    SuperdenseTime& rc = rclock[k];
    std::vector<int>* values = &rv[k];
    std::vector<double>* times = &rt[k];
    spawn([&r, &rc, values, times] {
      for (int i = 0; i < 6; ++i) {
        rc = SuperdenseTime{rc.t + cycles(5).value(), 0};
        int item = -1;
        rc = r.read_at(item, rc);
        values->push_back(item);
        times->push_back(static_cast<double>(rc.t) / static_cast<double>(kCycle.value()));
      }
    });
  }
  spawn([] { wait(cycles(30)); });
  sc_core::sc_start();

  const std::vector<int> items{0, 1, 2, 3, 4, 5};
  const std::vector<double> read_times{5, 10, 15, 20, 25, 30};
  const double done_at[3] = {25, 20, 0};
  const double mean[3] = {1.0, 55.0 / 30.0, 105.0 / 30.0};
  const size_t max[3] = {1, 2, 6};
  const double full[3] = {30, 25, 0};
  const double blocked[3] = {25, 20, 0};
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(wv[k], items) << k;
    EXPECT_EQ(wt[k], read_times) << k;
    EXPECT_EQ(done[k], done_at[k]) << k;
    EXPECT_EQ(rv[k], items) << k;
    EXPECT_EQ(rt[k], read_times) << k;
    for (Fifo<int>* f : {writers[k], readers[k]}) {
      const FifoStats s = f->stats();
      EXPECT_EQ(s.written, 6u) << f->name();
      EXPECT_EQ(s.read, 6u) << f->name();
      EXPECT_EQ(s.max_occupancy, max[k]) << f->name();
      EXPECT_DOUBLE_EQ(s.mean_occupancy, mean[k]) << f->name();
      EXPECT_EQ(in_cycles(s.full), full[k]) << f->name();
      EXPECT_EQ(in_cycles(s.empty), 0) << f->name();
      EXPECT_EQ(in_cycles(s.writer_blocked), blocked[k]) << f->name();
      EXPECT_EQ(in_cycles(s.reader_blocked), 0) << f->name();
      EXPECT_EQ(in_cycles(s.observed), 30) << f->name();
    }
  }
}

// Producer writes one item every 2 cycles (t=0,2,4,6, then waits until 8);
// the consumer reads greedily. Each item is read in the instant it is written,
// so occupancy is 1 only for zero time: max 1, mean 0, empty all 8 cycles. The
// consumer is starved on [0,2), [2,4), [4,6) (at t=0 only for one delta): 6.
TEST(Fifo, StarvedConsumer) {
  Fifo<int> f("f", 4);
  std::vector<double> times;
  spawn([&f] {
    for (int i = 0; i < 4; ++i) {
      f.write(i);
      wait(cycles(2));
    }
  });
  spawn([&f, &times] {
    for (int i = 0; i < 4; ++i) {
      EXPECT_EQ(f.read(), i);
      times.push_back(in_cycles(sc_core::sc_time_stamp()));
    }
  });
  sc_core::sc_start();

  EXPECT_EQ(times, (std::vector<double>{0, 2, 4, 6}));
  EXPECT_EQ(in_cycles(sc_core::sc_time_stamp()), 8);
  const FifoStats s = f.stats();
  EXPECT_EQ(s.max_occupancy, 1u);
  EXPECT_DOUBLE_EQ(s.mean_occupancy, 0.0);
  EXPECT_EQ(in_cycles(s.empty), 8);
  EXPECT_EQ(in_cycles(s.full), 0);
  EXPECT_EQ(in_cycles(s.reader_blocked), 6);
  EXPECT_EQ(in_cycles(s.writer_blocked), 0);
}

// A probe that only counts: attaching one takes the reader's traced wake-up
// path (hw/fifo.h, wait_for_item): in the delta after the write, then a
// timed wait for the item's latency.
struct CountingProbe : FifoProbe<int> {
  void read_called(uint64_t) override {}
  void taken(const int&, uint64_t) override {}
  void written(const int&, uint64_t) override {}
  void blocked(bool, bool, uint64_t) override { ++intervals; }
  void occupancy(size_t, uint64_t) override {}
  int intervals = 0;
};

// A starved reader and an item still in its producer's latency, on two
// FIFOs with the same traffic: untraced, the reader sleeps until the item is
// ready; traced, it wakes in the delta after the write and waits out the
// latency. Same read times and figures either way, by hand:
//   t=0  item 0 written, ready at 3 -> read at 3;  the reader waits to 4
//   t=5  item 1, ready 8; t=6 item 2, ready 9 -> read at 8 and at 9 (ready)
//   t=16 item 3 with no latency -> read at 16, in the next delta
// starved [0,3) + [4,8) + [10,16) = 13; occupancy 1 on [0,3) and [5,6), 2 on
// [6,8), 1 on [8,9): area 9 over 17 cycles, empty 10, at most 2.
TEST(Fifo, StarvedReaderWakesAtTheReadyTimeTracedOrNot) {
  Fifo<int> plain("plain", 4), traced("traced", 4);
  CountingProbe probe;
  traced.set_probe(&probe);
  std::vector<double> times[2];
  Fifo<int>* fifos[2] = {&plain, &traced};
  for (int k = 0; k < 2; ++k) {
    Fifo<int>& f = *fifos[k];
    spawn([&f] {
      const auto now = [] { return sc_core::sc_time_stamp(); };
      f.write(0, now() + cycles(3));
      wait(cycles(5));
      f.write(1, now() + cycles(3));
      wait(cycles(1));
      f.write(2, now() + cycles(3));
      wait(cycles(10));
      f.write(3);
    });
    spawn([&f, t = &times[k]] {
      for (int i = 0; i < 4; ++i) {
        EXPECT_EQ(f.read(), i);
        t->push_back(in_cycles(sc_core::sc_time_stamp()));
        wait(cycles(1));
      }
    });
  }
  sc_core::sc_start();

  EXPECT_EQ(in_cycles(sc_core::sc_time_stamp()), 17);
  for (int k = 0; k < 2; ++k) {
    SCOPED_TRACE(k == 0 ? "untraced" : "traced");
    EXPECT_EQ(times[k], (std::vector<double>{3, 8, 9, 16}));
    const FifoStats s = fifos[k]->stats();
    EXPECT_EQ(in_cycles(s.reader_blocked), 13);
    EXPECT_DOUBLE_EQ(s.mean_occupancy, 9.0 / 17.0);
    EXPECT_EQ(in_cycles(s.empty), 10);
    EXPECT_EQ(s.max_occupancy, 2u);
    EXPECT_EQ(in_cycles(s.writer_blocked), 0);
  }
  // The traced reader's starve time is split where the item arrived: items 0
  // and 1 give two intervals each (waiting for a write, then for its
  // latency), item 3 one: 5 intervals, 10 begin/end calls.
  if constexpr (kTraceHooks) {
    EXPECT_EQ(probe.intervals, 10);
  }
}

// A reader blocked when the simulation ends is counted up to "now": the
// consumer waits from t=0 for an item that arrives at 10, then waits for one
// that never comes while the producer idles until 25: 10 + 15 cycles.
TEST(Fifo, BlockedTimeCountsUpToNow) {
  Fifo<int> f("f", 4);
  spawn([&f] {
    wait(cycles(10));
    f.write(7);
    wait(cycles(15));
  });
  spawn([&f] {
    EXPECT_EQ(f.read(), 7);
    f.read();
    ADD_FAILURE() << "read an item never written";
  });
  sc_core::sc_start();
  EXPECT_EQ(in_cycles(sc_core::sc_time_stamp()), 25);
  EXPECT_EQ(in_cycles(f.stats().reader_blocked), 25);
  EXPECT_EQ(in_cycles(f.stats().empty), 25);
  EXPECT_EQ(f.stats().read, 1u);
}

// A ready time given as sc_time_stamp() (a reference to the kernel's time)
// is the time of the call: a writer blocked from 0 to 10 on a full FIFO of
// depth 1 writes an item ready 0 cycles after the call plus its 10 cycles of
// waiting, readable at 10, not 20 (the wait counted twice when the reference
// was read after it).
TEST(Fifo, ReadyTimeGivenAsTheKernelsTimeIsTakenAtTheCall) {
  Fifo<int> f("f", 1);
  spawn([&f] {
    f.write(1);
    f.write(2, sc_core::sc_time_stamp());
  });
  std::vector<double> times;
  spawn([&f, &times] {
    wait(cycles(10));
    EXPECT_EQ(f.read(), 1);
    EXPECT_EQ(f.read(), 2);
    times.push_back(in_cycles(sc_core::sc_time_stamp()));
  });
  sc_core::sc_start();
  EXPECT_EQ(times, std::vector<double>{10});
  EXPECT_EQ(in_cycles(f.stats().writer_blocked), 10);
}

// Non-blocking access and the delta-cycle visibility rule, step by step.
TEST(Fifo, NonBlockingAccessAndDeltaVisibility) {
  Fifo<int> f("f", 2);
  bool ran = false;
  spawn([&] {
    EXPECT_EQ(f.depth(), 2u);
    EXPECT_TRUE(f.nb_write(1));
    EXPECT_TRUE(f.nb_write(2));
    EXPECT_FALSE(f.nb_write(3));  // full
    EXPECT_EQ(f.size(), 0u);      // written in this delta: readable from the next
    EXPECT_EQ(f.num_free(), 0u);
    int v = 0;
    EXPECT_FALSE(f.nb_read(v));
    wait(sc_core::SC_ZERO_TIME);
    EXPECT_EQ(f.size(), 2u);
    EXPECT_EQ(f.front(), 1);
    EXPECT_TRUE(f.nb_read(v));
    EXPECT_EQ(v, 1);
    EXPECT_EQ(f.size(), 1u);
    EXPECT_EQ(f.front(), 2);
    EXPECT_EQ(f.num_free(), 0u);  // freed in this delta: writable from the next
    wait(sc_core::SC_ZERO_TIME);
    EXPECT_EQ(f.num_free(), 1u);
    EXPECT_TRUE(f.nb_write(3));  // wraps around the ring
    wait(sc_core::SC_ZERO_TIME);
    EXPECT_TRUE(f.nb_read(v));
    EXPECT_EQ(v, 2);
    EXPECT_TRUE(f.nb_read(v));
    EXPECT_EQ(v, 3);
    EXPECT_FALSE(f.nb_read(v));
    ran = true;
  });
  sc_core::sc_start();
  EXPECT_TRUE(ran);
  EXPECT_EQ(f.stats().written, 3u);
  EXPECT_EQ(f.stats().read, 3u);
  EXPECT_EQ(f.stats().max_occupancy, 2u);
}

// A pass-through stage reached through ports: reads, works 2 cycles, writes.
struct PassStage : sc_core::sc_module {
  FifoInPort<int> in;
  FifoOutPort<int> out;
  SC_HAS_PROCESS(PassStage);
  explicit PassStage(sc_core::sc_module_name name) : sc_core::sc_module(name) { SC_THREAD(run); }
  void run() {
    for (;;) {
      const int v = in->read();
      wait(cycles(2));
      out->write(v * 10);
    }
  }
};

// An idle stage sleeps on the FIFO's event: the event-driven consumer below
// wakes once per instant with new data (t=2, 4, 6), never in between, and
// drains what is there with nb_read.
TEST(Fifo, PortsAndEventDrivenConsumer) {
  Fifo<int> a("a", 4), b("b", 4);
  PassStage stage("stage");
  stage.in(a);
  stage.out(b);
  spawn([&a] {
    for (int i = 1; i <= 3; ++i) a.write(i);
  });
  std::vector<int> values;
  std::vector<double> times;
  int wakeups = 0;
  spawn([&] {
    for (;;) {
      wait(b.data_written_event());
      ++wakeups;
      int v;
      while (b.nb_read(v)) {
        values.push_back(v);
        times.push_back(in_cycles(sc_core::sc_time_stamp()));
      }
    }
  });
  sc_core::sc_start();
  EXPECT_EQ(values, (std::vector<int>{10, 20, 30}));
  EXPECT_EQ(times, (std::vector<double>{2, 4, 6}));
  EXPECT_EQ(wakeups, 3);
  // The stage waits for `a` only after the last item, at t=6, until the end.
  EXPECT_EQ(in_cycles(sc_core::sc_time_stamp()), 6);
  EXPECT_EQ(in_cycles(a.stats().reader_blocked), 0);
  // `a` held 2 items on [0,2), 1 on [2,4), 0 after: mean (4 + 2) / 6.
  EXPECT_DOUBLE_EQ(a.stats().mean_occupancy, 1.0);
  EXPECT_EQ(a.stats().max_occupancy, 3u);
}

// Probability 1 and at most 1 cycle: every write and read first waits exactly
// one cycle. The producer writes item k at t=k+1 and the consumer, stalling
// alongside, reads it in the same instant: 10 items end at t=10 with 20
// injected stalls and no blocking.
TEST(Fifo, CertainStallsAreExact) {
  Fifo<int> f("f", 4);
  f.set_stalls(RandomStalls(f.basename(), 1, 1.0, 1, kCycle));
  std::vector<double> times;
  spawn([&f] {
    for (int i = 0; i < 10; ++i) f.write(i);
  });
  spawn([&] {
    for (int i = 0; i < 10; ++i) {
      EXPECT_EQ(f.read(), i);
      times.push_back(in_cycles(sc_core::sc_time_stamp()));
    }
  });
  sc_core::sc_start();
  EXPECT_EQ(times, (std::vector<double>{1, 2, 3, 4, 5, 6, 7, 8, 9, 10}));
  const FifoStats s = f.stats();
  EXPECT_EQ(s.injected_stalls, 20u);
  EXPECT_EQ(in_cycles(s.injected_stall), 20);
  EXPECT_EQ(in_cycles(s.writer_blocked), 0);
  EXPECT_EQ(in_cycles(s.reader_blocked), 0);
}

// Random stalls change timing, never the item sequence; the same seed gives
// the same timing.
TEST(Fifo, RandomStallsKeepSequenceAndAreDeterministic) {
  constexpr int kItems = 500;
  struct Chain {
    Fifo<int> fifo;
    std::vector<int> values;
    std::vector<double> times;
    explicit Chain(const char* name) : fifo(name, 2) {}
  };
  Chain plain("plain"), a("a"), b("b"), c("c");
  a.fifo.set_stalls(RandomStalls(a.fifo.basename(), 42, 0.3, 4, kCycle));
  b.fifo.set_stalls(RandomStalls(b.fifo.basename(), 42, 0.3, 4, kCycle));
  c.fifo.set_stalls(RandomStalls(c.fifo.basename(), 43, 0.3, 4, kCycle));
  for (Chain* ch : {&plain, &a, &b, &c}) {
    spawn([ch] {
      for (int i = 0; i < kItems; ++i) ch->fifo.write(i);
    });
    spawn([ch] {
      for (int i = 0; i < kItems; ++i) {
        ch->values.push_back(ch->fifo.read());
        ch->times.push_back(in_cycles(sc_core::sc_time_stamp()));
        wait(kCycle);  // a consumer taking one item per cycle
      }
    });
  }
  sc_core::sc_start();

  std::vector<int> expected(kItems);
  for (int i = 0; i < kItems; ++i) expected[i] = i;
  for (Chain* ch : {&plain, &a, &b, &c}) EXPECT_EQ(ch->values, expected) << ch->fifo.name();

  // Without stalls the consumer reads item i at cycle i.
  EXPECT_EQ(plain.times.back(), kItems - 1);
  EXPECT_EQ(plain.fifo.stats().injected_stalls, 0u);
  EXPECT_EQ(a.times, b.times);
  EXPECT_NE(a.times, c.times);
  EXPECT_GT(a.times.back(), plain.times.back());

  // 1000 operations drawn at p = 0.3, stall lengths uniform in 1..4 (mean 2.5).
  const FifoStats s = a.fifo.stats();
  EXPECT_GT(s.injected_stalls, 250u);
  EXPECT_LT(s.injected_stalls, 350u);
  const double mean_stall = in_cycles(s.injected_stall) / static_cast<double>(s.injected_stalls);
  EXPECT_GT(mean_stall, 2.2);
  EXPECT_LT(mean_stall, 2.8);
}

TEST(Fifo, RejectsBadParameters) {
  EXPECT_THROW(Fifo<int>("zero", 0), std::invalid_argument);
  Fifo<int> f("f", 1);
  EXPECT_THROW(f.set_stalls(RandomStalls(f.basename(), 1, 1.5, 1, kCycle)), std::invalid_argument);
  EXPECT_THROW(f.set_stalls(RandomStalls(f.basename(), 1, 0.5, 0, kCycle)), std::invalid_argument);
  EXPECT_THROW(f.set_stalls(RandomStalls(f.basename(), 1, 0.5, 1, sc_core::SC_ZERO_TIME)),
               std::invalid_argument);
}

}  // namespace
}  // namespace gpusim
