// Runs a few steps of SPH water alone, for profilers (callgrind, perf) and bit checks:
//   dsdem_profile_sph N STEPS WARMUP
// BM_SphTank's tank (N x N fluid particles at rest, dp = 0.01 m), one thread unless
// OMP_NUM_THREADS says otherwise. Prints the particle count and an FNV-1a hash of the
// fluid's positions, velocities and densities after the steps.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "sph/fluid.hpp"
#include "sph_tank.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

using namespace dsdem;

namespace {

std::uint64_t fnv1a(std::uint64_t h, const std::vector<double>& v) {
  const auto* p = reinterpret_cast<const unsigned char*>(v.data());
  for (std::size_t k = 0; k < v.size() * sizeof(double); ++k) h = (h ^ p[k]) * 1099511628211ull;
  return h;
}

}  // namespace

int main(int argc, char** argv) {
  const int n = argc > 1 ? std::atoi(argv[1]) : 0;
  if (n < 2) {
    std::fprintf(stderr, "usage: %s N STEPS WARMUP  (N x N fluid particles, N >= 2)\n", argv[0]);
    return 2;
  }
  const int steps = argc > 2 ? std::atoi(argv[2]) : 20;
  const int warmup = argc > 3 ? std::atoi(argv[3]) : 5;
  bool parallel = false;
#ifdef _OPENMP
  parallel = omp_get_max_threads() > 1;
#endif
  sph::Fluid fluid = bench::sph_tank(n, parallel);
  const double dt = fluid.stable_dt();
  for (int k = 0; k < warmup; ++k) fluid.step(dt);
  for (int k = 0; k < steps; ++k) fluid.step(dt);
  std::uint64_t h = 1469598103934665603ull;
  for (const auto* a : {&fluid.fluid().x, &fluid.fluid().y, &fluid.fluid().vx, &fluid.fluid().vy, &fluid.fluid().rho})
    h = fnv1a(h, *a);
  std::printf("particles %zu boundary %zu steps %d state %016llx\n", fluid.fluid().size(), fluid.boundary().size(),
              steps, static_cast<unsigned long long>(h));
  return 0;
}
