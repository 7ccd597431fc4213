// The linear tetrahedron kernel (fem/tet4.hpp) in an element loop: tet-evaluations per second,
// one thread, on a structured cube mesh of N = 6 n^3 tetrahedra (each cell split in six around
// its main diagonal). Structure of arrays: node positions and forces as x, y, z arrays; per
// tetrahedron its 4 node indices, Dm^-1, V0 and S0 in, det F and strain energy out. Each
// iteration zeroes the node forces, then per tetrahedron gathers 4 positions, calls
// tet_internal_force (no damping, no Cauchy stress: a step of `dsdem run`) and scatters the
// 4 forces. Counters: tets/s and B/tet, the bytes of every array the loop touches per
// tetrahedron (the node arrays' share included).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <random>
#include <vector>

#include <omp.h>

#include "common/materials.hpp"
#include "fem/tet4.hpp"
#include "mesh/model_builder3d.hpp"
#include "mesh/structured.hpp"
#include "solver/continuum3d.hpp"

using namespace dsdem;

namespace {

struct TetMesh {
  std::vector<double> x, y, z;     // current node positions, m
  std::vector<double> fx, fy, fz;  // node forces, N
  std::vector<std::array<Index, 4>> conn;
  std::vector<Mat3> Dm_inv;
  std::vector<double> volume0;
  std::vector<fem::Vec6> S0;
  std::vector<double> detF, energy;  // per tetrahedron, out

  double bytes() const {
    auto b = [](const auto& v) { return static_cast<double>(v.size() * sizeof(v[0])); };
    return b(x) + b(y) + b(z) + b(fx) + b(fy) + b(fz) + b(conn) + b(Dm_inv) + b(volume0) + b(S0) + b(detF) +
           b(energy);
  }
};

// n^3 cells of edge 1/n, six tetrahedra per cell (the Kuhn split: each a path from corner 0 to
// corner 7 along the three axes in one of the six orders), all positively oriented; nodes
// displaced by up to 1e-4 of the cell so the element is strained, and a lithostatic-like S0.
TetMesh cube_mesh(int n) {
  TetMesh m;
  const int np = n + 1;
  const double h = 1.0 / n;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> d(-1e-4 * h, 1e-4 * h);
  std::vector<Vec3> X;
  X.reserve(static_cast<std::size_t>(np) * np * np);
  for (int k = 0; k < np; ++k)
    for (int j = 0; j < np; ++j)
      for (int i = 0; i < np; ++i) X.emplace_back(i * h, j * h, k * h);
  for (const auto& p : X) {
    m.x.push_back(p.x() + d(rng));
    m.y.push_back(p.y() + d(rng));
    m.z.push_back(p.z() + d(rng));
  }
  m.fx.assign(X.size(), 0.0);
  m.fy.assign(X.size(), 0.0);
  m.fz.assign(X.size(), 0.0);
  auto node = [np](int i, int j, int k) { return static_cast<Index>(i + np * (j + np * k)); };
  const int orders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  fem::Vec6 s0;
  s0 << -1e6, -1e6, -2e6, 0.0, 0.0, 0.0;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        for (const auto& o : orders) {
          std::array<int, 3> c{i, j, k};
          std::array<Index, 4> t;
          t[0] = node(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[o[s]];
            t[s + 1] = node(c[0], c[1], c[2]);
          }
          auto g = fem::tet_reference_geometry(X[t[0]], X[t[1]], X[t[2]], X[t[3]]);
          if (g.volume < 0.0) {
            std::swap(t[1], t[2]);
            g = fem::tet_reference_geometry(X[t[0]], X[t[1]], X[t[2]], X[t[3]]);
          }
          m.conn.push_back(t);
          m.Dm_inv.push_back(g.Dm_inv);
          m.volume0.push_back(g.volume);
          m.S0.push_back(s0);
        }
  m.detF.assign(m.conn.size(), 0.0);
  m.energy.assign(m.conn.size(), 0.0);
  return m;
}

// arg: cells along a side; N = 6 n^3 tetrahedra.
void BM_TetInternalForce(benchmark::State& state) {
  TetMesh m = cube_mesh(static_cast<int>(state.range(0)));
  const std::size_t ne = m.conn.size(), nn = m.x.size();
  const fem::ElasticConstants c{8.75e9, 8.75e9};  // E = 21.9 GPa, nu = 0.25
  for (auto _ : state) {
    std::fill(m.fx.begin(), m.fx.end(), 0.0);
    std::fill(m.fy.begin(), m.fy.end(), 0.0);
    std::fill(m.fz.begin(), m.fz.end(), 0.0);
    for (std::size_t t = 0; t < ne; ++t) {
      const auto& cn = m.conn[t];
      fem::TetInput in;
      for (int a = 0; a < 4; ++a) in.x[a] = Vec3(m.x[cn[a]], m.y[cn[a]], m.z[cn[a]]);
      in.Dm_inv = m.Dm_inv[t];
      in.volume0 = m.volume0[t];
      in.S0 = m.S0[t];
      in.cauchy = false;
      fem::TetResponse r;
      std::array<Vec3, 4> no_damping;  // beta = 0: zeros nobody reads
      fem::tet_internal_force(in, c, r, no_damping);
      for (int a = 0; a < 4; ++a) {
        m.fx[cn[a]] += r.force[a].x();
        m.fy[cn[a]] += r.force[a].y();
        m.fz[cn[a]] += r.force[a].z();
      }
      m.detF[t] = r.detF;
      m.energy[t] = r.strain_energy;
    }
    benchmark::DoNotOptimize(m.fx.data());
    benchmark::DoNotOptimize(m.energy.data());
    benchmark::ClobberMemory();
  }
  state.counters["tets"] = static_cast<double>(ne);
  state.counters["nodes"] = static_cast<double>(nn);
  state.counters["B/tet"] = m.bytes() / static_cast<double>(ne);
  state.counters["tets/s"] =
      benchmark::Counter(static_cast<double>(state.iterations() * ne), benchmark::Counter::kIsRate);
}
// N = 10 368, 105 456 and 998 250 tetrahedra.
BENCHMARK(BM_TetInternalForce)->Arg(12)->Arg(26)->Arg(55)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace

// Whole steps of the 3D continuum (solver/continuum3d): a box of N = 6 n^3 tetrahedra of rock
// (law 0: linear elastic; 1: Mohr-Coulomb, elastic at this stress, so its yield check runs
// on every tetrahedron), fixed at its base, under gravity with Rayleigh mass damping, on 1 or
// 2 threads. Every tetrahedron starts from an anisotropic in-situ stress, so the law sees a
// general stress state at any size. Counters: tet-steps/s, and B/tet: the model's and the
// solver's arrays per tetrahedron (the nodes' share included).
static void BM_Continuum3DStep(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  const bool plastic = state.range(2) == 1;
  const Material rock = plastic ? test::mohr_coulomb_material("rock", 1e9, 0.25, 2500.0, 1e6, 35.0, 0.0)
                                : test::elastic_material("rock", 1e9, 0.25, 2500.0);
  Model3 model = mesh::build_model_3d(mesh::box_mesh(n, n, n, 1.0, 1.0, 1.0), rock);
  Vec6 S0;
  S0 << -2e5, -1.5e5, -3e5, 2e4, -1e4, 3e4;
  model.tetrahedra.stress0.assign(model.tetrahedra.size(), S0);
  solver::Solver3 s(model);
  std::vector<solver::PrescribedDof> base;
  for (const Index v : model.groups[static_cast<std::size_t>(model.find_group("zmin"))].nodes)
    for (int d = 0; d < 3; ++d) {
      solver::PrescribedDof dof;
      dof.node = v;
      dof.dir = d;
      base.push_back(dof);
    }
  s.set_constraints(base);
  solver::StepSettings3 st;
  st.alpha = 1.0;
  s.set_settings(st);
  s.set_parallel(threads > 1);
  omp_set_num_threads(threads);
  s.initialise();
  for (int k = 0; k < 5; ++k) s.step();  // warm-up
  for (auto _ : state) s.step();
  omp_set_num_threads(1);
  const double ne = static_cast<double>(model.tetrahedra.size());
  state.counters["tets"] = ne;
  state.counters["tet-steps/s"] =
      benchmark::Counter(ne * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["B/tet"] = static_cast<double>(s.memory_bytes()) / ne;
}
BENCHMARK(BM_Continuum3DStep)
    ->ArgsProduct({{12, 26, 55}, {1, 2}, {0, 1}})
    ->UseRealTime()->Unit(benchmark::kMillisecond)->MinTime(2.0);
