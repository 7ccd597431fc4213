#pragma once
// The ensemble file (docs/theory.md §13): a base scenario, the number of members, the sampling,
// the varied values (any key that `dsdem run --set` reaches, each with a distribution),
// their rank correlations, fixed overrides and events. Read and validated as a whole before
// any member starts: every error names file, line and key (io::SchemaReader), and every
// member's overrides are applied to the base scenario and validated as `dsdem run` would.
#include <cstdint>
#include <string>
#include <vector>

#include "ensemble/sampling.hpp"
#include "io/scenario.hpp"
#include "io/schema.hpp"

namespace dsdem::ensemble {

struct VariedValue {
  std::vector<std::string> keys;         // --set paths that all take the sampled value
  std::string name;                      // column name (default: the first key)
  Distribution distribution;
  std::vector<std::string> list_values;  // a list's choices as YAML text (flow style)
  io::SourceLocation where;
  // The --set value text of probability u, and its number (NaN for a non-numeric choice).
  std::string text(double u) const;
  double number(double u) const;
};

enum class Comparison { Greater, GreaterEqual, Less, LessEqual };

// "key > value": a threshold event on a scalar of the members' summary.json (flattened name).
struct EventSpec {
  std::string name;
  std::string key;
  Comparison op = Comparison::Greater;
  double threshold = 0.0;
  io::SourceLocation where;
  bool holds(double v) const;
};

struct EnsembleSpec {
  std::string file, directory, title;
  std::string base;  // the base scenario, resolved against the file's folder
  std::size_t members = 0;
  SamplingMethod method = SamplingMethod::LatinHypercube;
  std::uint64_t seed = 1;
  std::vector<VariedValue> vary;
  std::vector<std::vector<double>> correlation;  // vary x vary, or empty
  std::vector<std::string> fixed;                // "key=value", applied before the varied values
  std::vector<EventSpec> events;
  int member_threads = 1;
  bool member_fields = false;
  std::vector<std::string> postprocess;  // a command run in each finished member; {out} = its folder
  std::vector<double> deposit_thresholds_m{1.0, 5.0, 10.0};
  int bootstrap_resamples = 1000;
};

// One member: its probabilities, values and the --set assignments that make it.
struct MemberPlan {
  std::size_t index = 0;
  std::vector<double> u;
  std::vector<std::string> values;  // --set text per varied value
  std::vector<double> numbers;      // numeric value per varied value (NaN when not a number)
  std::vector<std::string> sets;    // fixed, then one per key of every varied value
};

// Every key of the ensemble file (for validation and docs/ensemble-reference.md).
const std::vector<io::KeySpec>& ensemble_schema();
std::string ensemble_schema_markdown();

// Reads and validates the file; throws io::ScenarioError listing every problem.
EnsembleSpec load_ensemble(const std::string& path);
EnsembleSpec parse_ensemble(const std::string& yaml_text, const std::string& file_name);
// The members, deterministic from the seed.
std::vector<MemberPlan> plan_members(const EnsembleSpec& spec);
// Applies each member's overrides to the base scenario and validates it (io::load_scenario);
// throws io::ScenarioError naming the ensemble file's line of the offending value.
void validate_members(const EnsembleSpec& spec, const std::vector<MemberPlan>& members);

}  // namespace dsdem::ensemble
