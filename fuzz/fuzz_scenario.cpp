// Fuzz target: the scenario parser (YAML text -> Scenario, or io::ScenarioError).
// Any other exception, crash, hang or sanitizer report is a bug.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "io/scenario.hpp"

namespace {
// The scenario's files resolve against this directory, not the working directory: which
// files a fuzzed name reaches must not depend on where the repository is checked out
// (the CI smoke passed in one clone and failed in another with the same seed). It holds
// a fixed set of empty files, so the "file exists" branches stay reachable.
const std::string kDirectory = "/tmp/dsdem-fuzz-scenario";
}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  std::filesystem::create_directories(kDirectory + "/mesh");
  for (const char* name : {"slope.geo", "slope.msh", "quake.csv", "quake.at2", "mesh/square.geo"})
    std::ofstream(kDirectory + "/" + name, std::ios::trunc);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // The first line, when it starts with "#set ", is used as a --set override: the
  // override syntax is fuzzed together with the document.
  std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> overrides;
  if (text.rfind("#set ", 0) == 0) {
    const auto eol = text.find('\n');
    overrides.push_back(text.substr(5, eol == std::string::npos ? std::string::npos : eol - 5));
  }
  try {
    (void)dsdem::io::parse_scenario(text, kDirectory + "/fuzz.yaml", overrides);
  } catch (const dsdem::io::ScenarioError&) {
  }
  return 0;
}
