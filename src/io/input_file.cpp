#include "io/input_file.hpp"

#include <fmt/format.h>

namespace dsdem::io {

std::string input_file_problem(const std::filesystem::path& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (st.type() == fs::file_type::not_found) return fmt::format("file not found: {}", path.string());
  if (ec) {
    // Keep the message readable when the name itself is the problem (e.g. ENAMETOOLONG).
    std::string shown = path.string();
    if (shown.size() > 200) shown = shown.substr(0, 120) + "..." + shown.substr(shown.size() - 60);
    return fmt::format("cannot access {}: {}", shown, ec.message());
  }
  if (st.type() == fs::file_type::directory) return fmt::format("{} is a directory, not a file", path.string());
  // A device or pipe (e.g. /dev/zero) could be read forever: only regular files.
  if (st.type() != fs::file_type::regular) return fmt::format("{}: not a regular file (a device, pipe or socket)", path.string());
  return "";
}

}  // namespace dsdem::io
