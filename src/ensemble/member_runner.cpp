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

RunnerResult run_members(const EnsembleSpec& spec, const std::vector<MemberPlan>& plans,
                         const std::vector<std::size_t>& which, const RunnerOptions& o) {
  RunnerResult res;
  std::deque<std::size_t> queue;
  for (std::size_t i : which) {
    if (member_complete(member_dir(o.out_dir, i, spec.members), plans[i])) {
      ++res.skipped;
      continue;
    }
    queue.push_back(i);
  }
  struct Running {
    std::size_t member = 0;
    int stage = 0;  // 0: the run, 1: the post-processing
    std::chrono::steady_clock::time_point start;
  };
  std::map<pid_t, Running> running;
  const auto t0 = std::chrono::steady_clock::now();
  std::size_t finished = 0;
  const std::size_t total = which.size();
  const int jobs = std::max(1, o.jobs);
  bool forwarded = false;
  bool progress_due = false;
  std::string progress_note;

  auto launch_run = [&](std::size_t i) {
    const fs::path dir = member_dir(o.out_dir, i, spec.members);
    std::error_code ec;
    fs::remove_all(dir, ec);  // a killed run's leftovers
    fs::create_directories(dir);
    std::vector<std::string> args{o.dsdem_exe, "run", spec.base, "-o", dir.string(), "--threads",
                                  std::to_string(spec.member_threads), "-q", "--no-plots"};
    if (!spec.member_fields) args.emplace_back("--no-fields");
    for (const auto& s : plans[i].sets) {
      args.emplace_back("--set");
      args.push_back(s);
    }
    running[spawn(args, dir / "member.log", true, spec.member_threads)] = {i, 0, std::chrono::steady_clock::now()};
  };
  auto launch_post = [&](const Running& r) {
    const fs::path dir = member_dir(o.out_dir, r.member, spec.members);
    std::vector<std::string> args;
    for (std::string w : spec.postprocess) {
      for (const auto& [from, to] : {std::pair<std::string, std::string>{"{out}", dir.string()}, {"{scripts}", o.scripts_dir}})
        for (std::size_t p; (p = w.find(from)) != std::string::npos;) w.replace(p, from.size(), to);
      args.push_back(w);
    }
    running[spawn(args, dir / "member.log", false, spec.member_threads)] = {r.member, 1, r.start};
  };
  auto finish = [&](const Running& r, const std::string& status, int exit_code, int sig, const std::string& diagnosis) {
    const fs::path dir = member_dir(o.out_dir, r.member, spec.members);
    Json m = Json::object();
    m["member"] = r.member;
    m["status"] = status;
    m["exit_code"] = exit_code;
    if (sig) m["signal"] = sig;
    m["diagnosis"] = diagnosis;
    Json values = Json::object();
    for (std::size_t j = 0; j < spec.vary.size(); ++j) values[spec.vary[j].name] = plans[r.member].values[j];
    m["values"] = values;
    m["sets"] = plans[r.member].sets;
    m["wall_time_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - r.start).count();
    io::write_json_file(dir / "member.json", m);
    ++finished;
    ++res.ran;
    if (status != "ok") ++res.failed;
    progress_note = status == "ok" ? "" : fmt::format(" - member {} {}: {}", r.member, status, diagnosis);
    progress_due = true;
  };
  // The progress line, once the pool has been refilled: the members running then.
  auto report_progress = [&] {
    if (!progress_due || o.quiet) return;
    progress_due = false;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const std::size_t done = res.skipped + finished;
    const double eta = elapsed / static_cast<double>(finished) * static_cast<double>(total - done);
    fmt::print(stderr, "{}ensemble: {}/{} members done ({} failed, {} running), ETA {}{}\n", o.label, done, total,
               res.failed, running.size(), duration_text(eta), progress_note);
  };

  while (!queue.empty() || !running.empty()) {
    const bool stop = o.stop_signal && *o.stop_signal;
    if (stop && !forwarded) {
      for (const auto& [pid, r] : running) ::kill(pid, SIGTERM);
      forwarded = true;
    }
    while (!stop && static_cast<int>(running.size()) < jobs && !queue.empty()) {
      launch_run(queue.front());
      queue.pop_front();
    }
    report_progress();
    if (running.empty()) break;
    int status = 0;
    const pid_t pid = ::waitpid(-1, &status, 0);
    if (pid < 0) {
      if (errno == EINTR) continue;
      if (errno == ECHILD) break;
      throw std::runtime_error(fmt::format("waiting for the members: {}", std::strerror(errno)));
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    const Running r = it->second;
    running.erase(it);
    const fs::path dir = member_dir(o.out_dir, r.member, spec.members);
    if (WIFSIGNALED(status)) {
      const int sig = WTERMSIG(status);
      if (sig == SIGKILL || sig == SIGTERM || sig == SIGINT) continue;  // killed: no marker, rerun next time
      finish(r, "crashed", -1, sig, fmt::format("killed by signal {} ({})", sig, strsignal(sig)));
      continue;
    }
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    if (r.stage == 1) {
      if (code == 0) finish(r, "ok", 0, 0, "");
      else finish(r, "postprocess_failed", code, 0, read_tail_error(dir / "member.log"));
      continue;
    }
    if (code == 128 + SIGINT || code == 128 + SIGTERM || code == 137) continue;  // stopped: rerun next time
    if (code == kExitNotExecuted) {  // the binary was missing or being replaced: rerun next time
      finish(r, "killed", code, 0, read_tail_error(dir / "member.log"));
      continue;
    }
    if (code == 0) {
      bool completed = false;
      try {
        completed = io::read_json_file(dir / "summary.json").value("completed", false);
      } catch (...) {
      }
      if (!completed) {
        finish(r, "failed", 0, 0, "the run ended without a complete summary.json");
      } else if (!spec.postprocess.empty() && !stop) {
        launch_post(r);
      } else if (!spec.postprocess.empty()) {
        continue;  // stopped before its post-processing: rerun next time
      } else {
        finish(r, "ok", 0, 0, "");
      }
    } else {
      const std::string st = code == kExitUnstable ? "unstable" : code == kExitInputError ? "input_error" : "failed";
      finish(r, st, code, 0, diagnosis_of(dir));
    }
  }
  report_progress();  // the last member's line
  res.stopped = !queue.empty() || (o.stop_signal && *o.stop_signal && res.ran + res.skipped < total);
  return res;
}

}  // namespace dsdem::ensemble
