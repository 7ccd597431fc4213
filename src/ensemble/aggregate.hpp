#pragma once
// The ensemble's aggregates (docs/theory.md §13), from the member folders on disk:
//   OUT/members.csv     one row per member: status, sampled values, every scalar of its summary.json
//   OUT/ensemble.json   mean, sd, P5/P50/P95 with bootstrap intervals; event probabilities with
//                       Wilson intervals; exceedance curves; Spearman sensitivities; convergence
//   OUT/envelopes.csv   P5/P50/P95 over time of the gauge displacement and speed magnitudes and
//                       of the kinetic energy (from each member's history.csv)
//   OUT/deposit_hazard.csv  P(debris thicker than d) along x, when the members' summary.json
//                       holds deposit_profile {x_m, thickness_m}
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "ensemble/ensemble_file.hpp"

namespace dsdem::ensemble {

// A scalar of summary.json: a number, a boolean, or absent (null).
struct Scalar {
  enum class Kind { Missing, Number, Boolean } kind = Kind::Missing;
  double value = 0.0;  // booleans: 0 or 1
};

// Every number and boolean of `j`, by dotted name: objects by key, lists of objects with a
// "name" by that name, short lists of numbers (at most 3: vectors) by index. Longer lists
// (profiles) and strings are left out, and so are the keys of the machine rather than of the
// physics (wall time, speed, threads), so that members.csv is the same however the members ran.
std::vector<std::pair<std::string, Scalar>> flatten_scalars(const nlohmann::ordered_json& j);

struct AggregateResult {
  std::size_t members = 0, ok = 0, failed = 0, missing = 0;
};

// Reads OUT/members/*/ and writes members.csv, ensemble.json, envelopes.csv (and
// deposit_hazard.csv). `plans` give the sampled values.
AggregateResult aggregate(const EnsembleSpec& spec, const std::vector<MemberPlan>& plans,
                          const std::filesystem::path& out_dir);

}  // namespace dsdem::ensemble
