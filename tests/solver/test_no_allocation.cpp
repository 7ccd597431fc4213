// No heap allocation inside the time loop after warm-up (issue 7): Solver::step() on a
// model with joints (some breaking) and contacts allocates nothing once its buffers
// have grown. The global operator new of the test_solver binary is replaced here to
// count calls (the only replacement in test_solver; tests/contact has its own).
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "mesh/model_builder.hpp"
#include "mesh/structured.hpp"
#include "solver/constraints.hpp"
#include "solver/solver.hpp"

namespace {
std::atomic<long> g_solver_allocations{0};

void* counted_alloc(std::size_t n) {
  g_solver_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* counted_aligned_alloc(std::size_t n, std::align_val_t al) {
  g_solver_allocations.fetch_add(1, std::memory_order_relaxed);
  const std::size_t a = static_cast<std::size_t>(al);
  const std::size_t size = ((n ? n : 1) + a - 1) / a * a;
  if (void* p = std::aligned_alloc(a, size)) return p;
  throw std::bad_alloc();
}
}  // namespace

void* operator new(std::size_t n) { return counted_alloc(n); }
void* operator new[](std::size_t n) { return counted_alloc(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  try {
    return counted_alloc(n);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  try {
    return counted_alloc(n);
  } catch (...) {
    return nullptr;
  }
}
void* operator new(std::size_t n, std::align_val_t al) { return counted_aligned_alloc(n, al); }
void* operator new[](std::size_t n, std::align_val_t al) { return counted_aligned_alloc(n, al); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }

using namespace dsdem;

namespace {

// Discrete block falling onto a contact ground slab (as in test_determinism.cpp).
Model impact_model(int nx, int ny) {
  const double h = 0.01;
  RawMesh raw = mesh::rectangle_mesh(nx, ny, nx * h, ny * h, mesh::Diagonal::Alternate, 0.0, 0.02 * h, "block");
  RawMesh ground = mesh::rectangle_mesh(nx, 2, nx * h, 2 * h, mesh::Diagonal::Alternate, 0.0, -2 * h, "ground");
  for (auto& g : ground.groups)
    if (g.dim == 1) g.name = "ground_" + g.name;
  mesh::append_mesh(raw, ground);
  io::Scenario sc;
  sc.file = "(test)";
  Material rock;
  rock.name = "rock";
  rock.E = 21e9;
  rock.nu = 0.2;
  rock.rho = 2500;
  sc.materials["rock"] = rock;
  sc.regions.push_back(io::RegionSpec{"block", "rock", Zone::Discrete, {}, {}});
  sc.regions.push_back(io::RegionSpec{"ground", "rock", Zone::ContactBedrock, {}, {}});
  sc.joints.present = true;
  sc.joints.defaults.ft = 2.5e6;
  sc.joints.defaults.c = 10e6;
  sc.joints.defaults.phi_deg = 30;
  sc.joints.defaults.GI = 50;
  sc.joints.defaults.GII = 500;
  sc.contact.friction = 0.5;
  sc.contact.restitution = 0.5;
  sc.stages.push_back(io::StageSpec{});
  Model model = mesh::build_model(sc, raw);
  for (Index t : model.groups[model.find_group("block")].triangles)
    for (Index n : model.triangles.conn[t]) model.nodes.v[n] = Vec2(3.0, -20.0);
  return model;
}

void check_no_allocation(int threads, bool parallel) {
#ifdef _OPENMP
  omp_set_num_threads(threads);
#endif
  Model model = impact_model(24, 12);
  solver::Solver s(model);
  s.set_parallel(parallel);
  io::BoundarySpec fixed;
  fixed.group = "ground";
  fixed.type = io::BoundaryType::Fixed;
  s.set_constraints(solver::build_constraints(model, {fixed}, 0.0));
  s.set_settings({Vec2(0.0, -9.81), 50.0, 1e-7, 0.3 * solver::stable_time_step(model, 1e-7).dt, true});
  s.initialise();
  // Warm-up: buffers grow, threads start, and the impact's contact count passes its peak
  // (the contact buffers grow geometrically while the count rises, which is allowed).
  long warm_contacts = 0;
  for (int k = 0; k < 600; ++k) {
    s.step();
    warm_contacts = std::max<long>(warm_contacts, s.active_contacts());
  }
  const long broken_before = s.broken_joints();
  const long before = g_solver_allocations.load();
  long max_contacts = 0;
  for (int k = 0; k < 200; ++k) {
    s.step();
    max_contacts = std::max<long>(max_contacts, s.active_contacts());
  }
  const long allocations = g_solver_allocations.load() - before;
#ifdef _OPENMP
  omp_set_num_threads(1);
#endif
  EXPECT_EQ(allocations, 0) << threads << " thread(s); contacts: peak " << warm_contacts << " in warm-up, "
                            << max_contacts << " after";
  // The measured steps did the work that could allocate: contacts and breaking joints.
  EXPECT_GT(max_contacts, 0);
  EXPECT_GT(s.broken_joints(), broken_before);
}

}  // namespace

TEST(NoAllocation, CounterSeesAllocations) {
  const long before = g_solver_allocations.load();
  auto* p = new std::vector<double>(10);
  delete p;
  EXPECT_GE(g_solver_allocations.load() - before, 2);
}

TEST(NoAllocation, StepAllocatesNothingAfterWarmUpSerial) { check_no_allocation(1, false); }

TEST(NoAllocation, StepAllocatesNothingAfterWarmUpTwoThreads) { check_no_allocation(2, true); }
