#pragma once
// Runs the dsdem binary in tests and captures what it prints.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

#include "common/remove_at_exit.hpp"

namespace dsdem::test {

struct Command {
  int exit_code = -1;
  std::string output;  // stdout and stderr
};

// Runs a shell command line, stdout and stderr captured.
inline Command run_command(const std::string& command_line) {
  Command c;
  const std::string cmd = command_line + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return c;
  char buf[4096];
  std::size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) c.output.append(buf, n);
  const int status = pclose(p);
  c.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return c;
}

inline Command run_dsdem(const std::string& args) { return run_command(std::string(DSDEM_BINARY) + " " + args); }

inline std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

inline std::filesystem::path fresh_dir(const std::string& name) {
  const auto d = std::filesystem::temp_directory_path() / ("dsdem_test_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  remove_at_exit(d);  // with the log a test may write next to it
  remove_at_exit(d.string() + ".log");
  return d;
}

inline std::string example(const std::string& rel) { return std::string(DSDEM_SOURCE_DIR) + "/examples/" + rel; }

}  // namespace dsdem::test
