#include "ensemble/aggregate.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "ensemble/member_runner.hpp"
#include "ensemble/statistics.hpp"
#include "io/atomic_file.hpp"
#include "io/json_file.hpp"

namespace dsdem::ensemble {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace {

// Keys of how and where a member ran, not of what it computed.
const std::set<std::string> kMachineKeys{"wall_time_s", "wall_time_total_s", "element_steps_per_s", "threads",
                                         "steps_on_one_thread", "restart_step", "deposit_profile"};

void flatten_into(const Json& j, const std::string& prefix, std::vector<std::pair<std::string, Scalar>>& out) {
  auto name = [&](const std::string& k) { return prefix.empty() ? k : prefix + "." + k; };
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it) {
      if (kMachineKeys.count(it.key())) continue;
      flatten_into(it.value(), name(it.key()), out);
    }
  } else if (j.is_array()) {
    const bool named = !j.empty() && std::all_of(j.begin(), j.end(), [](const Json& e) {
      return e.is_object() && e.contains("name") && e["name"].is_string();
    });
    const bool vector = !j.empty() && j.size() <= 3 && std::all_of(j.begin(), j.end(), [](const Json& e) { return e.is_number(); });
    if (named) {
      for (const auto& e : j) {
        Json rest = e;
        rest.erase("name");
        flatten_into(rest, name(e["name"].get<std::string>()), out);
      }
    } else if (vector) {
      for (std::size_t i = 0; i < j.size(); ++i) flatten_into(j[i], name(std::to_string(i)), out);
    }
  } else if (j.is_boolean()) {
    out.push_back({prefix, {Scalar::Kind::Boolean, j.get<bool>() ? 1.0 : 0.0}});
  } else if (j.is_number()) {
    out.push_back({prefix, {Scalar::Kind::Number, j.get<double>()}});
  } else if (j.is_null()) {
    out.push_back({prefix, {}});
  }
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string number_text(double v) { return std::isfinite(v) ? fmt::format("{}", v) : ""; }

struct MemberData {
  std::string status = "missing";
  int exit_code = 0;
  std::string diagnosis;
  std::map<std::string, Scalar> scalars;
  Json summary;
};

// history.csv: header and numeric rows.
struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  int column(const std::string& name) const {
    const auto it = std::find(header.begin(), header.end(), name);
    return it == header.end() ? -1 : static_cast<int>(it - header.begin());
  }
};

Table read_csv(const fs::path& p) {
  Table t;
  std::ifstream in(p);
  std::string line;
  if (!std::getline(in, line)) return t;
  std::stringstream hs(line);
  for (std::string c; std::getline(hs, c, ',');) t.header.push_back(c);
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream ls(line);
    for (std::string c; std::getline(ls, c, ',');) {
      try {
        row.push_back(std::stod(c));
      } catch (...) {
        row.push_back(std::nan(""));
      }
    }
    if (row.size() == t.header.size()) t.rows.push_back(std::move(row));
  }
  return t;
}

// Linear interpolation of (t, y) at time x, held constant beyond the ends.
double interpolate(const std::vector<double>& t, const std::vector<double>& y, double x) {
  if (t.empty()) return std::nan("");
  if (x <= t.front()) return y.front();
  if (x >= t.back()) return y.back();
  const auto k = static_cast<std::size_t>(std::upper_bound(t.begin(), t.end(), x) - t.begin());
  const double s = (x - t[k - 1]) / (t[k] - t[k - 1]);
  return y[k - 1] + s * (y[k] - y[k - 1]);
}

Json interval_json(const Interval& i) { return Json::array({i.low, i.high}); }

std::uint64_t key_seed(std::uint64_t seed, std::size_t k) { return seed ^ (0x9E3779B97F4A7C15ull * (k + 1)); }

// Member counts at which the convergence of the estimates is shown.
std::vector<std::size_t> convergence_counts(std::size_t n) {
  std::vector<std::size_t> c;
  const std::size_t step = std::max<std::size_t>(1, n / 20);
  for (std::size_t k = std::min<std::size_t>(5, n); k < n; k += step) c.push_back(k);
  if (n > 0) c.push_back(n);
  return c;
}

Json distribution_json(const VariedValue& v) {
  const Distribution& d = v.distribution;
  Json j = Json::object();
  j["name"] = v.name;
  j["keys"] = v.keys;
  switch (d.kind) {
    case DistributionKind::Uniform: j["distribution"] = "uniform", j["lower"] = d.lower, j["upper"] = d.upper; break;
    case DistributionKind::Integer: j["distribution"] = "integer", j["lower"] = d.lower, j["upper"] = d.upper; break;
    case DistributionKind::Normal:
      j["distribution"] = "normal", j["mean"] = d.mean, j["sd"] = d.sd;
      if (std::isfinite(d.lower)) j["lower"] = d.lower;
      if (std::isfinite(d.upper)) j["upper"] = d.upper;
      break;
    case DistributionKind::Lognormal: j["distribution"] = "lognormal", j["mean"] = d.mean, j["sd"] = d.sd; break;
    case DistributionKind::Triangular:
      j["distribution"] = "triangular", j["lower"] = d.lower, j["mode"] = d.mode, j["upper"] = d.upper;
      break;
    case DistributionKind::List:
      j["distribution"] = "list", j["values"] = v.list_values;
      if (!d.weights.empty()) j["weights"] = d.weights;
      break;
  }
  return j;
}

}  // namespace

std::vector<std::pair<std::string, Scalar>> flatten_scalars(const Json& j) {
  std::vector<std::pair<std::string, Scalar>> out;
  flatten_into(j, "", out);
  return out;
}

AggregateResult aggregate(const EnsembleSpec& spec, const std::vector<MemberPlan>& plans, const fs::path& out_dir) {
  AggregateResult res;
  res.members = plans.size();
  std::vector<MemberData> data(plans.size());
  std::vector<std::string> columns;
  std::set<std::string> seen;
  std::map<std::string, bool> is_boolean;
  for (std::size_t i = 0; i < plans.size(); ++i) {
    const fs::path dir = member_dir(out_dir, i, spec.members);
    MemberData& m = data[i];
    try {
      const Json marker = io::read_json_file(dir / "member.json");
      m.status = marker.value("status", std::string("missing"));
      m.exit_code = marker.value("exit_code", 0);
      m.diagnosis = marker.value("diagnosis", std::string());
    } catch (...) {
      m.status = "missing";
    }
    if (m.status == "killed") m.status = "missing";
    if (m.status != "missing" && fs::exists(dir / "summary.json")) {
      try {
        m.summary = io::read_json_file(dir / "summary.json");
        for (auto& [k, v] : flatten_scalars(m.summary)) {
          if (!seen.count(k)) {
            seen.insert(k);
            columns.push_back(k);
          }
          if (v.kind == Scalar::Kind::Boolean) is_boolean[k] = true;
          else if (v.kind == Scalar::Kind::Number) is_boolean.emplace(k, false);
          m.scalars[k] = v;
        }
      } catch (...) {
      }
    }
    if (m.status == "ok") ++res.ok;
    else if (m.status == "missing") ++res.missing;
    else ++res.failed;
  }

  // members.csv
  std::string csv = "member,status,exit_code";
  for (const auto& v : spec.vary) csv += "," + csv_field(v.name);
  for (const auto& c : columns) csv += "," + csv_field(c);
  csv += "\n";
  for (std::size_t i = 0; i < plans.size(); ++i) {
    const MemberData& m = data[i];
    csv += fmt::format("{},{},{}", i, m.status, m.status == "missing" ? "" : std::to_string(m.exit_code));
    for (const auto& v : plans[i].values) csv += "," + csv_field(v);
    for (const auto& c : columns) {
      csv += ",";
      const auto it = m.scalars.find(c);
      if (it == m.scalars.end() || it->second.kind == Scalar::Kind::Missing) continue;
      csv += it->second.kind == Scalar::Kind::Boolean ? (it->second.value != 0.0 ? "true" : "false")
                                                       : number_text(it->second.value);
    }
    csv += "\n";
  }
  io::write_file_atomically(out_dir / "members.csv", csv);

  // The ok members, in index order, feed every statistic.
  std::vector<std::size_t> ok;
  for (std::size_t i = 0; i < plans.size(); ++i)
    if (data[i].status == "ok") ok.push_back(i);
  auto series = [&](const std::string& key, std::vector<std::size_t>* who) {
    std::vector<double> x;
    for (std::size_t i : ok) {
      const auto it = data[i].scalars.find(key);
      if (it == data[i].scalars.end() || it->second.kind == Scalar::Kind::Missing) continue;
      x.push_back(it->second.value);
      if (who) who->push_back(i);
    }
    return x;
  };

  Json out = Json::object();
  out["title"] = spec.title;
  out["ensemble_file"] = spec.file;
  out["base"] = spec.base;
  out["members"] = plans.size();
  out["sampling"] = Json::object({{"method", spec.method == SamplingMethod::MonteCarlo ? "monte_carlo" : "latin_hypercube"},
                                  {"seed", spec.seed}});
  Json varied = Json::array();
  for (const auto& v : spec.vary) varied.push_back(distribution_json(v));
  out["varied"] = varied;
  out["fixed"] = spec.fixed;
  out["completed_members"] = res.ok;
  out["failed_members"] = res.failed;
  out["missing_members"] = res.missing;
  Json failures = Json::array();
  for (std::size_t i = 0; i < plans.size(); ++i)
    if (data[i].status != "ok" && data[i].status != "missing")
      failures.push_back(Json::object({{"member", i}, {"status", data[i].status}, {"exit_code", data[i].exit_code},
                                       {"diagnosis", data[i].diagnosis}}));
  out["failures"] = failures;
  out["statistics_note"] = "over the completed members; intervals 95 %: percentile bootstrap for mean, sd and quantiles, "
                           "Wilson for probabilities";

  // P5/P50/P95, and P10/P90 (the percentiles engineers quote for a hazard).
  const std::vector<double> ps{0.05, 0.10, 0.5, 0.90, 0.95};
  const std::vector<std::string> p_names{"p5", "p10", "p50", "p90", "p95"};
  Json scalars = Json::object();
  std::vector<std::string> varying;
  for (std::size_t k = 0; k < columns.size(); ++k) {
    const std::string& key = columns[k];
    if (is_boolean[key]) continue;
    std::vector<double> x = series(key, nullptr);
    if (x.empty()) continue;
    Json s = Json::object();
    std::vector<double> sorted = x;
    std::sort(sorted.begin(), sorted.end());
    s["n"] = x.size();
    s["mean"] = mean(x);
    s["sd"] = standard_deviation(x);
    s["min"] = sorted.front();
    for (std::size_t q = 0; q < ps.size(); ++q) s[p_names[q]] = quantile_sorted(sorted, ps[q]);
    s["max"] = sorted.back();
    if (sorted.front() != sorted.back()) {
      varying.push_back(key);
      const auto b = bootstrap(x, ps, spec.bootstrap_resamples, key_seed(spec.seed, k));
      Json ci = Json::object({{"mean", interval_json(b.mean)}, {"sd", interval_json(b.sd)}});
      for (std::size_t q = 0; q < ps.size(); ++q) ci[p_names[q]] = interval_json(b.quantiles[q]);
      s["ci95"] = ci;
      // Empirical exceedance: P(X >= x_(i)) = (n - i) / n.
      Json ex = Json::object();
      Json pv = Json::array();
      for (std::size_t i = 0; i < sorted.size(); ++i)
        pv.push_back(static_cast<double>(sorted.size() - i) / static_cast<double>(sorted.size()));
      ex["value"] = sorted;
      ex["probability"] = pv;
      s["exceedance"] = ex;
    }
    scalars[key] = s;
  }
  out["scalars"] = scalars;

  // Events: every boolean of summary.json, the file's thresholds, and a member failing.
  Json events = Json::object();
  auto event_json = [&](std::size_t count, std::size_t n) {
    const Interval w = wilson_interval(count, n);
    return Json::object({{"n", n}, {"count", count}, {"probability", n ? static_cast<double>(count) / n : 0.0},
                         {"wilson95", interval_json(w)}});
  };
  std::vector<std::pair<std::string, std::vector<double>>> event_series;  // 0/1 over ok members, for convergence
  for (const auto& key : columns) {
    if (!is_boolean[key]) continue;
    const auto x = series(key, nullptr);
    const auto count = static_cast<std::size_t>(std::count(x.begin(), x.end(), 1.0));
    Json e = event_json(count, x.size());
    e["kind"] = "boolean";
    e["key"] = key;
    events[key] = e;
    event_series.push_back({key, x});
  }
  for (const auto& ev : spec.events) {
    if (!seen.count(ev.key)) {
      events[ev.name] = Json::object({{"kind", "threshold"}, {"key", ev.key}, {"n", 0},
                                      {"error", "no member's summary.json has this key (see members.csv for the names)"}});
      continue;
    }
    // A null value (e.g. river_blocked_time_s of a run in which the river was never
    // blocked) is the event not happening; a member without the key does not count.
    std::vector<double> hit;
    for (std::size_t i : ok) {
      const auto it = data[i].scalars.find(ev.key);
      if (it == data[i].scalars.end()) continue;
      hit.push_back(it->second.kind != Scalar::Kind::Missing && ev.holds(it->second.value) ? 1.0 : 0.0);
    }
    Json e = event_json(static_cast<std::size_t>(std::count(hit.begin(), hit.end(), 1.0)), hit.size());
    e["kind"] = "threshold";
    e["key"] = ev.key;
    e["threshold"] = ev.threshold;
    events[ev.name] = e;
    event_series.push_back({ev.name, hit});
  }
  {
    const std::size_t ran = res.ok + res.failed;
    Json e = event_json(res.failed, ran);
    e["kind"] = "member";
    e["key"] = "status != ok";
    events["member_failed"] = e;
  }
  out["events"] = events;

  // Sensitivity: Spearman rank correlation of each varying output with each numeric input.
  Json sens = Json::object();
  for (const auto& key : varying) {
    std::vector<std::size_t> who;
    const auto y = series(key, &who);
    if (y.size() < 3) continue;
    Json row = Json::object();
    for (std::size_t j = 0; j < spec.vary.size(); ++j) {
      std::vector<double> x;
      for (std::size_t i : who) x.push_back(plans[i].numbers[j]);
      if (std::any_of(x.begin(), x.end(), [](double v) { return !std::isfinite(v); })) continue;
      row[spec.vary[j].name] = spearman(x, y);
    }
    sens[key] = row;
  }
  out["sensitivity_spearman"] = sens;

  // Convergence: the estimates from the first n completed members.
  Json conv = Json::object();
  const auto counts = convergence_counts(ok.size());
  conv["n"] = counts;
  Json conv_s = Json::object();
  for (const auto& key : varying) {
    const auto x = series(key, nullptr);
    Json m = Json::array(), p50 = Json::array(), p95 = Json::array();
    for (std::size_t n : counts) {
      const std::vector<double> head(x.begin(), x.begin() + static_cast<long>(std::min(n, x.size())));
      m.push_back(mean(head));
      p50.push_back(quantile(head, 0.5));
      p95.push_back(quantile(head, 0.95));
    }
    conv_s[key] = Json::object({{"mean", m}, {"p50", p50}, {"p95", p95}});
  }
  conv["scalars"] = conv_s;
  Json conv_e = Json::object();
  for (const auto& [name, x] : event_series) {
    Json p = Json::array();
    for (std::size_t n : counts) {
      const std::size_t m = std::min(n, x.size());
      p.push_back(m ? std::count(x.begin(), x.begin() + static_cast<long>(m), 1.0) / static_cast<double>(m) : 0.0);
    }
    conv_e[name] = p;
  }
  conv["events"] = conv_e;
  out["convergence"] = conv;

  // Gauge and energy envelopes over time.
  std::vector<Table> histories;
  for (std::size_t i : ok) histories.push_back(read_csv(member_dir(out_dir, i, spec.members) / "history.csv"));
  std::size_t longest = 0;
  for (std::size_t h = 0; h < histories.size(); ++h)
    if (histories[h].rows.size() > histories[longest].rows.size()) longest = h;
  Json env = Json::object();
  if (!histories.empty() && !histories[longest].rows.empty()) {
    const Table& ref = histories[longest];
    std::vector<std::string> names;
    std::vector<std::pair<std::string, std::string>> pairs;  // x and y columns of a magnitude ("" y: a plain column)
    for (const auto& h : ref.header) {
      const auto strip = [&](const std::string& suffix) {
        return h.size() > suffix.size() && h.compare(h.size() - suffix.size(), suffix.size(), suffix) == 0
                   ? h.substr(0, h.size() - suffix.size())
                   : std::string();
      };
      if (const auto g = strip("_displacement_x_m"); !g.empty()) {
        names.push_back(g + "_displacement_m");
        pairs.push_back({h, g + "_displacement_y_m"});
      } else if (const auto g2 = strip("_velocity_x_m_per_s"); !g2.empty()) {
        names.push_back(g2 + "_speed_m_per_s");
        pairs.push_back({h, g2 + "_velocity_y_m_per_s"});
      }
    }
    if (ref.column("kinetic_J_per_m") >= 0) {
      names.push_back("kinetic_J_per_m");
      pairs.push_back({"kinetic_J_per_m", ""});
    }
    const int tcol = ref.column("time_s");
    std::vector<double> grid;
    for (const auto& r : ref.rows) grid.push_back(r[static_cast<std::size_t>(tcol)]);
    std::vector<std::vector<std::vector<double>>> pct(names.size(), std::vector<std::vector<double>>(3));
    for (std::size_t s = 0; s < names.size(); ++s) {
      std::vector<std::vector<double>> member_series;
      for (const auto& h : histories) {
        const int cx = h.column(pairs[s].first), cy = pairs[s].second.empty() ? -1 : h.column(pairs[s].second);
        const int ct = h.column("time_s");
        if (cx < 0 || ct < 0) continue;
        std::vector<double> t, y;
        for (const auto& r : h.rows) {
          t.push_back(r[static_cast<std::size_t>(ct)]);
          const double a = r[static_cast<std::size_t>(cx)];
          y.push_back(cy >= 0 ? std::hypot(a, r[static_cast<std::size_t>(cy)]) : a);
        }
        std::vector<double> on_grid;
        for (double x : grid) on_grid.push_back(interpolate(t, y, x));
        member_series.push_back(std::move(on_grid));
      }
      for (std::size_t g = 0; g < grid.size(); ++g) {
        std::vector<double> at;
        for (const auto& ms : member_series) at.push_back(ms[g]);
        std::sort(at.begin(), at.end());
        for (std::size_t q = 0; q < 3; ++q) pct[s][q].push_back(quantile_sorted(at, ps[q]));
      }
    }
    std::string text = "time_s";
    for (const auto& n : names) text += fmt::format(",{0}_p5,{0}_p50,{0}_p95", n);
    text += "\n";
    for (std::size_t g = 0; g < grid.size(); ++g) {
      text += number_text(grid[g]);
      for (std::size_t s = 0; s < names.size(); ++s)
        for (std::size_t q = 0; q < 3; ++q) text += "," + number_text(pct[s][q][g]);
      text += "\n";
    }
    io::write_file_atomically(out_dir / "envelopes.csv", text);
    env["file"] = "envelopes.csv";
    env["series"] = names;
    env["members"] = histories.size();
  } else {
    env["file"] = nullptr;
    env["note"] = "no completed member has a history.csv";
  }
  out["envelopes"] = env;

  // Deposit hazard profile: P(thickness > d) at each x.
  std::vector<std::pair<std::vector<double>, std::vector<double>>> profiles;
  for (std::size_t i : ok) {
    const Json& s = data[i].summary;
    if (!s.contains("deposit_profile")) continue;
    const Json& d = s["deposit_profile"];
    if (!d.contains("x_m") || !d.contains("thickness_m")) continue;
    try {
      profiles.push_back({d["x_m"].get<std::vector<double>>(), d["thickness_m"].get<std::vector<double>>()});
    } catch (...) {
    }
  }
  Json dep = Json::object();
  if (!profiles.empty() && !profiles.front().first.empty()) {
    const auto& grid = profiles.front().first;
    std::string text = "x_m";
    for (double d : spec.deposit_thresholds_m) text += fmt::format(",p_thicker_than_{}_m", d);
    text += "\n";
    for (double x : grid) {
      text += number_text(x);
      for (double d : spec.deposit_thresholds_m) {
        std::size_t count = 0;
        for (const auto& [px, pt] : profiles)
          if (px.size() == pt.size() && interpolate(px, pt, x) > d) ++count;
        text += "," + number_text(static_cast<double>(count) / static_cast<double>(profiles.size()));
      }
      text += "\n";
    }
    io::write_file_atomically(out_dir / "deposit_hazard.csv", text);
    dep = Json::object({{"file", "deposit_hazard.csv"}, {"members", profiles.size()}, {"thresholds_m", spec.deposit_thresholds_m}});
  } else {
    dep = Json::object({{"file", nullptr},
                        {"note", "the members' summary.json has no deposit_profile {x_m, thickness_m}: no hazard profile"}});
  }
  out["deposit_hazard"] = dep;

  io::write_json_file(out_dir / "ensemble.json", out);
  return res;
}

}  // namespace dsdem::ensemble
