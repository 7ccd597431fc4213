#include "ensemble/ensemble_file.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <regex>
#include <sstream>

namespace dsdem::ensemble {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
using io::KeyPath;
using io::KeySpec;
using io::KeyType;

// The parameters each distribution takes: required, then optional.
struct ParamSet {
  std::vector<std::string> required, optional;
};
ParamSet params_of(DistributionKind k) {
  switch (k) {
    case DistributionKind::Uniform: return {{"lower", "upper"}, {}};
    case DistributionKind::Normal: return {{"mean", "sd"}, {"lower", "upper"}};
    case DistributionKind::Lognormal: return {{"mean", "sd"}, {}};
    case DistributionKind::Triangular: return {{"lower", "mode", "upper"}, {}};
    case DistributionKind::List: return {{"values"}, {"weights"}};
    case DistributionKind::Integer: return {{"lower", "upper"}, {}};
  }
  return {};
}

std::string flow_text(const YAML::Node& n) {
  if (n.IsScalar()) return n.Scalar();
  YAML::Emitter e;
  e << YAML::Flow << n;
  return e.c_str();
}

io::SourceLocation location(const std::string& file, const YAML::Node& n, const std::string& path) {
  io::SourceLocation w;
  w.file = file;
  w.key = path;
  if (n.IsDefined()) {
    w.line = n.Mark().line;
    w.column = n.Mark().column;
  }
  return w;
}

}  // namespace

std::string VariedValue::text(double u) const {
  const double x = distribution.quantile(u);
  switch (distribution.kind) {
    case DistributionKind::List: return list_values[static_cast<std::size_t>(x)];
    case DistributionKind::Integer: return fmt::format("{}", static_cast<long long>(x));
    default: return fmt::format("{}", x);
  }
}

double VariedValue::number(double u) const {
  if (distribution.kind != DistributionKind::List) return distribution.quantile(u);
  const std::string t = text(u);
  try {
    std::size_t used = 0;
    const double v = std::stod(t, &used);
    if (used == t.size()) return v;
  } catch (...) {
  }
  return std::numeric_limits<double>::quiet_NaN();
}

bool EventSpec::holds(double v) const {
  switch (op) {
    case Comparison::Greater: return v > threshold;
    case Comparison::GreaterEqual: return v >= threshold;
    case Comparison::Less: return v < threshold;
    case Comparison::LessEqual: return v <= threshold;
  }
  return false;
}

EnsembleSpec load_ensemble(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw io::ScenarioError({fmt::format("{}: cannot open the ensemble file", path)});
  std::stringstream buf;
  buf << in.rdbuf();
  return parse_ensemble(buf.str(), path);
}

namespace {

// Rewrites the scenario's errors about an override ("--set key=value: ...") to the line of
// the ensemble file that made the override.
std::vector<std::string> map_errors(const io::ScenarioError& e, const std::map<std::string, io::SourceLocation>& where,
                                    const std::string& prefix = "") {
  std::vector<std::string> out;
  for (const auto& line : e.errors()) {
    std::string mapped = line;
    if (line.rfind("--set ", 0) == 0) {
      const std::string rest = line.substr(6);
      const auto colon = rest.find(": ");
      const std::string token = rest.substr(0, colon);
      const std::string k = token.substr(0, token.find('='));
      const auto it = where.find(k);
      if (it != where.end())
        mapped = it->second.describe(fmt::format("{}{}{}", prefix, token,
                                                 colon == std::string::npos ? "" : ": " + rest.substr(colon + 2)));
    } else if (!prefix.empty()) {
      mapped = prefix + line;
    }
    out.push_back(mapped);
  }
  return out;
}

}  // namespace

namespace {

// The ensemble file's reader: each section by its own function, the errors of all of them
// collected (file, line and key) before anything is thrown.
class EnsembleReader {
 public:
  EnsembleReader(const std::string& file, const YAML::Node& root_node)
      : file_name(file), root(root_node), r(file, ensemble_schema()) {}

  EnsembleSpec read() {
    read_top();
    read_sampling();
    read_vary();
    read_correlation();
    read_fixed();
    read_events();
    read_member();
    read_deposit_thresholds();
    if (!r.ok()) throw io::ScenarioError(r.errors());
    check_against_base();
    return spec;
  }

 private:
  void read_top() {
    spec.file = file_name;
    spec.directory = std::filesystem::path(file_name).parent_path().string();
    if (spec.directory.empty()) spec.directory = ".";
    r.check_keys(root, top);
    spec.title = r.string(root, top, "title").value_or("");
    const auto base = r.string(root, top, "base");
    if (base) {
      const std::filesystem::path p(*base);
      spec.base = p.is_absolute() ? p.string() : (std::filesystem::path(spec.directory) / p).lexically_normal().string();
      if (!std::filesystem::is_regular_file(spec.base))
        r.error(root["base"], "base", fmt::format("the base scenario '{}' does not exist", spec.base));
    }
    if (const auto n = r.integer(root, top, "members")) spec.members = static_cast<std::size_t>(*n);
  }

  void read_sampling() {
    YAML::Node sampling = r.section(root, top, "sampling", YAML::NodeType::Map);
    if (!sampling.IsDefined()) sampling = YAML::Node(YAML::NodeType::Map);
    const KeyPath ps{"sampling", "sampling"};
    r.check_keys(sampling, ps);
    if (const auto m = r.string(sampling, ps, "method"))
      spec.method = *m == "monte_carlo" ? SamplingMethod::MonteCarlo : SamplingMethod::LatinHypercube;
    if (const auto s = r.integer(sampling, ps, "seed")) spec.seed = static_cast<std::uint64_t>(*s);
  }

  // Each varied value: its keys, its name and its distribution.
  void read_vary() {
    const YAML::Node vary = r.section(root, top, "vary", YAML::NodeType::Sequence);
    if (vary.IsDefined() && vary.size() == 0) r.error(vary, "vary", "no varied value: list at least one");
    for (std::size_t i = 0; vary.IsDefined() && i < vary.size(); ++i) {
      const YAML::Node item = vary[i];
      const KeyPath pi = KeyPath{"vary", "vary"}.index(i);
      if (!item.IsMap()) {
        r.error(item, pi.actual, "expected a map (key, distribution and its parameters)");
        continue;
      }
      r.check_keys(item, pi);
      VariedValue v;
      v.where = location(file_name, item, pi.actual);
      read_keys(item, pi, i, v);
      read_distribution(item, pi, v);
      spec.vary.push_back(std::move(v));
    }
  }

  void read_keys(const YAML::Node& item, const KeyPath& pi, std::size_t i, VariedValue& v) {
    const YAML::Node kn = item["key"];
    if (!kn.IsDefined() || kn.IsNull()) {
      r.error(item, pi.child("key").actual, "missing value (the scenario key to vary, as --set names it)");
    } else if (kn.IsScalar()) {
      v.keys.push_back(kn.Scalar());
    } else if (kn.IsSequence() && kn.size() > 0) {
      for (const auto& k : kn) {
        if (!k.IsScalar()) {
          r.error(k, pi.child("key").actual, "expected a key (a dotted path)");
          continue;
        }
        v.keys.push_back(k.Scalar());
      }
    } else {
      r.error(kn, pi.child("key").actual, "expected a key or a non-empty list of keys");
    }
    for (const auto& k : v.keys) {
      if (k.empty() || k.find('=') != std::string::npos || k.find(' ') != std::string::npos)
        r.error(kn, pi.child("key").actual, fmt::format("'{}' is not a key path (write it as --set names it, without =)", k));
      if (key_where.count(k))
        r.error(kn, pi.child("key").actual, fmt::format("'{}' is varied twice (also at {})", k, key_where[k].key));
      key_where[k] = location(file_name, kn, pi.child("key").actual);
    }
    v.name = r.string(item, pi, "name").value_or(v.keys.empty() ? "" : v.keys.front());
    if (by_name.count(v.name)) r.error(item["name"].IsDefined() ? item["name"] : item, pi.actual, fmt::format("a second varied value named '{}' (give each its own name)", v.name));
    by_name[v.name] = i;
  }

  void read_distribution(const YAML::Node& item, const KeyPath& pi, VariedValue& v) {
    const auto dist = r.string(item, pi, "distribution");
    if (dist) {
      static const std::map<std::string, DistributionKind> kinds{
          {"uniform", DistributionKind::Uniform},       {"normal", DistributionKind::Normal},
          {"lognormal", DistributionKind::Lognormal},   {"triangular", DistributionKind::Triangular},
          {"list", DistributionKind::List},             {"integer", DistributionKind::Integer}};
      Distribution& d = v.distribution;
      d.kind = kinds.at(*dist);
      const ParamSet pset = params_of(d.kind);
      auto takes = [&](const std::string& p) {
        return std::find(pset.required.begin(), pset.required.end(), p) != pset.required.end() ||
               std::find(pset.optional.begin(), pset.optional.end(), p) != pset.optional.end();
      };
      std::string takes_list;
      for (const auto& p : pset.required) takes_list += (takes_list.empty() ? "" : ", ") + p;
      for (const auto& p : pset.optional) takes_list += (takes_list.empty() ? "" : ", ") + p + " (optional)";
      bool complete = true;
      for (const char* p : {"lower", "upper", "mode", "mean", "sd", "values", "weights"}) {
        const YAML::Node pn = item[p];
        if (pn.IsDefined() && !takes(p)) {
          r.error(pn, pi.child(p).actual, fmt::format("a {} distribution takes {}, not {}", *dist, takes_list, p));
          complete = false;
        }
      }
      for (const auto& p : pset.required)
        if (!item[p].IsDefined() || item[p].IsNull()) {
          r.error(item, pi.child(p).actual, fmt::format("missing value (a {} distribution takes {})", *dist, takes_list));
          complete = false;
        }
      if (d.kind == DistributionKind::Normal) d.lower = -kInf, d.upper = kInf;
      for (const char* p : {"lower", "upper", "mode", "mean", "sd"}) {
        if (!takes(p)) continue;
        const auto x = r.number(item, pi, p);
        if (!x) {
          if (item[p].IsDefined() && !item[p].IsNull()) complete = false;
          continue;
        }
        double* field = std::string(p) == "lower" ? &d.lower : std::string(p) == "upper" ? &d.upper
                        : std::string(p) == "mode" ? &d.mode : std::string(p) == "mean" ? &d.mean : &d.sd;
        *field = *x;
      }
      if (d.kind == DistributionKind::List && item["values"].IsDefined()) {
        const YAML::Node vals = item["values"];
        if (!vals.IsSequence()) {
          r.error(vals, pi.child("values").actual, "expected a list of choices");
          complete = false;
        } else {
          for (const auto& c : vals) v.list_values.push_back(flow_text(c));
          d.choices = v.list_values.size();
        }
        const YAML::Node w = item["weights"];
        if (w.IsDefined()) {
          if (!w.IsSequence()) {
            r.error(w, pi.child("weights").actual, "expected a list of numbers");
            complete = false;
          } else {
            for (const auto& x : w) {
              try {
                d.weights.push_back(x.as<double>());
              } catch (...) {
                r.error(x, pi.child("weights").actual, "expected a number");
                complete = false;
              }
            }
          }
        }
      }
      if (complete) {
        const std::string problem = d.check();
        if (!problem.empty()) {
          // Point at the parameter the message starts with, when it names one.
          const std::string first = problem.substr(0, problem.find(' '));
          const bool named = item[first].IsDefined();
          r.error(named ? item[first] : item, named ? pi.child(first).actual : pi.actual,
                  fmt::format("impossible {} distribution: {}", *dist, problem));
        }
      }
    }
  }

  void read_correlation() {
    const YAML::Node corr = r.section(root, top, "correlation", YAML::NodeType::Sequence);
    if (corr.IsDefined() && !spec.vary.empty()) {
      const std::size_t k = spec.vary.size();
      spec.correlation.assign(k, std::vector<double>(k, 0.0));
      for (std::size_t i = 0; i < k; ++i) spec.correlation[i][i] = 1.0;
      bool ok = true;
      for (std::size_t i = 0; i < corr.size(); ++i) {
        const KeyPath pc = KeyPath{"correlation", "correlation"}.index(i);
        const YAML::Node item = corr[i];
        if (!item.IsMap()) {
          r.error(item, pc.actual, "expected a map {between: [a, b], rank: r}");
          ok = false;
          continue;
        }
        r.check_keys(item, pc);
        const auto rho = r.number(item, pc, "rank");
        const YAML::Node b = item["between"];
        std::vector<std::size_t> idx;
        if (!b.IsDefined() || !b.IsSequence() || b.size() != 2) {
          r.error(b.IsDefined() ? b : item, pc.child("between").actual, "expected two names of varied values [a, b]");
        } else {
          for (const auto& nm : b) {
            const std::string s = nm.IsScalar() ? nm.Scalar() : "";
            const auto it = by_name.find(s);
            if (it == by_name.end()) {
              std::vector<std::string> names;
              for (const auto& [n, _] : by_name) names.push_back(n);
              const std::string near = io::nearest(s, names);
              r.error(nm, pc.child("between").actual,
                      fmt::format("'{}' is not the name of a varied value{}", s, near.empty() ? "" : "; did you mean '" + near + "'?"));
            } else {
              idx.push_back(it->second);
            }
          }
          if (idx.size() == 2 && idx[0] == idx[1]) {
            r.error(b, pc.child("between").actual, "a value's correlation with itself is 1");
            idx.clear();
          }
        }
        if (idx.size() == 2 && rho) {
          spec.correlation[idx[0]][idx[1]] = spec.correlation[idx[1]][idx[0]] = *rho;
        } else {
          ok = false;
        }
      }
      if (ok) {
        const std::string problem = check_correlation(spec.correlation);
        if (!problem.empty()) r.error(corr, "correlation", problem);
        if (spec.members > 0 && spec.members < k + 2)
          r.error(corr, "correlation", fmt::format("{} members are too few to shape the correlation of {} values (at least {})",
                                                   spec.members, k, k + 2));
      }
    }
  }

  void read_fixed() {
    const YAML::Node fixed = r.section(root, top, "fixed", YAML::NodeType::Map);
    for (auto it = fixed.begin(); fixed.IsDefined() && it != fixed.end(); ++it) {
      const std::string k = it->first.Scalar();
      const std::string path = "fixed." + k;
      if (key_where.count(k)) r.error(it->first, path, fmt::format("'{}' is also varied ({})", k, key_where[k].key));
      spec.fixed.push_back(k + "=" + flow_text(it->second));
      fixed_where[k] = location(file_name, it->first, path);
    }
  }

  void read_events() {
    const YAML::Node events = r.section(root, top, "events", YAML::NodeType::Sequence);
    for (std::size_t i = 0; events.IsDefined() && i < events.size(); ++i) {
      read_event(events[i], i);
    }
  }

  // One event: "key > value" or {name, when: "key > value"}.
  void read_event(const YAML::Node& item, std::size_t i) {
    static const std::regex condition(R"(^\s*([A-Za-z0-9_.\-]+)\s*(>=|<=|>|<)\s*(\S+)\s*$)");
    const KeyPath pe = KeyPath{"events", "events"}.index(i);
    EventSpec ev;
    std::string when;
    YAML::Node at = item;
    if (item.IsScalar()) {
      when = item.Scalar();
    } else if (item.IsMap()) {
      r.check_keys(item, pe);
      when = r.string(item, pe, "when").value_or("");
      ev.name = r.string(item, pe, "name").value_or("");
      if (item["when"].IsDefined()) at = item["when"];
      if (when.empty()) return;
    } else {
      r.error(item, pe.actual, "expected \"key > value\" or a map {name, when}");
      return;
    }
    std::smatch m;
    double threshold = 0.0;
    bool number_ok = false;
    if (std::regex_match(when, m, condition)) {
      try {
        std::size_t used = 0;
        threshold = std::stod(m[3].str(), &used);
        number_ok = used == m[3].str().size() && std::isfinite(threshold);
      } catch (...) {
      }
    }
    if (!number_ok) {
      r.error(at, pe.actual, fmt::format("'{}' is not a condition \"key > value\" (operators >, >=, <, <=; a number)", when));
      return;
    }
    ev.key = m[1].str();
    const std::string op = m[2].str();
    ev.op = op == ">" ? Comparison::Greater : op == ">=" ? Comparison::GreaterEqual : op == "<" ? Comparison::Less
                                                                                     : Comparison::LessEqual;
    ev.threshold = threshold;
    if (ev.name.empty()) ev.name = fmt::format("{} {} {}", ev.key, op, m[3].str());
    ev.where = location(file_name, at, pe.actual);
    spec.events.push_back(ev);
  }

  void read_member() {
    YAML::Node member = r.section(root, top, "member", YAML::NodeType::Map);
    if (!member.IsDefined()) member = YAML::Node(YAML::NodeType::Map);
    const KeyPath pm{"member", "member"};
    r.check_keys(member, pm);
    if (const auto t = r.integer(member, pm, "threads")) spec.member_threads = static_cast<int>(*t);
    if (const auto f = r.boolean(member, pm, "fields")) spec.member_fields = *f;
    const YAML::Node post = member["postprocess"];
    if (post.IsDefined() && !post.IsNull()) {
      if (!post.IsSequence() || post.size() == 0) {
        r.error(post, "member.postprocess", "expected a command as a list of words, e.g. [python3, script.py, \"{out}\"]");
      } else {
        for (const auto& w : post) {
          if (!w.IsScalar()) r.error(w, "member.postprocess", "expected a word (a string)");
          else spec.postprocess.push_back(w.Scalar());
        }
      }
    }
  }

  void read_deposit_thresholds() {
    const YAML::Node dep = root["deposit_thresholds_m"];
    if (dep.IsDefined() && !dep.IsNull()) {
      spec.deposit_thresholds_m.clear();
      if (!dep.IsSequence() || dep.size() == 0) r.error(dep, "deposit_thresholds_m", "expected a list of thicknesses in m");
      for (std::size_t i = 0; dep.IsSequence() && i < dep.size(); ++i) {
        double d = -1.0;
        try {
          d = dep[i].as<double>();
        } catch (...) {
        }
        if (!(d > 0.0) || !std::isfinite(d)) r.error(dep[i], fmt::format("deposit_thresholds_m[{}]", i), "expected a thickness > 0 in m");
        else spec.deposit_thresholds_m.push_back(d);
      }
    }
    if (const auto b = r.integer(root, top, "bootstrap_resamples")) spec.bootstrap_resamples = static_cast<int>(*b);
  }

  // The overrides against the base scenario: the fixed ones, then each varied value at its
  // median, so an unknown key or a value out of range names the ensemble file's line.
  void check_against_base() {
    std::vector<std::string> errors;
    try {
      io::load_scenario(spec.base, spec.fixed);
    } catch (const io::ScenarioError& e) {
      for (auto& l : map_errors(e, fixed_where)) errors.push_back(l);
    }
    if (errors.empty()) {
      for (const auto& v : spec.vary) {
        std::map<std::string, io::SourceLocation> where = fixed_where;
        std::vector<std::string> sets = spec.fixed;
        const std::string value = v.text(0.5);
        for (const auto& k : v.keys) {
          sets.push_back(k + "=" + value);
          where[k] = key_where[k];
        }
        try {
          io::load_scenario(spec.base, sets);
        } catch (const io::ScenarioError& e) {
          for (auto& l : map_errors(e, where)) errors.push_back(l);
        }
      }
    }
    if (!errors.empty()) throw io::ScenarioError(errors);
  }

  const std::string file_name;
  const YAML::Node root;
  io::SchemaReader r;
  EnsembleSpec spec;
  const KeyPath top{"", ""};
  std::map<std::string, std::size_t> by_name;             // varied value -> its index
  std::map<std::string, io::SourceLocation> key_where;    // varied key -> where
  std::map<std::string, io::SourceLocation> fixed_where;  // fixed key -> where
};

}  // namespace

EnsembleSpec parse_ensemble(const std::string& yaml_text, const std::string& file_name) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw io::ScenarioError({fmt::format("{}:{}:{}: YAML syntax error: {}", file_name, e.mark.line + 1, e.mark.column + 1, e.msg)});
  }
  if (!root.IsMap())
    throw io::ScenarioError({fmt::format("{}: the ensemble file must be a YAML map (base, members, vary, ...)", file_name)});
  return EnsembleReader(file_name, root).read();
}

std::vector<MemberPlan> plan_members(const EnsembleSpec& spec) {
  const auto u = sample_probabilities(spec.members, spec.vary.size(), spec.method, spec.seed, spec.correlation);
  std::vector<MemberPlan> out(spec.members);
  for (std::size_t i = 0; i < spec.members; ++i) {
    MemberPlan& m = out[i];
    m.index = i;
    m.u = u[i];
    m.sets = spec.fixed;
    for (std::size_t j = 0; j < spec.vary.size(); ++j) {
      const VariedValue& v = spec.vary[j];
      m.values.push_back(v.text(u[i][j]));
      m.numbers.push_back(v.number(u[i][j]));
      for (const auto& k : v.keys) m.sets.push_back(k + "=" + m.values.back());
    }
  }
  return out;
}

void validate_members(const EnsembleSpec& spec, const std::vector<MemberPlan>& members) {
  std::map<std::string, io::SourceLocation> where;
  for (const auto& v : spec.vary)
    for (const auto& k : v.keys) where[k] = v.where;
  std::vector<std::string> errors;
  std::size_t failing = 0;
  for (const auto& m : members) {
    try {
      io::load_scenario(spec.base, m.sets);
    } catch (const io::ScenarioError& e) {
      if (++failing <= 5)
        for (auto& l : map_errors(e, where, fmt::format("member {}: ", m.index))) errors.push_back(l);
    }
  }
  if (failing > 5) errors.push_back(fmt::format("... and {} more members with errors", failing - 5));
  if (!errors.empty()) throw io::ScenarioError(errors);
}

}  // namespace dsdem::ensemble
