#pragma once
// Scratch folders of a test binary removed when it exits: a `make test` left ~100
// folders in /tmp per run (meshes, run outputs) that no test removed after itself.
// DSDEM_KEEP_TEST_DIRS=1 keeps them, to look at what a failing test wrote.
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <vector>

namespace dsdem::test {

inline void remove_at_exit(const std::filesystem::path& p) {
  struct Registry {
    std::mutex m;
    std::vector<std::filesystem::path> paths;
    ~Registry() {
      if (const char* keep = std::getenv("DSDEM_KEEP_TEST_DIRS"); keep && *keep && *keep != '0') return;
      std::error_code ec;
      for (const auto& q : paths) std::filesystem::remove_all(q, ec);
    }
  };
  static Registry registry;
  const std::lock_guard<std::mutex> lock(registry.m);
  registry.paths.push_back(p);
}

}  // namespace dsdem::test
