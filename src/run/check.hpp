#pragma once
// `dsdem check`: the model, its time step and estimates of run time, memory and output.
#include <cstddef>
#include <string>
#include <vector>

#include "run/prepare.hpp"

namespace dsdem::run {

// Prints the model summary, dt and its control, and an estimate of the run time
// measured on a few steps. Returns the text.
std::string check_report(PreparedRun& run);

// The moving water's share of the run time (run.moving_water set): a few water steps at rest
// timed (one thread, as a small pool runs), and the water steps of the settle at the stable
// step at rest and of the run at the step of water moving at c0 / 10, the speed its sound
// speed was chosen for: sub-steps of each solid step when that is shorter than the solid's,
// else one over as many solid steps as fit in it. A calm pool takes a few per cent fewer; a
// violent flow (squeezes, splashes faster than c0 / 10) more.
struct WaterEstimate {
  double per_step_s = 0.0;
  int steps_timed = 0;
  double per_solid_step = 1.0;  // water sub-steps per solid step (1: one water step over one or more)
  double steps = 0.0;           // the settle's and the run's water steps
};
WaterEstimate estimate_water_steps(const PreparedRun& run);

// Bytes of memory a run of this model needs (data structures per node, element, joint,
// plus contact buffers), and the bytes of output it will write. Estimates, for `check`.
std::size_t estimate_memory_bytes(const PreparedRun& run);
std::size_t estimate_output_bytes(const PreparedRun& run, bool write_fields = true);

// Warnings `check` prints when the run needs more memory than the machine has available
// (MemAvailable in /proc/meminfo) or longer than 24 h of wall time. Empty when fine.
std::vector<std::string> resource_warnings(std::size_t memory_bytes, std::size_t available_bytes,
                                           double wall_seconds);
// MemAvailable from /proc/meminfo in bytes; 0 when unknown.
std::size_t available_memory_bytes();

}  // namespace dsdem::run
