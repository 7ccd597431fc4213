#include "ensemble/member_runner.hpp"

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <deque>
#include <fstream>
#include <map>
#include <stdexcept>

#include "io/json_file.hpp"

namespace dsdem::ensemble {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace {

// Exit codes of `dsdem run` (app/main.cpp): 2 bad input, 3 unstable, 128 + signal when stopped.
constexpr int kExitInputError = 2;
constexpr int kExitUnstable = 3;
constexpr int kExitNotExecuted = 127;  // spawn(): exec failed

// Starts `args` with stdout and stderr appended to `log`. The child dies with this process
// (PR_SET_PDEATHSIG), so a killed ensemble leaves no member running behind it.
pid_t spawn(const std::vector<std::string>& args, const fs::path& log, bool truncate, int threads) {
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const std::string log_s = log.string();
  const std::string omp = std::to_string(threads);
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error(fmt::format("cannot start a member: fork: {}", std::strerror(errno)));
  if (pid == 0) {
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(137);
    const int fd = ::open(log_s.c_str(), O_WRONLY | O_CREAT | (truncate ? O_TRUNC : O_APPEND), 0644);
    if (fd >= 0) {
      ::dup2(fd, 1);
      ::dup2(fd, 2);
      ::close(fd);
    }
    const int null = ::open("/dev/null", O_RDONLY);
    if (null >= 0) ::dup2(null, 0);
    ::setenv("OMP_NUM_THREADS", omp.c_str(), 1);
    // A member is a plain run, not a rank: it must not see the launcher's MPI environment.
    ::unsetenv("OMPI_COMM_WORLD_SIZE");
    ::execvp(argv[0], argv.data());
    const char msg[] = "error: cannot execute the member's command\n";
    [[maybe_unused]] auto n = ::write(2, msg, sizeof msg - 1);
    ::_exit(kExitNotExecuted);
  }
  return pid;
}

// The last "error:" message of a log with its indented lines, or else its last line.
std::string read_tail_error(const fs::path& log) {
  std::ifstream in(log);
  std::string line, last, last_error;
  bool in_error = false;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    last = line;
    if (line.rfind("error:", 0) == 0) {
      last_error = line;
      in_error = true;
    } else if (in_error && line[0] == ' ') {
      const std::size_t k = line.find_first_not_of(' ');
      if (k != std::string::npos) last_error.append(" ").append(line, k, std::string::npos);
    } else {
      in_error = false;
    }
  }
  return last_error.empty() ? last : last_error;
}

std::string diagnosis_of(const fs::path& dir) {
  const fs::path d = dir / "diagnosis.json";
  if (fs::exists(d)) {
    try {
      const auto j = io::read_json_file(d);
      if (j.contains("message") && j["message"].is_string()) return j["message"].get<std::string>();
    } catch (...) {
    }
  }
  return read_tail_error(dir / "member.log");
}

std::string duration_text(double s) {
  if (!(s >= 0.0) || s > 1e8) return "?";
  const long t = static_cast<long>(s + 0.5);
  if (t >= 3600) return fmt::format("{}h{:02d}m", t / 3600, (t % 3600) / 60);
  if (t >= 60) return fmt::format("{}m{:02d}s", t / 60, t % 60);
  return fmt::format("{}s", t);
}

}  // namespace

std::string member_folder_name(std::size_t index, std::size_t members) {
  std::size_t digits = 4;
  for (std::size_t m = 10000; m < members; m *= 10) ++digits;
  return fmt::format("{:0{}d}", index, digits);
}

fs::path member_dir(const fs::path& out_dir, std::size_t index, std::size_t members) {
  return out_dir / "members" / member_folder_name(index, members);
}

bool member_complete(const fs::path& dir, const MemberPlan& plan) {
  const fs::path marker = dir / "member.json";
  if (!fs::exists(marker)) return false;
  Json j;
  try {
    j = io::read_json_file(marker);
  } catch (...) {
    return false;
  }
  std::vector<std::string> sets;
  if (j.contains("sets"))
    for (const auto& s : j["sets"]) sets.push_back(s.get<std::string>());
  if (sets != plan.sets)
    throw std::runtime_error(fmt::format(
        "{} holds a member run with other values than this ensemble's member {} (was the ensemble file changed?): "
        "give another output folder or delete that one",
        dir.string(), plan.index));
  return j.value("status", std::string("killed")) != "killed";
}

namespace {

// The pool of member processes: at most o.jobs at a time, each member's run then its
// post-processing; each exit classified (ok, failed with its diagnosis, or killed: rerun
// next time), with a progress line.
class MemberPool {
 public:
  MemberPool(const EnsembleSpec& spec, const std::vector<MemberPlan>& plans, const RunnerOptions& o)
      : spec_(spec), plans_(plans), o_(o), jobs_(std::max(1, o.jobs)), t0_(std::chrono::steady_clock::now()) {}

  RunnerResult run(const std::vector<std::size_t>& which) {
    std::deque<std::size_t> queue;
    for (std::size_t i : which) {
      if (member_complete(member_dir(o_.out_dir, i, spec_.members), plans_[i])) {
        ++res_.skipped;
        continue;
      }
      queue.push_back(i);
    }
    total_ = which.size();
    bool forwarded = false;
    while (!queue.empty() || !running_.empty()) {
      const bool stop = o_.stop_signal && *o_.stop_signal;
      if (stop && !forwarded) {
        for (const auto& [pid, r] : running_) ::kill(pid, SIGTERM);
        forwarded = true;
      }
      while (!stop && static_cast<int>(running_.size()) < jobs_ && !queue.empty()) {
        launch_run(queue.front());
        queue.pop_front();
      }
      report_progress();
      if (running_.empty()) break;
      int status = 0;
      const pid_t pid = ::waitpid(-1, &status, 0);
      if (pid < 0) {
        if (errno == EINTR) continue;
        if (errno == ECHILD) break;
        throw std::runtime_error(fmt::format("waiting for the members: {}", std::strerror(errno)));
      }
      const auto it = running_.find(pid);
      if (it == running_.end()) continue;
      const Running r = it->second;
      running_.erase(it);
      exited(r, status, stop);
    }
    report_progress();  // the last member's line
    res_.stopped = !queue.empty() || (o_.stop_signal && *o_.stop_signal && res_.ran + res_.skipped < total_);
    return res_;
  }

 private:
  struct Running {
    std::size_t member = 0;
    int stage = 0;  // 0: the run, 1: the post-processing
    std::chrono::steady_clock::time_point start;
  };

  fs::path dir_of(std::size_t member) const { return member_dir(o_.out_dir, member, spec_.members); }

  void launch_run(std::size_t i) {
    const fs::path dir = dir_of(i);
    std::error_code ec;
    fs::remove_all(dir, ec);  // a killed run's leftovers
    fs::create_directories(dir);
    std::vector<std::string> args{o_.dsdem_exe, "run", spec_.base, "-o", dir.string(), "--threads",
                                  std::to_string(spec_.member_threads), "-q", "--no-plots"};
    if (!spec_.member_fields) args.emplace_back("--no-fields");
    for (const auto& s : plans_[i].sets) {
      args.emplace_back("--set");
      args.push_back(s);
    }
    running_[spawn(args, dir / "member.log", true, spec_.member_threads)] = {i, 0, std::chrono::steady_clock::now()};
  }

  void launch_post(const Running& r) {
    const fs::path dir = dir_of(r.member);
    std::vector<std::string> args;
    for (std::string w : spec_.postprocess) {
      for (const auto& [from, to] : {std::pair<std::string, std::string>{"{out}", dir.string()}, {"{scripts}", o_.scripts_dir}})
        for (std::size_t p; (p = w.find(from)) != std::string::npos;) w.replace(p, from.size(), to);
      args.push_back(w);
    }
    running_[spawn(args, dir / "member.log", false, spec_.member_threads)] = {r.member, 1, r.start};
  }

  // A process ended: the member is finished (its marker written), goes on to its
  // post-processing, or was stopped (no marker: rerun next time).
  void exited(const Running& r, int status, bool stop) {
    const fs::path dir = dir_of(r.member);
    if (WIFSIGNALED(status)) {
      const int sig = WTERMSIG(status);
      if (sig == SIGKILL || sig == SIGTERM || sig == SIGINT) return;  // killed: no marker, rerun next time
      finish(r, "crashed", -1, sig, fmt::format("killed by signal {} ({})", sig, strsignal(sig)));
      return;
    }
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    if (r.stage == 1) {
      if (code == 0) finish(r, "ok", 0, 0, "");
      else finish(r, "postprocess_failed", code, 0, read_tail_error(dir / "member.log"));
      return;
    }
    if (code == 128 + SIGINT || code == 128 + SIGTERM || code == 137) return;  // stopped: rerun next time
    if (code == kExitNotExecuted) {  // the binary was missing or being replaced: rerun next time
      finish(r, "killed", code, 0, read_tail_error(dir / "member.log"));
      return;
    }
    if (code != 0) {
      const std::string st = code == kExitUnstable ? "unstable" : code == kExitInputError ? "input_error" : "failed";
      finish(r, st, code, 0, diagnosis_of(dir));
      return;
    }
    bool completed = false;
    try {
      completed = io::read_json_file(dir / "summary.json").value("completed", false);
    } catch (...) {
    }
    if (!completed) finish(r, "failed", 0, 0, "the run ended without a complete summary.json");
    else if (!spec_.postprocess.empty() && !stop) launch_post(r);
    else if (spec_.postprocess.empty()) finish(r, "ok", 0, 0, "");
    // else: stopped before its post-processing, rerun next time
  }

  // The member's marker (member.json), last: a member with one is complete.
  void finish(const Running& r, const std::string& status, int exit_code, int sig, const std::string& diagnosis) {
    Json m = Json::object();
    m["member"] = r.member;
    m["status"] = status;
    m["exit_code"] = exit_code;
    if (sig) m["signal"] = sig;
    m["diagnosis"] = diagnosis;
    Json values = Json::object();
    for (std::size_t j = 0; j < spec_.vary.size(); ++j) values[spec_.vary[j].name] = plans_[r.member].values[j];
    m["values"] = values;
    m["sets"] = plans_[r.member].sets;
    m["wall_time_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - r.start).count();
    io::write_json_file(dir_of(r.member) / "member.json", m);
    ++finished_;
    ++res_.ran;
    if (status != "ok") ++res_.failed;
    progress_note_ = status == "ok" ? "" : fmt::format(" - member {} {}: {}", r.member, status, diagnosis);
    progress_due_ = true;
  }

  // The progress line, once the pool has been refilled: the members running then.
  void report_progress() {
    if (!progress_due_ || o_.quiet) return;
    progress_due_ = false;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
    const std::size_t done = res_.skipped + finished_;
    const double eta = elapsed / static_cast<double>(finished_) * static_cast<double>(total_ - done);
    fmt::print(stderr, "{}ensemble: {}/{} members done ({} failed, {} running), ETA {}{}\n", o_.label, done, total_,
               res_.failed, running_.size(), duration_text(eta), progress_note_);
  }

  const EnsembleSpec& spec_;
  const std::vector<MemberPlan>& plans_;
  const RunnerOptions& o_;
  const int jobs_;
  const std::chrono::steady_clock::time_point t0_;
  RunnerResult res_;
  std::map<pid_t, Running> running_;
  std::size_t finished_ = 0, total_ = 0;
  bool progress_due_ = false;
  std::string progress_note_;
};

}  // namespace

RunnerResult run_members(const EnsembleSpec& spec, const std::vector<MemberPlan>& plans,
                         const std::vector<std::size_t>& which, const RunnerOptions& o) {
  return MemberPool(spec, plans, o).run(which);
}

}  // namespace dsdem::ensemble
