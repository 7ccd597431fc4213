// Runs a few steps of a benchmark model, for profilers (callgrind, perf):
//   dsdem_profile box NX NY STEPS WARMUP   |   dsdem_profile disc H_0.1MM STEPS WARMUP
#include <cstdio>
#include <cstdlib>
#include <string>

#include "bench_models.hpp"

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
  for (int k = 0; k < warmup; ++k) s.step();
  long contacts = 0;
  for (int k = 0; k < steps; ++k) {
    s.step();
    contacts += s.active_contacts();
  }
  std::printf("elements %zu joints %zu steps %d contacts/step %.1f broken %ld\n", model.triangles.size(),
              model.joints.size(), steps, static_cast<double>(contacts) / steps, s.broken_joints());
  return 0;
}
