#include "run/restart.hpp"

#include <cstdint>
#include <stdexcept>

#include <fmt/format.h>

#include "mesh/node_order.hpp"

namespace dsdem::run {

namespace {

// What identifies a model in a checkpoint: its sizes (nodes, elements, joints), the name
// of its elements, its node positions' fingerprint and its gauge count.
struct ModelFacts {
  std::vector<double> size;
  const char* elements;
  double fingerprint;
  std::size_t gauges;
};

ModelFacts facts_of(const PreparedRun& run) {
  const Model& m = run.model;
  return {{static_cast<double>(m.nodes.size()), static_cast<double>(m.triangles.size()),
           static_cast<double>(m.joints.size())},
          "triangles",
          mesh::node_order_fingerprint(m.nodes.X),
          run.gauges.size()};
}

ModelFacts facts_of(const PreparedRun3& run) {
  const Model3& m = run.model;
  return {{static_cast<double>(m.nodes.size()), static_cast<double>(m.tetrahedra.size()), 0.0},
          "tetrahedra",
          mesh::node_order_fingerprint(m.nodes.X),
          run.gauges.size()};
}

// The checkpoint's model (sizes, node numbering and positions, triangle order) must be
// this scenario's: arrays of another model would be read into the wrong entities.
template <class Prepared>
void check_same_model(const io::CheckpointReader& in, const Prepared& run) {
  const ModelFacts m = facts_of(run);
  const auto size = in.doubles("runner/model_size");
  if (size != m.size)
    throw std::runtime_error(fmt::format(
        "it belongs to another model ({} nodes, {} {}, {} joints; this scenario gives {}, {}, {}): use the "
        "scenario, mesh and --set options of the original run",
        size.size() > 0 ? size[0] : 0, size.size() > 1 ? size[1] : 0, m.elements, size.size() > 2 ? size[2] : 0,
        m.size[0], m.size[1], m.size[2]));
  // Nodes are numbered by first use (mesh/node_order.hpp): node arrays in any other order
  // would be read into the wrong nodes.
  if (!in.has("runner/node_order"))
    throw std::runtime_error(
        "it was written by an older dsdem that numbered the nodes as the mesh does; this one numbers them in the "
        "order the elements use them, so its node arrays do not fit: run the scenario again from the start");
  // The triangle numbering moves every node (mesh/triangle_order.hpp); a checkpoint with
  // no record of it is from a dsdem that always kept the file's order.
  const bool spatial = in.has("runner/spatial_triangle_order") && in.integer("runner/spatial_triangle_order") != 0;
  if (spatial != run.scenario.spatial_triangle_order)
    throw std::runtime_error(fmt::format(
        "it was written with mesh.triangle_order = {}{}, this scenario gives {}: continue it with --set "
        "mesh.triangle_order={}",
        io::Scenario::triangle_order_name(spatial),
        in.has("runner/spatial_triangle_order") ? "" : " (dsdem before 2026-11-24)",
        io::Scenario::triangle_order_name(run.scenario.spatial_triangle_order), io::Scenario::triangle_order_name(spatial)));
  if (in.scalar("runner/node_order") != m.fingerprint)
    throw std::runtime_error("it belongs to another model (its node positions or their order differ): use the "
                             "scenario, mesh and --set options of the original run");
}

// The time settings must be those of the original run.
template <class Prepared>
void check_same_time_step(const io::CheckpointReader& in, const Prepared& run) {
  const double dt = in.scalar("runner/dt");
  if (dt != run.dt)
    throw std::runtime_error(fmt::format("it was made with dt = {} s, this scenario gives dt = {} s: the time settings "
                                         "and materials must be those of the original run",
                                         dt, run.dt));
  // (A checkpoint from before time.adaptive has no flag: its run may go on either way.)
  if (in.has("runner/adaptive_dt") && (in.integer("runner/adaptive_dt") != 0) != run.scenario.adaptive_dt)
    throw std::runtime_error(fmt::format("it was made with time.adaptive = {}, this scenario gives {}: the time "
                                         "settings must be those of the original run",
                                         !run.scenario.adaptive_dt, run.scenario.adaptive_dt));
}

}  // namespace

template <class Prepared>
void write_runner_state(io::CheckpointWriter& w, const RunnerState& s, const Prepared& run) {
  const ModelFacts m = facts_of(run);
  w.put("runner/dt", run.dt);
  w.put_int("runner/adaptive_dt", run.scenario.adaptive_dt ? 1 : 0);
  w.put("runner/node_order", m.fingerprint);
  w.put_int("runner/spatial_triangle_order", run.scenario.spatial_triangle_order ? 1 : 0);
  w.put("runner/model_size", m.size);
  w.put_int("runner/stage", static_cast<std::int64_t>(s.stage));
  w.put("runner/stage_starts", s.stage_starts);
  w.put("runner/scalars", std::vector<double>{s.stage_end, s.peak_kinetic, s.next_field, s.next_history,
                                               s.max_balance_error, s.wall_time_before});
  w.put("runner/counts", std::vector<double>{static_cast<double>(s.history_rows), static_cast<double>(s.fields_frames),
                                              static_cast<double>(s.cracks_frames),
                                              static_cast<double>(s.contacts_frames)});
  std::vector<double> g;
  for (const auto& x : s.gauges) g.insert(g.end(), {x.max_disp, x.max_speed, x.time_of_max_speed});
  w.put("runner/gauges", g);
  if (!s.water_watch.empty()) {
    w.put_int("runner/water_frames", static_cast<std::int64_t>(s.water_frames));
    w.put("runner/water_watch", s.water_watch);
  }
  if (!s.peak_displacement.empty()) w.put("runner/peak_displacement", s.peak_displacement);
  if (const auto& i = s.slide_impact)
    w.put("runner/slide_impact", std::vector<double>{i->time, i->entry.x(), i->entry.y(), i->slide.speed,
                                                     i->slide.thickness, i->slide.mass, i->slide.slope_deg,
                                                     i->slide.depth, i->slide.water_density});
}

template <class Prepared>
RunnerState read_runner_state(const io::CheckpointReader& in, const Prepared& run) {
  const std::size_t n_gauges = facts_of(run).gauges;
  if (!in.has("runner/dt"))
    throw std::runtime_error("this checkpoint has no run state (written by an older dsdem or by the library)");
  check_same_model(in, run);
  check_same_time_step(in, run);
  RunnerState s;
  s.time = in.scalar("time");
  s.stage = static_cast<std::size_t>(in.integer("runner/stage"));
  const std::size_t stages = run.scenario.stages.size();
  if (s.stage >= stages)
    throw std::runtime_error(fmt::format(
        "the run in it is complete (all {} stages done at t = {} s): add a stage to the scenario to continue it",
        s.stage, s.time));
  s.stage_starts = in.doubles("runner/stage_starts");
  // Inside stage s.stage: its start is recorded. A complete run's end state (stage = the
  // number of stages done) has not entered the stage added since: run() enters it.
  if (s.stage_starts.size() != s.stage + 1 && s.stage_starts.size() != s.stage)
    throw std::runtime_error("its stage record is inconsistent (damaged file?)");
  const auto sc = in.doubles("runner/scalars");
  const auto counts = in.doubles("runner/counts");
  const auto g = in.doubles("runner/gauges");
  if (sc.size() != 6 || counts.size() != 4) throw std::runtime_error("its run state is incomplete (damaged file?)");
  if (g.size() != 3 * n_gauges)
    throw std::runtime_error(fmt::format("it has {} gauges, this scenario {}: the gauges must be those of the original run",
                                         g.size() / 3, n_gauges));
  s.stage_end = sc[0];
  s.peak_kinetic = sc[1];
  s.next_field = sc[2];
  s.next_history = sc[3];
  s.max_balance_error = sc[4];
  s.wall_time_before = sc[5];
  s.history_rows = static_cast<std::size_t>(counts[0]);
  s.fields_frames = static_cast<std::size_t>(counts[1]);
  s.cracks_frames = static_cast<std::size_t>(counts[2]);
  s.contacts_frames = static_cast<std::size_t>(counts[3]);
  s.gauges.resize(n_gauges);
  for (std::size_t i = 0; i < s.gauges.size(); ++i) s.gauges[i] = {g[3 * i], g[3 * i + 1], g[3 * i + 2]};
  if (in.has("runner/water_watch")) {
    s.water_frames = static_cast<std::size_t>(in.integer("runner/water_frames"));
    s.water_watch = in.doubles("runner/water_watch");
  }
  if (in.has("runner/peak_displacement")) s.peak_displacement = in.doubles("runner/peak_displacement");
  if (in.has("runner/slide_impact")) {
    const auto v = in.doubles("runner/slide_impact");
    if (v.size() != 9) throw std::runtime_error("its slide impact record is incomplete (damaged file?)");
    SlideAtImpact i;
    i.time = v[0];
    i.entry = Vec2(v[1], v[2]);
    i.slide.speed = v[3];
    i.slide.thickness = v[4];
    i.slide.mass = v[5];
    i.slide.slope_deg = v[6];
    i.slide.depth = v[7];
    i.slide.water_density = v[8];
    s.slide_impact = i;
  }
  return s;
}

template void write_runner_state(io::CheckpointWriter&, const RunnerState&, const PreparedRun&);
template void write_runner_state(io::CheckpointWriter&, const RunnerState&, const PreparedRun3&);
template RunnerState read_runner_state(const io::CheckpointReader&, const PreparedRun&);
template RunnerState read_runner_state(const io::CheckpointReader&, const PreparedRun3&);

}  // namespace dsdem::run
