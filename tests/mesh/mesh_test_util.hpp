#pragma once
// Helpers shared by the mesh tests: the test data folder, a scratch folder per process
// and the message a call throws.
#include <unistd.h>

#include <exception>
#include <filesystem>
#include <functional>
#include <string>

#include "common/remove_at_exit.hpp"

namespace dsdem::test {

inline std::string mesh_data(const std::string& name) { return std::string(DSDEM_TEST_DATA_DIR) + "/mesh/" + name; }

// A folder under the system temp dir for this test process, removed at exit.
inline std::filesystem::path mesh_temp_dir() {
  const std::filesystem::path d =
      std::filesystem::temp_directory_path() / ("dsdem_test_mesh_" + std::to_string(::getpid()));
  std::filesystem::create_directories(d);
  static const bool registered = (remove_at_exit(d), true);
  (void)registered;
  return d;
}

// What f() throws, or "" when it returns.
inline std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace dsdem::test
