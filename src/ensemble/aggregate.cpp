#include "ensemble/aggregate.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
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

namespace {

// One aggregation: the members' markers and summaries read once, then each product
// (members.csv, the statistics, events, sensitivity, convergence, envelopes, hazard).
class Aggregation {
 public:
  Aggregation(const EnsembleSpec& spec, const std::vector<MemberPlan>& plans, const fs::path& out_dir)
      : spec_(spec), plans_(plans), out_dir_(out_dir), data_(plans.size()) {}

  AggregateResult run() {
    read_members();
    write_members_csv();
    Json out = header();
    out["scalars"] = scalar_statistics();
    out["events"] = event_probabilities();
    out["sensitivity_spearman"] = sensitivity();
    out["convergence"] = convergence();
    out["envelopes"] = envelopes();
    out["deposit_hazard"] = deposit_hazard();
    io::write_json_file(out_dir_ / "ensemble.json", out);
    return res_;
  }

 private:
  // Every member's marker (status) and the scalars of its summary.json, in column order
  // of first appearance.
  void read_members() {
    res_.members = plans_.size();
    for (std::size_t i = 0; i < plans_.size(); ++i) {
      const fs::path dir = member_dir(out_dir_, i, spec_.members);
      MemberData& m = data_[i];
      try {
        const Json marker = io::read_json_file(dir / "member.json");
        m.status = marker.value("status", std::string("missing"));
        m.exit_code = marker.value("exit_code", 0);
        m.diagnosis = marker.value("diagnosis", std::string());
      } catch (...) {
        m.status = "missing";
      }
      if (m.status == "killed") m.status = "missing";
      if (m.status != "missing" && fs::exists(dir / "summary.json")) read_summary(dir / "summary.json", m);
      if (m.status == "ok") ++res_.ok;
      else if (m.status == "missing") ++res_.missing;
      else ++res_.failed;
    }
    // The ok members, in index order, feed every statistic.
    for (std::size_t i = 0; i < plans_.size(); ++i)
      if (data_[i].status == "ok") ok_.push_back(i);
  }

  void read_summary(const fs::path& file, MemberData& m) {
    try {
      m.summary = io::read_json_file(file);
      for (auto& [k, v] : flatten_scalars(m.summary)) {
        if (!seen_.count(k)) {
          seen_.insert(k);
          columns_.push_back(k);
        }
        if (v.kind == Scalar::Kind::Boolean) is_boolean_[k] = true;
        else if (v.kind == Scalar::Kind::Number) is_boolean_.emplace(k, false);
        m.scalars[k] = v;
      }
    } catch (...) {
    }
  }

  void write_members_csv() const {
    std::string csv = "member,status,exit_code";
    for (const auto& v : spec_.vary) csv.append(",").append(csv_field(v.name));
    for (const auto& c : columns_) csv.append(",").append(csv_field(c));
    csv += "\n";
    for (std::size_t i = 0; i < plans_.size(); ++i) {
      const MemberData& m = data_[i];
      csv += fmt::format("{},{},{}", i, m.status, m.status == "missing" ? "" : std::to_string(m.exit_code));
      for (const auto& v : plans_[i].values) csv.append(",").append(csv_field(v));
      for (const auto& c : columns_) {
        csv += ",";
        const auto it = m.scalars.find(c);
        if (it == m.scalars.end() || it->second.kind == Scalar::Kind::Missing) continue;
        csv += it->second.kind == Scalar::Kind::Boolean ? (it->second.value != 0.0 ? "true" : "false")
                                                         : number_text(it->second.value);
      }
      csv += "\n";
    }
    io::write_file_atomically(out_dir_ / "members.csv", csv);
  }

  // The values of `key` over the ok members that have it (and who they are).
  std::vector<double> series(const std::string& key, std::vector<std::size_t>* who = nullptr) const {
    std::vector<double> x;
    for (std::size_t i : ok_) {
      const auto it = data_[i].scalars.find(key);
      if (it == data_[i].scalars.end() || it->second.kind == Scalar::Kind::Missing) continue;
      x.push_back(it->second.value);
      if (who) who->push_back(i);
    }
    return x;
  }

  Json header() const {
    Json out = Json::object();
    out["title"] = spec_.title;
    out["ensemble_file"] = spec_.file;
    out["base"] = spec_.base;
    out["members"] = plans_.size();
    out["sampling"] = Json::object(
        {{"method", spec_.method == SamplingMethod::MonteCarlo ? "monte_carlo" : "latin_hypercube"}, {"seed", spec_.seed}});
    Json varied = Json::array();
    for (const auto& v : spec_.vary) varied.push_back(distribution_json(v));
    out["varied"] = varied;
    out["fixed"] = spec_.fixed;
    out["completed_members"] = res_.ok;
    out["failed_members"] = res_.failed;
    out["missing_members"] = res_.missing;
    Json failures = Json::array();
    for (std::size_t i = 0; i < plans_.size(); ++i)
      if (data_[i].status != "ok" && data_[i].status != "missing")
        failures.push_back(Json::object({{"member", i}, {"status", data_[i].status}, {"exit_code", data_[i].exit_code},
                                         {"diagnosis", data_[i].diagnosis}}));
    out["failures"] = failures;
    out["statistics_note"] = "over the completed members; intervals 95 %: percentile bootstrap for mean, sd and quantiles, "
                             "Wilson for probabilities";
    return out;
  }

  // Mean, sd, min, percentiles, max of every numeric output; for those that vary, 95 %
  // bootstrap intervals and the empirical exceedance P(X >= x_(i)) = (n - i) / n.
  Json scalar_statistics() {
    // P5/P50/P95, and P10/P90 (the percentiles engineers quote for a hazard).
    const std::vector<double> ps{0.05, 0.10, 0.5, 0.90, 0.95};
    const std::vector<std::string> p_names{"p5", "p10", "p50", "p90", "p95"};
    Json scalars = Json::object();
    for (std::size_t k = 0; k < columns_.size(); ++k) {
      const std::string& key = columns_[k];
      if (is_boolean_[key]) continue;
      std::vector<double> x = series(key);
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
        varying_.push_back(key);
        const auto b = bootstrap(x, ps, spec_.bootstrap_resamples, key_seed(spec_.seed, k));
        Json ci = Json::object({{"mean", interval_json(b.mean)}, {"sd", interval_json(b.sd)}});
        for (std::size_t q = 0; q < ps.size(); ++q) ci[p_names[q]] = interval_json(b.quantiles[q]);
        s["ci95"] = ci;
        Json pv = Json::array();
        for (std::size_t i = 0; i < sorted.size(); ++i)
          pv.push_back(static_cast<double>(sorted.size() - i) / static_cast<double>(sorted.size()));
        s["exceedance"] = Json::object({{"value", sorted}, {"probability", pv}});
      }
      scalars[key] = s;
    }
    return scalars;
  }

  static Json event_json(std::size_t count, std::size_t n) {
    const Interval w = wilson_interval(count, n);
    return Json::object({{"n", n}, {"count", count}, {"probability", n ? static_cast<double>(count) / n : 0.0},
                         {"wilson95", interval_json(w)}});
  }

  // Every boolean of summary.json, the file's thresholds, and a member failing.
  Json event_probabilities() {
    Json events = Json::object();
    for (const auto& key : columns_) {
      if (!is_boolean_[key]) continue;
      const auto x = series(key);
      Json e = event_json(static_cast<std::size_t>(std::count(x.begin(), x.end(), 1.0)), x.size());
      e["kind"] = "boolean";
      e["key"] = key;
      events[key] = e;
      event_series_.push_back({key, x});
    }
    for (const auto& ev : spec_.events) {
      if (!seen_.count(ev.key)) {
        events[ev.name] = Json::object({{"kind", "threshold"}, {"key", ev.key}, {"n", 0},
                                        {"error", "no member's summary.json has this key (see members.csv for the names)"}});
        continue;
      }
      // A null value (e.g. river_blocked_time_s of a run in which the river was never
      // blocked) is the event not happening; a member without the key does not count.
      std::vector<double> hit;
      for (std::size_t i : ok_) {
        const auto it = data_[i].scalars.find(ev.key);
        if (it == data_[i].scalars.end()) continue;
        hit.push_back(it->second.kind != Scalar::Kind::Missing && ev.holds(it->second.value) ? 1.0 : 0.0);
      }
      Json e = event_json(static_cast<std::size_t>(std::count(hit.begin(), hit.end(), 1.0)), hit.size());
      e["kind"] = "threshold";
      e["key"] = ev.key;
      e["threshold"] = ev.threshold;
      events[ev.name] = e;
      event_series_.push_back({ev.name, hit});
    }
    Json e = event_json(res_.failed, res_.ok + res_.failed);
    e["kind"] = "member";
    e["key"] = "status != ok";
    events["member_failed"] = e;
    return events;
  }

  // Spearman rank correlation of each varying output with each numeric input.
  Json sensitivity() const {
    Json sens = Json::object();
    for (const auto& key : varying_) {
      std::vector<std::size_t> who;
      const auto y = series(key, &who);
      if (y.size() < 3) continue;
      Json row = Json::object();
      for (std::size_t j = 0; j < spec_.vary.size(); ++j) {
        std::vector<double> x;
        for (std::size_t i : who) x.push_back(plans_[i].numbers[j]);
        if (std::any_of(x.begin(), x.end(), [](double v) { return !std::isfinite(v); })) continue;
        row[spec_.vary[j].name] = spearman(x, y);
      }
      sens[key] = row;
    }
    return sens;
  }

  // The estimates from the first n completed members.
  Json convergence() const {
    Json conv = Json::object();
    const auto counts = convergence_counts(ok_.size());
    conv["n"] = counts;
    Json conv_s = Json::object();
    for (const auto& key : varying_) {
      const auto x = series(key);
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
    for (const auto& [name, x] : event_series_) {
      Json p = Json::array();
      for (std::size_t n : counts) {
        const std::size_t m = std::min(n, x.size());
        p.push_back(m ? std::count(x.begin(), x.begin() + static_cast<long>(m), 1.0) / static_cast<double>(m) : 0.0);
      }
      conv_e[name] = p;
    }
    conv["events"] = conv_e;
    return conv;
  }

  // P5, P50, P95 over time of each gauge's displacement and speed magnitudes and of the
  // kinetic energy, interpolated to the longest member's times (OUT/envelopes.csv).
  Json envelopes() const {
    std::vector<Table> histories;
    for (std::size_t i : ok_) histories.push_back(read_csv(member_dir(out_dir_, i, spec_.members) / "history.csv"));
    std::size_t longest = 0;
    for (std::size_t h = 0; h < histories.size(); ++h)
      if (histories[h].rows.size() > histories[longest].rows.size()) longest = h;
    Json env = Json::object();
    if (histories.empty() || histories[longest].rows.empty()) {
      env["file"] = nullptr;
      env["note"] = "no completed member has a history.csv";
      return env;
    }
    const Table& ref = histories[longest];
    const EnvelopeSeries series = envelope_series(ref);
    const int tcol = ref.column("time_s");
    std::vector<double> grid;
    for (const auto& r : ref.rows) grid.push_back(r[static_cast<std::size_t>(tcol)]);
    const std::array<double, 3> ps{0.05, 0.5, 0.95};
    std::vector<std::array<std::vector<double>, 3>> pct(series.names.size());
    for (std::size_t s = 0; s < series.names.size(); ++s) {
      const auto member_series = on_grid(histories, series.columns[s], grid);
      for (std::size_t g = 0; g < grid.size(); ++g) {
        std::vector<double> at;
        for (const auto& ms : member_series) at.push_back(ms[g]);
        std::sort(at.begin(), at.end());
        for (std::size_t q = 0; q < 3; ++q) pct[s][q].push_back(quantile_sorted(at, ps[q]));
      }
    }
    std::string text = "time_s";
    for (const auto& n : series.names) text += fmt::format(",{0}_p5,{0}_p50,{0}_p95", n);
    text += "\n";
    for (std::size_t g = 0; g < grid.size(); ++g) {
      text += number_text(grid[g]);
      for (std::size_t s = 0; s < series.names.size(); ++s)
        for (std::size_t q = 0; q < 3; ++q) text += "," + number_text(pct[s][q][g]);
      text += "\n";
    }
    io::write_file_atomically(out_dir_ / "envelopes.csv", text);
    env["file"] = "envelopes.csv";
    env["series"] = series.names;
    env["members"] = histories.size();
    return env;
  }

  // The enveloped series of a history.csv header: gauge displacement and speed magnitudes
  // (x and y columns), and the kinetic energy (a plain column: y "").
  struct EnvelopeSeries {
    std::vector<std::string> names;
    std::vector<std::pair<std::string, std::string>> columns;
  };
  static EnvelopeSeries envelope_series(const Table& ref) {
    EnvelopeSeries out;
    for (const auto& h : ref.header) {
      const auto strip = [&](const std::string& suffix) {
        return h.size() > suffix.size() && h.compare(h.size() - suffix.size(), suffix.size(), suffix) == 0
                   ? h.substr(0, h.size() - suffix.size())
                   : std::string();
      };
      if (const auto g = strip("_displacement_x_m"); !g.empty()) {
        out.names.push_back(g + "_displacement_m");
        out.columns.push_back({h, g + "_displacement_y_m"});
      } else if (const auto g2 = strip("_velocity_x_m_per_s"); !g2.empty()) {
        out.names.push_back(g2 + "_speed_m_per_s");
        out.columns.push_back({h, g2 + "_velocity_y_m_per_s"});
      }
    }
    if (ref.column("kinetic_J_per_m") >= 0) {
      out.names.push_back("kinetic_J_per_m");
      out.columns.push_back({"kinetic_J_per_m", ""});
    }
    return out;
  }

  // Each history's series (a column, or the magnitude of an x and y pair) on the grid.
  static std::vector<std::vector<double>> on_grid(const std::vector<Table>& histories,
                                                  const std::pair<std::string, std::string>& column,
                                                  const std::vector<double>& grid) {
    std::vector<std::vector<double>> out;
    for (const auto& h : histories) {
      const int cx = h.column(column.first), cy = column.second.empty() ? -1 : h.column(column.second);
      const int ct = h.column("time_s");
      if (cx < 0 || ct < 0) continue;
      std::vector<double> t, y;
      for (const auto& r : h.rows) {
        t.push_back(r[static_cast<std::size_t>(ct)]);
        const double a = r[static_cast<std::size_t>(cx)];
        y.push_back(cy >= 0 ? std::hypot(a, r[static_cast<std::size_t>(cy)]) : a);
      }
      std::vector<double> at;
      for (double x : grid) at.push_back(interpolate(t, y, x));
      out.push_back(std::move(at));
    }
    return out;
  }

  // P(thickness > d) at each x of the members' deposit profiles (OUT/deposit_hazard.csv).
  Json deposit_hazard() const {
    std::vector<std::pair<std::vector<double>, std::vector<double>>> profiles;
    for (std::size_t i : ok_) {
      const Json& s = data_[i].summary;
      if (!s.contains("deposit_profile")) continue;
      const Json& d = s["deposit_profile"];
      if (!d.contains("x_m") || !d.contains("thickness_m")) continue;
      try {
        profiles.push_back({d["x_m"].get<std::vector<double>>(), d["thickness_m"].get<std::vector<double>>()});
      } catch (...) {
      }
    }
    if (profiles.empty() || profiles.front().first.empty())
      return Json::object({{"file", nullptr},
                           {"note", "the members' summary.json has no deposit_profile {x_m, thickness_m}: no hazard profile"}});
    const auto& grid = profiles.front().first;
    std::string text = "x_m";
    for (double d : spec_.deposit_thresholds_m) text += fmt::format(",p_thicker_than_{}_m", d);
    text += "\n";
    for (double x : grid) {
      text += number_text(x);
      for (double d : spec_.deposit_thresholds_m) {
        std::size_t count = 0;
        for (const auto& [px, pt] : profiles)
          if (px.size() == pt.size() && interpolate(px, pt, x) > d) ++count;
        text += "," + number_text(static_cast<double>(count) / static_cast<double>(profiles.size()));
      }
      text += "\n";
    }
    io::write_file_atomically(out_dir_ / "deposit_hazard.csv", text);
    return Json::object(
        {{"file", "deposit_hazard.csv"}, {"members", profiles.size()}, {"thresholds_m", spec_.deposit_thresholds_m}});
  }

  const EnsembleSpec& spec_;
  const std::vector<MemberPlan>& plans_;
  const fs::path out_dir_;
  AggregateResult res_;
  std::vector<MemberData> data_;
  std::vector<std::size_t> ok_;
  std::vector<std::string> columns_;  // the summary scalars, in order of first appearance
  std::set<std::string> seen_;
  std::map<std::string, bool> is_boolean_;
  std::vector<std::string> varying_;  // numeric outputs that differ between members
  std::vector<std::pair<std::string, std::vector<double>>> event_series_;  // 0/1 over ok members
};

}  // namespace

AggregateResult aggregate(const EnsembleSpec& spec, const std::vector<MemberPlan>& plans, const fs::path& out_dir) {
  return Aggregation(spec, plans, out_dir).run();
}

}  // namespace dsdem::ensemble
