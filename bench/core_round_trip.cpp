// The time a cache line takes to go from one core to another and back (two threads, one
// per CPU, passing a counter), for `make bench` to record with its 2-thread numbers: on a
// virtual machine it changes from minute to minute, and with it every 2-thread speed-up
// (profile: 105-170 ns in calm spells, 400-550 ns in far ones on the lead's VM).
// Prints "round_trip_ns <median of the batches>" for the first two CPUs this process may
// use, or "round_trip_ns n/a (<why>)": fewer than two CPUs, or the two threads not both
// running (a batch over 50 ms), so that a restricted machine never makes it hang.
#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <thread>
#include <vector>

namespace {

void pin_to(int cpu) {
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  pthread_setaffinity_np(pthread_self(), sizeof set, &set);
}

}  // namespace

int main() {
  cpu_set_t allowed;
  CPU_ZERO(&allowed);
  std::vector<int> cpus;
  if (sched_getaffinity(0, sizeof allowed, &allowed) == 0)
    for (int c = 0; c < CPU_SETSIZE && cpus.size() < 2; ++c)
      if (CPU_ISSET(c, &allowed)) cpus.push_back(c);
  if (cpus.size() < 2) {
    std::printf("round_trip_ns n/a (fewer than two CPUs)\n");
    return 0;
  }
  constexpr int kBatches = 21;
  constexpr long kTrips = 2000;
  constexpr double kBatchLimitS = 0.05;
  // Odd: the first thread's move made, the second's awaited; even: the other way round.
  alignas(64) std::atomic<long> counter{0};
  alignas(64) std::atomic<bool> stop{false};
  std::thread partner([&] {
    pin_to(cpus[1]);
    for (long k = 0; k < kBatches * kTrips; ++k) {
      while (counter.load(std::memory_order_acquire) != 2 * k + 1)
        if (stop.load(std::memory_order_relaxed)) return;
      counter.store(2 * k + 2, std::memory_order_release);
    }
  });
  pin_to(cpus[0]);
  std::array<double, kBatches> ns{};
  bool slow = false;
  for (int b = 0; b < kBatches && !slow; ++b) {
    const auto start = std::chrono::steady_clock::now();
    for (long k = b * kTrips; k < (b + 1) * kTrips && !slow; ++k) {
      counter.store(2 * k + 1, std::memory_order_release);
      for (long spins = 1; counter.load(std::memory_order_acquire) != 2 * k + 2; ++spins) {
        if (spins % 4096 == 0 &&
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > kBatchLimitS) {
          slow = true;
          break;
        }
      }
    }
    ns[b] = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - start).count() / kTrips;
  }
  stop.store(true, std::memory_order_relaxed);
  partner.join();
  if (slow) {
    std::printf("round_trip_ns n/a (CPUs %d and %d not both running this process)\n", cpus[0], cpus[1]);
    return 0;
  }
  std::sort(ns.begin(), ns.end());
  std::printf("round_trip_ns %.0f\n", ns[kBatches / 2]);
  return 0;
}
