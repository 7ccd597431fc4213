// SPH water alone (docs/theory.md §11): particle-steps per second per core for a tank of water
// at rest, 10^4 and 10^5 fluid particles (square tanks), one thread. The step is the full
// sph::Fluid::step: both neighbour passes, the cell lists, the boundary and the re-sorts.
#include <benchmark/benchmark.h>

#include <cmath>

#include "sph/fluid.hpp"
#include "sph_tank.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

using namespace dsdem;

namespace {

// args: fluid particles along one side (n x n), threads.
void BM_SphTank(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0)), threads = static_cast<int>(state.range(1));
#ifdef _OPENMP
  omp_set_num_threads(threads);
#endif
  sph::Fluid fluid = bench::sph_tank(n, threads > 1);
  const double dt = fluid.stable_dt();
  for (int k = 0; k < 5; ++k) fluid.step(dt);
  for (auto _ : state) fluid.step(dt);
  const double particles = static_cast<double>(fluid.fluid().size());
  state.counters["particles"] = particles;
  state.counters["boundary"] = static_cast<double>(fluid.boundary().size());
  state.counters["threads"] = threads;
  state.counters["particle_steps/s"] =
      benchmark::Counter(particles * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
#ifdef _OPENMP
  omp_set_num_threads(1);
#endif
}
BENCHMARK(BM_SphTank)->Args({100, 1})->Iterations(200)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SphTank)->Args({316, 1})->Iterations(20)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace
