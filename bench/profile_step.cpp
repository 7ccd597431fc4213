// Runs a few steps of a benchmark model, for profilers (callgrind, perf):
//   dsdem_profile box NX NY STEPS WARMUP   |   dsdem_profile disc H_0.1MM STEPS WARMUP
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <string>

#include "bench_models.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

using namespace dsdem;

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s box NX NY STEPS WARMUP | disc H STEPS WARMUP\n", argv[0]);
    return 2;
  }
  const std::string kind = argv[1];
  Model model;
  std::vector<solver::PrescribedDof> dofs;
  Vec2 g = Vec2::Zero();
  int a = 2;
  // Arguments checked before any model is built: a disc H in metres (0.005) instead of
  // tenths of a millimetre (50) asked for a ~10^10-cell mesh and aborted in bad_alloc.
  const bool box_ok = kind == "box" && argc >= 4 && std::atoi(argv[2]) >= 1 && std::atoi(argv[3]) >= 1;
  const bool disc_ok = kind == "disc" && argc >= 3 && std::atof(argv[2]) >= 5.0 && std::atof(argv[2]) <= 500.0;
  if (!box_ok && !disc_ok) {
    std::fprintf(stderr,
                 "usage: %s box NX NY STEPS WARMUP | disc H STEPS WARMUP\n"
                 "  box: NX, NY >= 1 cells; disc: H the element size in 0.1 mm, 5 to 500 (50 = 5 mm)\n",
                 argv[0]);
    return 2;
  }
  if (kind == "box") {
    model = bench::box_model(std::atoi(argv[2]), std::atoi(argv[3]));
    dofs = bench::box_constraints(model);
    g = Vec2(0.0, -9.81);
    a = 4;
  } else {
    model = bench::disc_model(1e-4 * std::atof(argv[2]));
    dofs = bench::disc_constraints(model);
    a = 3;
  }
  const int steps = argc > a ? std::atoi(argv[a]) : 100;
  const int warmup = argc > a + 1 ? std::atoi(argv[a + 1]) : 20;
  solver::Solver s(model);
  bench::prepare(s, std::move(dofs), g);
  // As the benchmark: OpenMP on whenever more than one thread is given (the solver would
  // otherwise choose by size and by timing, which makes profiles of small models serial).
#ifdef _OPENMP
  s.set_parallel(omp_get_max_threads() > 1);
#endif
  for (int k = 0; k < warmup; ++k) s.step();
  long contacts = 0, examined = 0;
  for (int k = 0; k < steps; ++k) {
    s.step();
    contacts += s.active_contacts();
    examined += s.contact_stats().examined_pairs;
  }
  // FNV-1a of every displacement and velocity bit: optimisations must leave it unchanged.
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&h](const Vec2& w) {
    for (int d = 0; d < 2; ++d) {
      std::uint64_t b;
      const double x = w[d];
      std::memcpy(&b, &x, sizeof b);
      h = (h ^ b) * 1099511628211ull;
    }
  };
  for (std::size_t i = 0; i < model.nodes.size(); ++i) mix(model.nodes.u[i]), mix(model.nodes.v[i]);
  std::printf("elements %zu joints %zu steps %d contacts/step %.1f examined pairs/step %.1f broken %ld broad-phase builds %ld state %016llx\n",
              model.triangles.size(), model.joints.size(), steps, static_cast<double>(contacts) / steps,
              static_cast<double>(examined) / steps, s.broken_joints(),
              s.contact() ? s.contact()->broad_phase().builds() : 0L, static_cast<unsigned long long>(h));
  return 0;
}
