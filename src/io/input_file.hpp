#pragma once
// Checks that a file named in the input exists before anything reads it. Never throws:
// a name the OS refuses (too long, bad component) is an input error like a missing file,
// not a crash (a filesystem_error escaping std::filesystem::exists; found by fuzz_scenario).
#include <filesystem>
#include <string>

namespace dsdem::io {

// "" when `path` names an existing regular file (symbolic links followed); otherwise why
// not, as "file not found: P", "P is a directory, not a file", "P: not a regular file
// (...)" or "cannot access P: <OS error>".
std::string input_file_problem(const std::filesystem::path& path);

}  // namespace dsdem::io
