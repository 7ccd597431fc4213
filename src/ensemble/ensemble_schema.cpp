// The ensemble file's keys (docs/ensemble-reference.md is generated from them).
#include <fmt/format.h>

#include <limits>

#include "ensemble/ensemble_file.hpp"

namespace dsdem::ensemble {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
using io::KeySpec;
using io::KeyType;

KeySpec key(std::string pattern, KeyType type, std::string def, std::string doc, double min = -kInf,
            double max = kInf, std::vector<std::string> choices = {}) {
  KeySpec s;
  s.pattern = std::move(pattern);
  s.type = type;
  s.default_text = std::move(def);
  s.doc = std::move(doc);
  s.min = min;
  s.max = max;
  s.choices = std::move(choices);
  return s;
}

}  // namespace

const std::vector<KeySpec>& ensemble_schema() {
  static const std::vector<KeySpec> s = [] {
    std::vector<KeySpec> v;
    v.push_back(key("title", KeyType::String, "", "Title of the ensemble, shown in the report."));
    v.push_back(key("base", KeyType::String, "required", "The base scenario (YAML), relative to this file."));
    v.push_back(key("members", KeyType::Integer, "required", "Number of members (runs).", 1, 1e7));
    v.push_back(key("sampling", KeyType::Map, "", "How the varied values are drawn."));
    v.push_back(key("sampling.method", KeyType::Choice, "latin_hypercube",
                    "Monte Carlo (independent draws) or Latin hypercube (one member in each of the n equal-probability "
                    "strata of every varied value).",
                    -kInf, kInf, {"monte_carlo", "latin_hypercube"}));
    v.push_back(key("sampling.seed", KeyType::Integer, "1", "Seed of the draws: the same seed gives the same members.", 0,
                    9007199254740992.0));
    v.push_back(key("vary", KeyType::List, "required", "The varied values, one entry each."));
    v.push_back(key("vary[].key", KeyType::String, "required",
                    "The scenario key as `dsdem run --set` names it (dotted path; list entries by index, e.g. "
                    "contact.pairs.0.friction), or a list of such keys that all take the same drawn value."));
    v.push_back(key("vary[].name", KeyType::String, "", "Column name in members.csv and the report (default: the first key)."));
    v.push_back(key("vary[].distribution", KeyType::Choice, "required",
                    "uniform (lower, upper); normal (mean, sd, optional lower/upper truncation); lognormal (mean, sd of "
                    "the value itself); triangular (lower, mode, upper); list (values, optional weights); integer (lower, "
                    "upper, both included: e.g. a wave seed).",
                    -kInf, kInf, {"uniform", "normal", "lognormal", "triangular", "list", "integer"}));
    for (const char* p : {"lower", "upper", "mode", "mean", "sd"})
      v.push_back(key(std::string("vary[].") + p, KeyType::Number, "", std::string("Distribution parameter ") + p + "."));
    v.push_back(key("vary[].values", KeyType::List, "", "list: the choices (any YAML value the key accepts)."));
    v.push_back(key("vary[].weights", KeyType::List, "", "list: relative weights of the choices (default: equal)."));
    v.push_back(key("correlation", KeyType::List, "", "Rank (Spearman) correlations between varied values (Iman-Conover)."));
    v.push_back(key("correlation[].between", KeyType::List, "required", "The two varied values, by name."));
    v.push_back(key("correlation[].rank", KeyType::Number, "required", "Their rank correlation.", -1, 1));
    v.push_back(key("fixed", KeyType::Map, "", "Overrides applied to every member (key: value, keys as for --set), e.g. a coarser mesh."));
    v.push_back(key("events", KeyType::List, "",
                    "Threshold events whose probability the report gives: \"key > value\" (>, >=, <, <=) on a scalar of "
                    "the members' summary.json, named as in members.csv (e.g. gauges.G1.max_displacement_m > 100), or a "
                    "map {name, when}."));
    v.push_back(key("events[].name", KeyType::String, "", "Name of the event (default: its condition)."));
    v.push_back(key("events[].when", KeyType::String, "required", "The condition, \"key > value\"."));
    v.push_back(key("member", KeyType::Map, "", "How each member runs."));
    v.push_back(key("member.threads", KeyType::Integer, "1", "OpenMP threads of each member.", 1, 4096));
    v.push_back(key("member.fields", KeyType::Boolean, "false", "Write each member's VTU field frames (off: histories and summary only)."));
    v.push_back(key("member.postprocess", KeyType::List, "",
                    "A command run in each member that finished (list of words; {out} is the member's folder, {scripts} "
                    "dsdem's scripts folder), e.g. [python3, \"{scripts}/dr2_postprocess.py\", \"{out}\", --quiet]: the "
                    "keys it merges into summary.json are aggregated too."));
    v.push_back(key("deposit_thresholds_m", KeyType::List, "[1, 5, 10]",
                    "Debris thicknesses d for the hazard profile P(thickness > d) along x (when the members' summary.json "
                    "has deposit_profile)."));
    v.push_back(key("bootstrap_resamples", KeyType::Integer, "1000", "Bootstrap resamples of the confidence intervals.", 0, 1e6));
    return v;
  }();
  return s;
}

std::string ensemble_schema_markdown() {
  std::string md = "| key | type | default | meaning |\n|---|---|---|---|\n";
  for (const auto& s : ensemble_schema()) {
    std::string type;
    switch (s.type) {
      case KeyType::Number: type = "number"; break;
      case KeyType::Integer: type = "integer"; break;
      case KeyType::Boolean: type = "boolean"; break;
      case KeyType::Map: type = "map"; break;
      case KeyType::List: type = "list"; break;
      case KeyType::Choice:
        for (const auto& c : s.choices) type += (type.empty() ? "" : ", ") + ("`" + c + "`");
        break;
      default: type = "string";
    }
    md += fmt::format("| `{}` | {} | {} | {} |\n", s.pattern, type, s.default_text, s.doc);
  }
  return md;
}

}  // namespace dsdem::ensemble
