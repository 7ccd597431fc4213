// Moving (SPH) water coupled with meshed solids through the solver (docs/theory.md §11): a
// floating block at its Archimedes draft, a heavy block sinking to rest on the bed, the
// momentum balance between water and nodes at every step, the solid's energy balance with
// the water's work, the same bits for 1 and 2 threads and after a checkpoint restart.
#include <H5Cpp.h>
#include <gtest/gtest.h>

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <unistd.h>

#include "common/block_on_ground.hpp"
#include "common/remove_at_exit.hpp"
#include "common/same_bits.hpp"
#include "io/checkpoint.hpp"
#include "mesh/model_builder.hpp"
#include "mesh/structured.hpp"
#include "solver/constraints.hpp"
#include "solver/moving_water.hpp"
#include "solver/solver.hpp"
#include "sph/setup.hpp"

using namespace dsdem;

namespace {

constexpr double kG = 9.81;

// A tank [0, width] of still water `depth` deep over a bed: SPH walls at x = 0, width and
// y = 0; with `bed` > 0 a fixed contact-bedrock slab [0, width] x [0, bed] whose top face
// carries the water. A square discrete block of side `side` (cells of `cell`), lower left
// corner `corner`, density rho, joints that never break (failure off).
struct Pool {
  double width = 1.2, depth = 0.6, bed = 0.0, dp = 0.02;
  double side = 0.4, cell = 0.1, rho = 500.0, E = 5e5;
  Vec2 corner = Vec2(0.4, 0.5);
};

// A block 0.2 m square held 5 cm above water 0.4 m deep, to be dropped into it.
Pool drop_pool() {
  Pool p;
  p.width = 0.8;
  p.depth = 0.4;
  p.side = 0.2;
  p.corner = Vec2(0.3, 0.35);
  return p;
}

Model pool_model(const Pool& p) {
  io::Scenario sc = test::impact_scenario();
  Material m;
  m.name = "block";
  m.E = p.E;
  m.nu = 0.25;
  m.rho = p.rho;
  sc.materials["block"] = m;
  const int n = static_cast<int>(std::lround(p.side / p.cell));
  RawMesh raw = mesh::rectangle_mesh(n, n, p.side, p.side, mesh::Diagonal::Alternate, p.corner.x(), p.corner.y(), "block");
  sc.regions.push_back(io::RegionSpec{"block", "block", Zone::Discrete, {}, {}});
  if (p.bed > 0.0) {
    RawMesh bed = mesh::rectangle_mesh(static_cast<int>(std::lround(p.width / 0.1)), 1, p.width, p.bed,
                                       mesh::Diagonal::Alternate, 0.0, 0.0, "bed");
    for (auto& g : bed.groups)
      if (g.dim == 1) g.name = "bed_" + g.name;
    mesh::append_mesh(raw, bed);
    Material soft = m;  // fixed anyway; soft so that it leaves the time step to the block
    soft.name = "bed";
    soft.rho = 2500.0;
    sc.materials["bed"] = soft;
    sc.regions.push_back(io::RegionSpec{"bed", "bed", Zone::ContactBedrock, {}, {}});
  }
  return mesh::build_model(sc, raw);
}

// The water and its coupling to the block's outline and the bed's top face; with kick > 0
// the particle first laid moves up at kick m/s.
void add_water(solver::Solver& s, const Pool& p, bool parallel, double settling, double kick = 0.0) {
  const Model& m = s.model();
  sph::FluidParameters par;
  par.dp = p.dp;
  par.c0 = sph::sound_speed_for(p.depth, 0.0, kG);
  par.alpha = 0.1;
  const double surface = p.bed + p.depth;
  sph::FluidParticles all, water;
  sph::fill_rectangle(all, 0.0, p.bed, p.width, surface, par, surface);
  const Vec2 c0 = p.corner, c1 = p.corner + Vec2(p.side, p.side);
  for (std::size_t i = 0; i < all.size(); ++i)
    if (!(all.x[i] > c0.x() && all.x[i] < c1.x() && all.y[i] > c0.y() && all.y[i] < c1.y()))
      water.add(all.x[i], all.y[i], all.rho[i]);
  water.mass = all.mass;
  const auto& block = m.groups[m.find_group("block")].triangles;
  std::vector<sph::SolidEdge> edges = solver::exposed_edges(m, block);
  if (p.bed > 0.0)
    for (const auto& e : solver::exposed_edges(m, m.groups[m.find_group("bed")].triangles))
      if (m.nodes.X[e.a].y() == p.bed && m.nodes.X[e.b].y() == p.bed) edges.push_back(e);
  std::vector<Vec2> x(m.nodes.size());
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = m.nodes.x(static_cast<Index>(i));
  sph::BoundaryParticles walls;
  sph::add_tank_walls(walls, 0.0, 0.0, p.width, surface + 0.5 * p.depth, sph::wall_layers(par), par, surface);
  sph::lay_edge_particles(walls, edges, x, sph::wall_layers(par), par, surface);
  sph::Fluid fluid(par, std::move(water), std::move(walls), parallel);
  fluid.set_settling_damping(settling);
  if (kick > 0.0) {
    sph::Fluid::State state = fluid.state();
    const auto k = static_cast<std::size_t>(std::find(state.fluid.id.begin(), state.fluid.id.end(), 0) - state.fluid.id.begin());
    state.fluid.vy[k] = kick;
    state.v_max = kick;
    fluid.restore(state);
  }
  s.set_moving_water(std::move(fluid), std::move(edges));
}

struct Coupled {
  std::unique_ptr<Model> model;
  std::unique_ptr<solver::Solver> solver;
};

// alpha: the solid's Rayleigh mass damping (1/s); settling: the fluid's velocity damping;
// kick: add_water's.
Coupled coupled(const Pool& p, double alpha, double settling, bool parallel = false, double kick = 0.0) {
  Coupled c;
  c.model = std::make_unique<Model>(pool_model(p));
  c.solver = std::make_unique<solver::Solver>(*c.model);
  solver::Solver& s = *c.solver;
  s.set_parallel(parallel);
  if (p.bed > 0.0) {
    io::BoundarySpec fixed;
    fixed.group = "bed";
    fixed.type = io::BoundaryType::Fixed;
    s.set_constraints(solver::build_constraints(*c.model, {fixed}, 0.0));
  }
  s.set_settings({Vec2(0.0, -kG), alpha, 0.0, 0.3 * solver::stable_time_step(*c.model, 0.0).dt, false});
  add_water(s, p, parallel, settling, kick);
  s.initialise();
  return c;
}

// The mean height of the block's bottom nodes and of all its nodes.
double block_bottom(const Model& m, const Pool& p) {
  double y = 0.0;
  int n = 0;
  for (Index t : m.groups[m.find_group("block")].triangles)
    for (Index i : m.triangles.conn[t])
      if (m.nodes.X[i].y() == p.corner.y()) y += m.nodes.x(i).y(), ++n;
  return y / n;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

// A block of density 500 released with half its Archimedes draft settles at draft H / 2.
// Settling: the solid's Rayleigh mass damping alpha = 10 /s (about 0.7 of critical for the
// heave, omega = sqrt(rho_w g B / m) = 7 /s less the added mass) and the fluid's velocity
// damping 5 /s (set_settling_damping) for the tank's sloshing, 2.5 s in all. The still level
// is that of the tank test (test_fluid.cpp): the top particles' heights plus dp / 2, here
// the mean over the columns 0.1 m or more from the walls and the block. The level from the
// water's area (the particles' m / rho) and the block's submerged part is printed beside it.
TEST(MovingWater, FloatingBlockSettlesAtItsArchimedesDraft) {
  const auto t0 = std::chrono::steady_clock::now();
  Pool p;
  // dp = 0.02: the block 20 particles high, in a tank 2.5 times as wide.
  p.width = 1.0;
  p.corner = Vec2(0.3, p.depth - 0.25 * p.side);  // draft 0.1 m: half the equilibrium's
  Coupled c = coupled(p, 10.0, 5.0);
  solver::Solver& s = *c.solver;
  while (s.time() < 2.5) s.step();
  const sph::Fluid& f = *s.moving_water();
  const double bottom = block_bottom(*c.model, p);
  const int columns = static_cast<int>(std::lround(p.width / p.dp));
  std::vector<double> top(static_cast<std::size_t>(columns), -INFINITY);
  double area = 0.0;
  for (std::size_t i = 0; i < f.fluid().size(); ++i) {
    area += f.fluid().vol[i];
    const int k = std::clamp(static_cast<int>(f.fluid().x[i] / p.dp), 0, columns - 1);
    top[static_cast<std::size_t>(k)] = std::max(top[static_cast<std::size_t>(k)], f.fluid().y[i]);
  }
  double level = 0.0;
  int counted = 0;
  for (int k = 0; k < columns; ++k) {
    const double xc = (k + 0.5) * p.dp;
    if (xc < 0.1 || xc > p.width - 0.1 || (xc > p.corner.x() - 0.1 && xc < p.corner.x() + p.side + 0.1)) continue;
    level += top[static_cast<std::size_t>(k)] + 0.5 * p.dp;
    ++counted;
  }
  level /= counted;
  // level (width - side) = area - side (bottom - bed): the block fills its submerged part.
  const double level_by_area = (area - p.side * bottom) / (p.width - p.side);
  const double draft = level - bottom, expected = 0.5 * p.side;
  const auto& e = s.energy();
  std::printf("floating block: %ld solid steps of %.3g s, %ld fluid steps, %zu particles; draft %.5f m (expected "
              "%.5f, error %.2f %%; from the water's area %.5f m); speed %.2g m/s; water work %.4g J/m, balance %.2g; "
              "%.1f s\n",
              s.step_count(), s.dt(), f.steps(), f.fluid().size(), draft, expected, 100.0 * (draft / expected - 1.0),
              level_by_area - bottom, c.model->nodes.v[c.model->groups[0].nodes[0]].norm(), e.moving_water_work,
              e.balance_error(), seconds_since(t0));
  EXPECT_NEAR(draft, expected, 0.02 * expected);
  EXPECT_LT(e.moving_water_work, 0.0);  // the water held the block up as it sank to its draft
  EXPECT_LT(e.balance_error(), 1e-3);
  for (const Vec2& v : c.model->nodes.v) EXPECT_LT(v.norm(), 0.01);
}

// A block of density 2500 released under water sinks onto the bed and comes to rest there
// (contact between the block and the bed, the water squeezed out from under it). Damping as
// above (alpha 10 /s; fluid 5 /s).
TEST(MovingWater, HeavyBlockSinksToRestOnTheBed) {
  const auto t0 = std::chrono::steady_clock::now();
  Pool p;
  p.width = 0.8;
  p.depth = 0.5;
  p.bed = 0.1;
  p.side = 0.2;
  p.rho = 2500.0;
  p.E = 5e6;
  p.corner = Vec2(0.3, p.bed + 0.2);
  Coupled c = coupled(p, 10.0, 5.0);
  solver::Solver& s = *c.solver;
  double lowest_speed_check = 0.0;
  while (s.time() < 1.5) s.step();
  const double bottom = block_bottom(*c.model, p);
  for (Index i : c.model->groups[c.model->find_group("block")].nodes)
    lowest_speed_check = std::max(lowest_speed_check, c.model->nodes.v[i].norm());
  std::printf("heavy block: %ld solid steps of %.3g s, %ld fluid steps; bottom %.5f m above the bed (%.2g dp), speed "
              "%.2g m/s, contacts %ld, balance %.2g; %.1f s\n",
              s.step_count(), s.dt(), s.moving_water()->steps(), bottom - p.bed, (bottom - p.bed) / p.dp,
              lowest_speed_check, s.active_contacts(), s.energy().balance_error(), seconds_since(t0));
  EXPECT_NEAR(bottom, p.bed, 0.01 * p.side);  // on the bed (the contacts' rounding and overlap)
  EXPECT_GT(s.active_contacts(), 0);
  EXPECT_LT(lowest_speed_check, 0.01);
  EXPECT_LT(s.energy().balance_error(), 1e-3);
}

// At every step the water's forces on the nodes sum to the coupled particles' (the mean of
// the sub-steps'), and at every sub-step all walls' recorded forces are minus the walls'
// forces on the fluid: momentum passes between water and solid to round-off.
TEST(MovingWater, MomentumPassesBetweenWaterAndNodesToRoundOff) {
  const Pool p = drop_pool();
  Coupled c = coupled(p, 0.0, 0.0);
  solver::Solver& s = *c.solver;
  const sph::Fluid& f = *s.moving_water();
  const double weight = f.fluid().mass * kG * static_cast<double>(f.fluid().size());
  double worst_fluid = 0.0, worst_nodes = 0.0, peak = 0.0;
  long substeps = 0;
  s.moving_water_coupling()->set_substep_observer([&](const sph::Fluid& w) {
    const auto bx = w.recorded_boundary_force_x(), by = w.recorded_boundary_force_y();
    double sx = 0.0, sy = 0.0, mx = 0.0, my = 0.0;
    for (std::size_t k = 0; k < bx.size(); ++k) sx += bx[k], sy += by[k];
    for (std::size_t i = 0; i < w.fluid().size(); ++i)
      mx += w.fluid().mass * w.fluid().ax[i], my += w.fluid().mass * (w.fluid().ay[i] + kG);
    worst_fluid = std::max({worst_fluid, std::abs(sx + mx), std::abs(sy + my)});
    ++substeps;
  });
  while (s.time() < 0.3) {
    s.step();
    const sph::SolidCoupling& cp = *s.moving_water_coupling();
    Vec2 sum = Vec2::Zero();
    for (const Vec2& fn : cp.forces()) sum += fn;
    worst_nodes = std::max(worst_nodes, (sum - cp.particle_force_sum()).cwiseAbs().maxCoeff());
    peak = std::max(peak, cp.particle_force_sum().norm());
  }
  std::printf("drop: %ld solid steps, %ld fluid sub-steps; peak water force %.4g N/m; momentum error: fluid %.3g, "
              "nodes %.3g N/m (water weight %.4g N/m); fluid energy %.4g J/m, water work on the block %.4g J/m\n",
              s.step_count(), substeps, peak, worst_fluid, worst_nodes, weight, s.energy().fluid_energy(),
              s.energy().moving_water_work);
  EXPECT_GT(peak, 100.0);  // the block hit the water
  EXPECT_LT(worst_fluid, 1e-11 * weight);
  EXPECT_LT(worst_nodes, 1e-12 * peak);
  EXPECT_LT(s.energy().balance_error(), 1e-3);
  // The water gained at most what it took from the block (less what its viscosity and
  // diffusion dissipated; the two sides' work differ by the time discretisation).
  EXPECT_LT(s.energy().moving_water_work, 0.0);
  EXPECT_LT(s.energy().fluid_energy(), -1.01 * s.energy().moving_water_work);
}

// A damped stage (a gravity stage's Rayleigh mass damping alpha) damps the water with the
// solid: its particles' velocities decay at the same rate, so water and banks settle together;
// the next, undamped stage lets the water move freely again.
TEST(MovingWater, ADampedStageDampsTheWaterAtItsRate) {
  const Pool p = drop_pool();
  double kinetic[2] = {0.0, 0.0};
  for (const double alpha : {0.0, 20.0}) {
    Coupled c = coupled(p, 0.0, 0.0);
    solver::Solver& s = *c.solver;
    solver::StepSettings stage = s.settings();
    stage.alpha = alpha;
    s.set_settings(stage);  // a stage begins
    EXPECT_EQ(s.moving_water()->settling_damping(), alpha);
    while (s.time() < 0.3) s.step();
    kinetic[alpha > 0.0 ? 1 : 0] = s.energy().fluid_kinetic;
    stage.alpha = 0.0;
    s.set_settings(stage);  // the next stage, undamped
    EXPECT_EQ(s.moving_water()->settling_damping(), 0.0);
  }
  std::printf("water's kinetic energy at 0.3 s after the drop: undamped %.4g J/m, alpha = 20 /s %.4g J/m\n", kinetic[0],
              kinetic[1]);
  EXPECT_GT(kinetic[0], 0.0);
  EXPECT_LT(kinetic[1], 0.1 * kinetic[0]);
}

namespace {

std::uint64_t fnv(const void* data, std::size_t bytes, std::uint64_t h = 1469598103934665603ull) {
  const auto* b = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < bytes; ++i) h = (h ^ b[i]) * 1099511628211ull;
  return h;
}

}  // namespace

TEST(MovingWater, OneAndTwoThreadsGiveTheSameBits) {
  auto run = [](int threads) {
    omp_set_num_threads(threads);
    Pool p;
    p.width = 0.8;
    p.depth = 0.4;
    p.side = 0.2;
    p.corner = Vec2(0.3, 0.35);
    Coupled c = coupled(p, 0.0, 0.0, threads > 1);
    for (int k = 0; k < 150; ++k) c.solver->step();
    const sph::Fluid& f = *c.solver->moving_water();
    std::uint64_t h = fnv(c.model->nodes.u.data(), c.model->nodes.u.size() * sizeof(Vec2));
    h = fnv(c.model->nodes.v.data(), c.model->nodes.v.size() * sizeof(Vec2), h);
    h = fnv(f.fluid().x.data(), f.fluid().size() * sizeof(double), h);
    h = fnv(f.fluid().y.data(), f.fluid().size() * sizeof(double), h);
    h = fnv(f.fluid().rho.data(), f.fluid().size() * sizeof(double), h);
    omp_set_num_threads(1);
    std::printf("%d thread(s): %ld fluid steps, state %016llx\n", threads, f.steps(), static_cast<unsigned long long>(h));
    return h;
  };
  EXPECT_EQ(run(1), run(2));
}

// Checkpoints of a coupled run (docs/user-guide.md, docs/theory.md §11): the solid, the water and the coupling
// between them are saved whole, and a solver built the same way continues with the same bits.
namespace {

// The drop above with damping on both sides (the solid's Rayleigh mass damping, the
// water's settling), so that their state crosses the checkpoint too.
std::filesystem::path checkpoint_path(const std::string& tag) {
  auto path = std::filesystem::temp_directory_path() / ("dsdem_water_ckpt_" + tag + "_" + std::to_string(::getpid()) + ".h5");
  test::remove_at_exit(path);
  return path;
}

void save(const solver::Solver& s, const std::filesystem::path& path) {
  io::CheckpointWriter w(path);
  s.save(w);
  w.commit();
}

template <class T>
bool same_array(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

// The nodes' motion and accelerations, the water's particles and clock, the coupling's
// forces and the energy ledger, bit for bit.
void expect_same_run(const Coupled& a, const Coupled& b) {
  const solver::Solver &sa = *a.solver, &sb = *b.solver;
  EXPECT_EQ(sa.step_count(), sb.step_count());
  EXPECT_TRUE(test::same_motion(*a.model, sa.time(), *b.model, sb.time()));
  EXPECT_TRUE(same_array(a.model->nodes.a, b.model->nodes.a));
  const sph::Fluid &fa = *sa.moving_water(), &fb = *sb.moving_water();
  EXPECT_EQ(fa.steps(), fb.steps());
  EXPECT_EQ(fa.time(), fb.time());
  for (auto m : {&sph::FluidParticles::x, &sph::FluidParticles::y, &sph::FluidParticles::vx, &sph::FluidParticles::vy,
                 &sph::FluidParticles::rho, &sph::FluidParticles::p})
    EXPECT_TRUE(same_array(fa.fluid().*m, fb.fluid().*m));
  EXPECT_TRUE(same_array(fa.fluid().id, fb.fluid().id));
  EXPECT_TRUE(same_array(fa.boundary().x, fb.boundary().x));
  EXPECT_TRUE(same_array(fa.boundary().rho, fb.boundary().rho));
  const auto ca = a.solver->moving_water_coupling()->state(), cb = b.solver->moving_water_coupling()->state();
  EXPECT_TRUE(same_array(ca.force, cb.force));
  const solver::EnergyLedger &ea = sa.energy(), &eb = sb.energy();
  EXPECT_EQ(std::memcmp(&ea, &eb, sizeof(ea)), 0) << "the energy ledgers differ: moving water work "
                                                   << ea.moving_water_work << " / " << eb.moving_water_work;
}

}  // namespace

// Run A, on one thread, checkpoints just before a re-sort of the water and just after it
// and goes on; B, built the same way on two threads, restores either file and runs to the
// same step: the same bits, across the next re-sorts.
TEST(MovingWater, CheckpointRestartContinuesBitIdentically) {
  const auto t0 = std::chrono::steady_clock::now();
  const Pool p = drop_pool();
  const long resort = sph::FluidParameters{}.resort_interval;
  omp_set_num_threads(1);
  Coupled a = coupled(p, 2.0, 5.0, false);
  for (int k = 0; k < 20; ++k) a.solver->step();
  struct Saved {
    std::filesystem::path path;
    long fluid_steps;
  };
  std::vector<Saved> saved;
  for (const long phase : {resort - 1, 0L}) {
    while (a.solver->moving_water()->steps() % resort != phase && a.solver->step_count() < 200) a.solver->step();
    const long fluid_steps = a.solver->moving_water()->steps();
    ASSERT_EQ(fluid_steps % resort, phase);
    saved.push_back({checkpoint_path("phase" + std::to_string(phase)), fluid_steps});
    save(*a.solver, saved.back().path);
  }
  const long end = a.solver->step_count() + 40;
  while (a.solver->step_count() < end) a.solver->step();
  ASSERT_GT(a.solver->moving_water()->steps() / resort, saved.front().fluid_steps / resort + 2)
      << "the test must cross re-sorts";
  omp_set_num_threads(2);
  for (const Saved& s : saved) {
    Coupled b = coupled(p, 2.0, 5.0, true);
    b.solver->restore(io::CheckpointReader(s.path));
    EXPECT_EQ(b.solver->moving_water()->steps(), s.fluid_steps);
    while (b.solver->step_count() < end) b.solver->step();
    expect_same_run(a, b);
    std::printf("checkpoint at fluid step %ld (re-sort phase %ld), restored on 2 threads: %ld solid, %ld fluid steps "
                "at the end, moving water work %.6g J/m\n",
                s.fluid_steps, s.fluid_steps % resort, b.solver->step_count(), b.solver->moving_water()->steps(),
                b.solver->energy().moving_water_work);
  }
  omp_set_num_threads(1);
  std::printf("checkpoint restarts: %.1f s\n", seconds_since(t0));
}

// The water steps at its own stable step (docs/theory.md §11): a block a hundred times stiffer
// takes solid steps ten times shorter than the water's, and the water advances once over as
// many of them as fit in its step, landing on the solid's time, its force on the nodes held in
// between. The drop's energy balance closes as in the drop above, and a checkpoint taken
// while the water waits restarts with the same bits.
TEST(MovingWater, WaterStepsAtItsOwnStepOverShorterSolidSteps) {
  Pool p = drop_pool();
  p.E = 5e7;
  omp_set_num_threads(1);
  Coupled a = coupled(p, 0.0, 0.0);
  solver::Solver& s = *a.solver;
  const sph::Fluid& f = *s.moving_water();
  long advances = 0, held = 0;
  double peak = 0.0;
  std::filesystem::path saved;
  long saved_at = -1;
  while (s.time() < 0.15) {
    const long before = f.steps();
    const double t0 = f.time(), allowed = f.stable_dt();
    const std::vector<Vec2> force(s.moving_water_coupling()->forces().begin(), s.moving_water_coupling()->forces().end());
    s.step();
    const auto now = s.moving_water_coupling()->forces();
    peak = std::max(peak, s.moving_water_coupling()->particle_force_sum().norm());
    if (f.steps() == before) {
      ++held;
      ASSERT_EQ(std::memcmp(force.data(), now.data(), force.size() * sizeof(Vec2)), 0) << "a held force changed";
      if (saved_at < 0 && s.time() > 0.1) {  // in the middle of the water's step, after impact
        saved = checkpoint_path("waiting");
        save(s, saved);
        saved_at = s.step_count();
      }
      continue;
    }
    ++advances;
    ASSERT_EQ(f.steps(), before + 1) << "the water needs no sub-steps here";
    EXPECT_LE(f.time() - t0, allowed * (1.0 + 1e-12));
    EXPECT_NEAR(f.time(), s.time(), 1e-12);
  }
  std::printf("stiff drop: %ld solid steps of %.3g s, %ld water steps (%ld solid steps with the force held), peak "
              "water force %.4g N/m, balance %.3g, moving water work %.4g J/m\n",
              s.step_count(), s.settings().dt, advances, held, peak, s.energy().balance_error(),
              s.energy().moving_water_work);
  EXPECT_GT(peak, 100.0);  // the block hit the water
  EXPECT_GT(held, 5 * advances);
  EXPECT_LT(s.energy().balance_error(), 1e-3);
  ASSERT_GT(saved_at, 0);
  Coupled b = coupled(p, 0.0, 0.0);
  b.solver->restore(io::CheckpointReader(saved));
  while (b.solver->step_count() < s.step_count()) b.solver->step();
  expect_same_run(a, b);
}

// A checkpoint of another set-up is refused with the entry named, before anything is
// restored: moving water in the file but not in the solver, the reverse, another particle
// count. A run without moving water writes no entry of it.
// Water faster than its sound speed is no longer weakly compressible water: the step stops
// the run naming the particle (its creation id, as water.pvd's particle_id) before the
// water's forces crush an element. A water of sound particles runs on.
TEST(MovingWater, WaterBeyondItsWeaklyCompressibleRangeStopsTheRunNamingTheParticle) {
  const Pool p = drop_pool();
  Coupled calm = coupled(p, 0.0, 0.0);
  EXPECT_TRUE(calm.solver->moving_water()->sound());
  for (int k = 0; k < 5; ++k) calm.solver->step();
  EXPECT_TRUE(calm.solver->moving_water()->sound());
  const double c0 = sph::sound_speed_for(p.depth, 0.0, kG);
  Coupled c = coupled(p, 0.0, 0.0, false, 3.0 * c0);
  EXPECT_FALSE(c.solver->moving_water()->sound());
  try {
    c.solver->step();
    FAIL() << "no instability reported";
  } catch (const solver::InstabilityError& e) {
    EXPECT_EQ(e.kind, "water_unsound");
    EXPECT_EQ(e.id, 0);
    EXPECT_NE(std::string(e.what()).find("particle 0 at"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("weakly compressible"), std::string::npos) << e.what();
  }
}

TEST(MovingWater, CheckpointOfAnotherSetUpIsRefused) {
  const Pool p = drop_pool();
  Coupled wet = coupled(p, 0.0, 0.0);
  for (int k = 0; k < 3; ++k) wet.solver->step();
  const auto wet_path = checkpoint_path("wet");
  save(*wet.solver, wet_path);

  Model dry_model = pool_model(p);
  solver::Solver dry(dry_model);
  dry.set_settings(wet.solver->settings());
  dry.initialise();
  auto expect_refused = [](solver::Solver& s, const std::filesystem::path& path, const std::string& words) {
    try {
      s.restore(io::CheckpointReader(path));
      ADD_FAILURE() << "a checkpoint of another set-up was accepted";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("'water_sph/counts'"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
    EXPECT_EQ(s.step_count(), 0);  // nothing restored
  };
  expect_refused(dry, wet_path, "this solver has none");

  const auto dry_path = checkpoint_path("dry");
  save(dry, dry_path);
  EXPECT_FALSE(H5::H5File(dry_path.string(), H5F_ACC_RDONLY).nameExists("water_sph"));
  Coupled fresh = coupled(p, 0.0, 0.0);
  expect_refused(*fresh.solver, dry_path, "without moving (SPH) water");

  Pool wider = p;
  wider.width = 0.84;
  Coupled other = coupled(wider, 0.0, 0.0);
  expect_refused(*other.solver, wet_path, "fluid particles");
}
