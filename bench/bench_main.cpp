// dsdem benchmarks: kernels (triangle internal force, joint law, narrow and
// broad phase) and whole runs (synthetic box of breakable elements at 10^3..10^6
// elements, synthetic Brazilian disc). Counters: element-steps/s (elem_steps/s),
// contacts/s, peak and current memory; wall time is Google Benchmark's own.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <sys/resource.h>
#include <cstring>
#include <fstream>
#include <memory>
#include <random>
#include <string>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "bench_models.hpp"
#include "contact/broad_phase.hpp"
#include "contact/narrow_phase.hpp"
#include "contact/spheropolygon.hpp"
#include "fem/cst.hpp"
#include "joint/joint_force.hpp"

using namespace dsdem;

namespace {

// VmHWM / VmRSS of this process, bytes.
double proc_status_kb(const char* key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  const std::size_t n = std::strlen(key);
  while (std::getline(in, line))
    if (line.compare(0, n, key) == 0) return std::atof(line.c_str() + n + 1);
  return 0.0;
}
double peak_bytes() { return 1024.0 * proc_status_kb("VmHWM"); }
double rss_bytes() { return 1024.0 * proc_status_kb("VmRSS"); }

void set_threads(int t) {
#ifdef _OPENMP
  omp_set_num_threads(t);
#else
  (void)t;
#endif
}

// --- kernels ---------------------------------------------------------------------

// The element loop of the solver on a 4096-triangle patch: gather x (and v with beta);
// kernel; store force, energy, det F, and the damping forces with beta (as the solver's
// shared triangles do). cauchy:0 is a step of `dsdem run` (stress on demand: no Cauchy
// stress, nothing else stored); cauchy:1 a step with the stress and strain of every
// triangle computed and stored (output, or a solver without stress on demand).
// items = element evaluations.
void BM_TriangleInternalForce(benchmark::State& state) {
  const bool damping = state.range(0) != 0;
  const bool cauchy = state.range(1) != 0;
  const int nx = 64, ny = 32;
  Material rock;
  rock.name = "rock";
  rock.E = 21e9;
  rock.nu = 0.2;
  rock.rho = 2500;
  Model model = mesh::build_model(mesh::rectangle_mesh(nx, ny, 1.0, 0.5), rock);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> d(-1e-4, 1e-4);
  for (std::size_t i = 0; i < model.nodes.size(); ++i) {
    model.nodes.u[i] = Vec2(d(rng), d(rng));
    model.nodes.v[i] = Vec2(d(rng), d(rng));
  }
  auto& tri = model.triangles;
  const auto& n = model.nodes;
  const std::size_t ne = tri.size();
  const fem::ElasticConstants c{model.materials[0].lambda(), model.materials[0].mu()};
  std::vector<std::array<Vec2, 3>> force(ne), dforce(damping ? ne : 0);
  std::vector<double> energy(ne), detF(ne);
  if (cauchy) {
    tri.stress.assign(ne, Vec3::Zero());  // output buffers (empty in a built model)
    tri.strain.assign(ne, Vec3::Zero());
  }
  for (auto _ : state) {
    for (std::size_t t = 0; t < ne; ++t) {
      const auto& cn = tri.conn[t];
      fem::TriangleInput in;
      for (int k = 0; k < 3; ++k) in.x[k] = n.X[cn[k]] + n.u[cn[k]];
      if (damping)  // the kernel reads v only when beta > 0 (as the solver gathers it)
        for (int k = 0; k < 3; ++k) in.v[k] = n.v[cn[k]];
      in.Dm_inv = tri.Dm_inv[t];
      in.area0 = tri.area0[t];
      in.S0 = tri.initial_stress(t);
      in.beta = damping ? 1e-6 : 0.0;
      in.cauchy = cauchy;
      fem::TriangleResponse r;
      std::array<Vec2, 3> no_damping;  // beta = 0: zeros nobody reads (the solver's own stack array)
      fem::triangle_internal_force(in, c, r, damping ? dforce[t] : no_damping);
      force[t] = r.force;
      if (cauchy) {
        tri.stress[t] = r.cauchy;
        tri.strain[t] = r.green;
      }
      energy[t] = r.strain_energy;
      detF[t] = r.detF;
    }
    benchmark::DoNotOptimize(force.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * ne));
  state.counters["elem_steps/s"] = benchmark::Counter(static_cast<double>(state.iterations() * ne), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_TriangleInternalForce)->ArgsProduct({{0, 1}, {0, 1}})->ArgNames({"beta", "cauchy"});

// The cohesive law of 4096 intact joints in the elastic / softening range.
void BM_JointLaw(benchmark::State& state) {
  JointProperties p;
  p.kn = p.ks = 2e13;
  p.ft = 2.5e6;
  p.c = 20e6;
  p.phi = 0.785;
  p.GI = 120;
  p.GII = 1500;
  const int nj = 4096;
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> d(-1e-7, 1.5e-7);
  std::vector<JointNodePositions> x(nj);
  std::vector<JointSeparations> delta(nj);
  std::vector<std::array<JointPointState, 2>> st(nj);
  for (int j = 0; j < nj; ++j) {
    const Vec2 a0(0.01 * j, 0.0), a1(0.01 * j + 0.01, 0.0);
    delta[j] = {Vec2(d(rng), d(rng)), Vec2(d(rng), d(rng))};
    x[j] = {a0, a1, a0 + delta[j][0], a1 + delta[j][1]};
  }
  double sink = 0.0;
  for (auto _ : state) {
    for (int j = 0; j < nj; ++j) {
      const JointForceResult r = joint_force(x[j], delta[j], 0.01, p, st[j], true);
      sink += r.f[0].x();
    }
    benchmark::DoNotOptimize(sink);
  }
  state.counters["joint_steps/s"] = benchmark::Counter(static_cast<double>(state.iterations() * nj), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_JointLaw);

// Narrow phase of 4096 overlapping pairs of rounded triangles (vertex-edge contacts).
void BM_NarrowPhase(benchmark::State& state) {
  using namespace contact;
  const int np = 4096;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> d(-0.2, 0.2);
  std::vector<Spheropolygon> a(np), b(np);
  std::vector<CoreEdges> ea(np), eb(np);
  for (int k = 0; k < np; ++k) {
    const Vec2 o(d(rng), d(rng));
    a[k] = make_spheropolygon(Vec2(0, 0), Vec2(1, 0), Vec2(0, 1), 0.05);
    b[k] = make_spheropolygon(Vec2(0.52, 0.52) + 0.05 * o, Vec2(1.52, 0.52) + 0.05 * o, Vec2(0.52, 1.52) + 0.05 * o, 0.05);
    ea[k] = core_edges(a[k].core);
    eb[k] = core_edges(b[k].core);
  }
  std::array<ContactGeometry, kMaxContactsPerPair> out;
  long contacts = 0;
  for (auto _ : state) {
    for (int k = 0; k < np; ++k) contacts += narrow_phase(a[k], ea[k], b[k], eb[k], out);
    benchmark::DoNotOptimize(out);
  }
  state.counters["pairs/s"] = benchmark::Counter(static_cast<double>(state.iterations() * np), benchmark::Counter::kIsRate);
  state.counters["contacts/pair"] = static_cast<double>(contacts) / static_cast<double>(state.iterations() * np);
}
BENCHMARK(BM_NarrowPhase);

// Broad-phase build over the triangles of a discrete block (every triangle its own
// nodes, as in zone A), excluding pairs that share a node.
void BM_BroadPhase(benchmark::State& state) {
  const int side = static_cast<int>(state.range(0));
  RawMesh raw = mesh::rectangle_mesh(side, side, side * 0.01, side * 0.01);
  io::Scenario sc = bench::rock_scenario();
  raw.groups[0].name = "block";
  sc.regions.push_back(io::RegionSpec{"block", "rock", Zone::Discrete, {}, {}});
  Model model = mesh::build_model(sc, raw);
  std::vector<Vec2> x(model.nodes.size());
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = model.nodes.X[i];
  contact::BroadPhase bp;
  const auto& conn = model.triangles.conn;
  for (auto _ : state) {
    bp.build(x, conn, model.contact.active, 0.001,
             [&conn](Index i, Index j) {
               for (Index p : conn[i])
                 for (Index q : conn[j])
                   if (p == q) return true;
               return false;
             });
    benchmark::DoNotOptimize(bp.pairs().data());
  }
  state.counters["triangles/s"] =
      benchmark::Counter(static_cast<double>(state.iterations() * conn.size()), benchmark::Counter::kIsRate);
  state.counters["pairs"] = static_cast<double>(bp.pairs().size());
}
BENCHMARK(BM_BroadPhase)->Arg(32)->Arg(256)->Unit(benchmark::kMillisecond);

// --- whole runs --------------------------------------------------------------------

// Steps a model: counters element-steps/s, contacts/s (contact evaluations per second),
// broken joints, peak memory and memory per element.
// CPU time of the whole process (all threads), s.
double process_cpu_seconds() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return static_cast<double>(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}

// threads > 1 forces OpenMP on (the solver's own timed choice would fall back to one
// thread on a loaded machine, hiding the scaling this measures); 1 forces it off.
void run_steps(benchmark::State& state, Model& model, std::vector<solver::PrescribedDof> dofs, Vec2 gravity, int warmup,
               double rss_before, int threads) {
  solver::Solver s(model);
  s.set_parallel(threads > 1);
  bench::prepare(s, std::move(dofs), gravity);
  for (int k = 0; k < warmup; ++k) s.step();
  double load[3] = {0.0, 0.0, 0.0};
  getloadavg(load, 3);
  double contacts = 0.0, examined = 0.0;
  const double cpu0 = process_cpu_seconds();
  for (auto _ : state) {
    s.step();
    contacts += static_cast<double>(s.active_contacts());
    examined += static_cast<double>(s.contact_stats().examined_pairs);
  }
  // CPU seconds per step, all threads (the main-thread CPU time that Google Benchmark
  // reports misses the second thread).
  state.counters["proc_cpu_s/step"] = (process_cpu_seconds() - cpu0) / static_cast<double>(state.iterations());
  state.counters["load1"] = load[0];
  const double ne = static_cast<double>(model.triangles.size());
  const double steps = static_cast<double>(state.iterations());
  state.counters["elements"] = ne;
  state.counters["elem_steps/s"] = benchmark::Counter(steps * ne, benchmark::Counter::kIsRate);
  state.counters["contacts/s"] = benchmark::Counter(contacts, benchmark::Counter::kIsRate);
  state.counters["contacts"] = contacts / steps;
  // The narrow phase's load per element: what a size's motion asks of the contact phase.
  state.counters["examined/elem"] = examined / (steps * ne);
  state.counters["broken"] = static_cast<double>(s.broken_joints());
  state.counters["joints"] = static_cast<double>(model.joints.size());
  state.counters["peak_MB"] = peak_bytes() / 1e6;
  state.counters["B/elem"] = (rss_bytes() - rss_before) / ne;
}

// Box of breakable elements: args (cells along x, cells along y, threads).
// Elements = 2 nx ny (block) + 4 nx (ground).
void BM_WholeBox(benchmark::State& state) {
  const int nx = static_cast<int>(state.range(0)), ny = static_cast<int>(state.range(1));
  set_threads(static_cast<int>(state.range(2)));
  const double rss0 = rss_bytes();
  Model model = bench::box_model(nx, ny);
  run_steps(state, model, bench::box_constraints(model), Vec2(0.0, -9.81), 20, rss0, static_cast<int>(state.range(2)));
  state.counters["threads"] = static_cast<double>(state.range(2));
  set_threads(1);
}
// ~10^3, 10^4, 10^5, 10^6 elements; 1 and 2 threads. Fixed step counts (each step of
// 10^6 elements takes about a second), all within the same phase of the motion: steps 20
// to 120 at most, the block's bottom row on the ground, no joint broken yet. (10^3 used to
// run 1 000 steps, into the impact that breaks ~100 of its joints: 190 against 124 ns per
// element-step on one thread, a different load from the other sizes' measured steps.)
BENCHMARK(BM_WholeBox)->Args({22, 20, 1})->Args({22, 20, 2})->Iterations(100)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_WholeBox)->Args({72, 68, 1})->Args({72, 68, 2})->Iterations(100)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_WholeBox)->Args({224, 222, 1})->Args({224, 222, 2})->Iterations(10)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_WholeBox)->Args({710, 702, 1})->Args({710, 702, 2})->Iterations(3)->UseRealTime()->Unit(benchmark::kMillisecond);
// Strips: boxes 20 cells high, 10^4 to 10^6 elements (10^3 is the 22 x 20 box above), over
// the same steps 20 to 120. The square boxes' steps cover different motions per element at
// each size: the impact's wave crosses the 20 rows of 10^3 in ~70 steps but only the lowest
// ~40 of 222 or 702 rows in the window, and the pairs examined per element-step differ
// threefold (0.077 at 10^3, 0.23-0.25 at 10^4 and 10^5). A strip's columns all move as
// the 10^3 box's do, so its time per element-step measures the cost of size alone.
BENCHMARK(BM_WholeBox)->Args({227, 20, 1})->Iterations(100)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_WholeBox)->Args({2272, 20, 1})->Iterations(100)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_WholeBox)->Args({22727, 20, 1})->Iterations(100)->UseRealTime()->Unit(benchmark::kMillisecond);

// Synthetic Brazilian disc (see bench_models.hpp): args (element size in 0.1 mm, threads).
void BM_WholeDisc(benchmark::State& state) {
  set_threads(static_cast<int>(state.range(1)));
  const double rss0 = rss_bytes();
  Model model = bench::disc_model(1e-4 * static_cast<double>(state.range(0)));
  run_steps(state, model, bench::disc_constraints(model), Vec2::Zero(), 200, rss0, static_cast<int>(state.range(1)));
  state.counters["threads"] = static_cast<double>(state.range(1));
  set_threads(1);
}
BENCHMARK(BM_WholeDisc)->Args({50, 1})->Args({50, 2})->Iterations(1000)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_WholeDisc)->Args({20, 1})->Args({20, 2})->Iterations(200)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
