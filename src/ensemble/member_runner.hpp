#pragma once
// Runs an ensemble's members as child processes of the same dsdem binary (docs/theory.md §13):
// `dsdem run BASE -o OUT/members/NNNN --set ...`, a pool of `jobs` at a time. A member is
// complete when OUT/members/NNNN/member.json exists (written atomically once its run and
// post-processing ended): a rerun skips complete members and reruns those whose run was
// killed. A member that fails is recorded with its exit status and diagnosis; the others go on.
#include <csignal>
#include <filesystem>
#include <string>
#include <vector>

#include "ensemble/ensemble_file.hpp"

namespace dsdem::ensemble {

struct RunnerOptions {
  std::filesystem::path out_dir;
  std::string dsdem_exe;    // the binary that runs the members
  std::string scripts_dir;  // {scripts} in member.postprocess
  int jobs = 1;             // members at a time (this process)
  bool quiet = false;
  std::string label;        // progress prefix (e.g. "rank 1/2: ")
  const volatile std::sig_atomic_t* stop_signal = nullptr;  // set: start no more members
};

// Member folder name: 0000, 0001, ... (more digits when there are more members).
std::string member_folder_name(std::size_t index, std::size_t members);
std::filesystem::path member_dir(const std::filesystem::path& out_dir, std::size_t index, std::size_t members);

// True when the member's marker exists and records its run as ended (ok or failed, not
// killed). Throws when the marker is of other overrides (another ensemble in that folder).
bool member_complete(const std::filesystem::path& dir, const MemberPlan& plan);

struct RunnerResult {
  std::size_t ran = 0, skipped = 0, failed = 0;
  bool stopped = false;  // by the stop signal: members left to run
};

// Runs the members `which` (indices into plans) that are not complete.
RunnerResult run_members(const EnsembleSpec& spec, const std::vector<MemberPlan>& plans,
                         const std::vector<std::size_t>& which, const RunnerOptions& options);

}  // namespace dsdem::ensemble
