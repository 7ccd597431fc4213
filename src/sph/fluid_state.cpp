// The state of the water between steps, for a checkpoint (docs/user-guide.md, docs/theory.md §11): taken and
// put back whole, so that a restored fluid continues with the same bits.
#include <algorithm>
#include <stdexcept>
#include <string>

#include "sph/fluid.hpp"
#include "sph/solid_coupling.hpp"

namespace dsdem::sph {

namespace {

template <class T>
void check_count(const std::vector<T>& v, std::size_t n, const char* what) {
  if (v.size() != n)
    throw std::invalid_argument(std::string("sph state: ") + what + " has " + std::to_string(v.size()) +
                                " entries, the fluid " + std::to_string(n));
}

}  // namespace

Fluid::State Fluid::state() const {
  return {f_, b_, time_, v_max_, a_max_, damping_rate_, boundary_work_, steps_, record_, rec_fx_, rec_fy_, excluded_};
}

void Fluid::restore(const State& s) {
  const std::size_t nb = b_.size();
  const FluidParticles& f = s.fluid;
  // The particles in the state and those it had excluded make the fluid this one was built as.
  if (f.x.size() + s.excluded.size() != initial_size_)
    throw std::invalid_argument("sph state: " + std::to_string(f.x.size()) + " fluid particles and " +
                                std::to_string(s.excluded.size()) + " excluded, the fluid was built with " +
                                std::to_string(initial_size_));
  if (s.excluded.size() > excluded_capacity())
    throw std::invalid_argument("sph state: " + std::to_string(s.excluded.size()) +
                                " excluded particles, more than this fluid's excluded_limit allows");
  const std::size_t nf = f.x.size();
  for (const auto* a : {&f.x, &f.y, &f.vx, &f.vy, &f.rho, &f.p, &f.vol, &f.ax, &f.ay, &f.drho, &f.gx, &f.gy})
    check_count(*a, nf, "a fluid particle array");
  check_count(f.id, nf, "the fluid particle ids");
  const BoundaryParticles& b = s.boundary;
  for (const auto* a : {&b.x, &b.y, &b.vx, &b.vy, &b.rho, &b.p, &b.drho, &b.nx, &b.ny, &b.wall_distance, &b.s})
    check_count(*a, nb, "a boundary particle array");
  check_count(b.edge, nb, "the boundary particle edges");
  // A coupling was built on the walls' edges: they must be the same walls.
  if (!std::equal(b.edge.begin(), b.edge.end(), b_.edge.begin()))
    throw std::invalid_argument("sph state: the boundary particles ride other edges than this fluid's");
  if (s.record) {
    check_count(s.rec_fx, nb, "the recorded boundary forces (x)");
    check_count(s.rec_fy, nb, "the recorded boundary forces (y)");
  }
  f_ = f;  // into the arrays as built: fewer particles fit their capacity
  excluded_.assign(s.excluded.begin(), s.excluded.end());  // keeps the reserve
  b_ = b;
  time_ = s.time;
  steps_ = s.steps;
  v_max_ = s.v_max;
  a_max_ = s.a_max;
  damping_rate_ = s.damping_rate;
  boundary_work_ = s.boundary_work;
  record_ = s.record;
  rec_fx_ = record_ ? s.rec_fx : std::vector<double>();
  rec_fy_ = record_ ? s.rec_fy : std::vector<double>();
  sound_ = first_unsound_particle() == f_.size();
  // The cell lists of the restored positions (boundary_forces() between steps reads them)
  // and neighbour lists built from them: the uninterrupted run built its lists at another
  // step, which leaves the sums unchanged (each runs over the pairs within the support in
  // ascending index, whatever the lists hold), so the lists need not be saved.
  update_cells();
  rebuild_neighbour_lists();
}

void SolidCoupling::restore(const State& s) {
  const std::size_t n = nodes_.size();
  for (const auto* a : {&s.x_last, &s.x_next, &s.force})
    if (a->size() != n)
      throw std::invalid_argument("sph::SolidCoupling state: " + std::to_string(a->size()) + " nodes, the coupling has " +
                                  std::to_string(n));
  x_last_ = s.x_last;
  x_next_ = s.x_next;
  force_ = s.force;
  particle_sum_ = s.particle_sum;
}

}  // namespace dsdem::sph
