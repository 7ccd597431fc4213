#include "io/history_writer.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "io/atomic_file.hpp"

namespace dsdem::io {
namespace fs = std::filesystem;

namespace {

void check_columns(const std::vector<HistoryColumn>& columns, const fs::path& path) {
  if (columns.empty())
    throw std::invalid_argument(fmt::format("history '{}': no columns", path.string()));
  std::vector<std::string> names;
  for (const auto& c : columns) {
    const std::string name = c.name();
    if (c.quantity.empty() || name.find_first_of(",\"\r\n") != std::string::npos)
      throw std::invalid_argument(
          fmt::format("history '{}': bad column name \"{}\"", path.string(), name));
    if (std::find(names.begin(), names.end(), name) != names.end())
      throw std::invalid_argument(
          fmt::format("history '{}': column \"{}\" given twice", path.string(), name));
    names.push_back(name);
  }
}

}  // namespace

std::string HistoryColumn::name() const { return name_with_unit(quantity, unit); }

HistoryWriter::HistoryWriter(fs::path path, std::vector<HistoryColumn> columns,
                             HistoryOptions options)
    : path_(std::move(path)), columns_(std::move(columns)), options_(options) {
  check_columns(columns_, path_);
  // Atomic header first: readers never see a file without its column names.
  write_file_atomically(path_, header() + "\n");
  fd_ = ::open(path_.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
  if (fd_ < 0) throw_os_error("cannot open history", path_, errno);
  buffer_.reserve(4096);
  last_flush_ = std::chrono::steady_clock::now();
}

HistoryWriter::HistoryWriter(fs::path path, std::vector<HistoryColumn> columns, Resume resume,
                             HistoryOptions options)
    : path_(std::move(path)), columns_(std::move(columns)), options_(options) {
  check_columns(columns_, path_);
  std::ifstream in(path_, std::ios::binary);
  if (!in) throw HistoryResumeError(fmt::format("cannot resume history '{}': the file is missing", path_.string()));
  std::string line;
  if (!std::getline(in, line) || line != header()) {
    // The first column that differs: what the two runs' scenarios (or versions) disagree on.
    std::vector<std::string> had;
    std::stringstream cells(line);
    for (std::string c; std::getline(cells, c, ',');) had.push_back(c);
    std::size_t k = 0;
    while (k < had.size() && k < columns_.size() && had[k] == columns_[k].name()) ++k;
    throw HistoryResumeError(fmt::format(
        "cannot resume history '{}': its columns differ from this run's at column {}: '{}' there, '{}' here "
        "(another scenario, --set options or version?)",
        path_.string(), k + 1, k < had.size() ? had[k] : "(none)", k < columns_.size() ? columns_[k].name() : "(none)"));
  }
  std::string kept = line + "\n";
  std::size_t rows = 0;
  // Only complete lines count (a kill never leaves half a row, but be safe).
  while (rows < resume.keep_rows && std::getline(in, line) && !in.eof()) {
    kept += line;
    kept += '\n';
    ++rows;
  }
  if (rows < resume.keep_rows)
    throw HistoryResumeError(fmt::format("cannot resume history '{}': it has {} rows, the checkpoint expects {}",
                                         path_.string(), rows, resume.keep_rows));
  in.close();
  write_file_atomically(path_, kept);
  fd_ = ::open(path_.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
  if (fd_ < 0) throw_os_error("cannot open history", path_, errno);
  rows_ = rows;
  buffer_.reserve(4096);
  last_flush_ = std::chrono::steady_clock::now();
}

HistoryWriter::~HistoryWriter() {
  try {
    close();
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
  }
  if (fd_ >= 0) (void)::close(fd_);  // close() threw before releasing the descriptor
}

std::string HistoryWriter::header() const {
  std::string line;
  for (std::size_t i = 0; i < columns_.size(); ++i) {
    if (i > 0) line += ',';
    line += columns_[i].name();
  }
  return line;
}

void HistoryWriter::append(std::span<const double> row) {
  if (fd_ < 0)
    throw std::logic_error(fmt::format("history '{}': append after close", path_.string()));
  if (row.size() != columns_.size())
    throw std::invalid_argument(fmt::format("history '{}': row of {} values for {} columns",
                                            path_.string(), row.size(), columns_.size()));
  // fmt's default format of a double is the shortest string that round-trips exactly.
  auto out = std::back_inserter(buffer_);
  for (std::size_t i = 0; i < row.size(); ++i) {
    if (i > 0) buffer_ += ',';
    fmt::format_to(out, "{}", row[i]);
  }
  buffer_ += '\n';
  ++rows_;
  if (std::chrono::steady_clock::now() - last_flush_ >= options_.flush_interval) flush();
}

void HistoryWriter::flush() {
  if (fd_ < 0) return;
  // Whole lines in one write() each time: a reader or a kill never sees half a row.
  std::size_t done = 0;
  while (done < buffer_.size()) {
    const ssize_t n = ::write(fd_, buffer_.data() + done, buffer_.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      const int err = errno;
      buffer_.erase(0, done);  // keep what is not on disk for a later retry
      throw_os_error("cannot write history", path_, err);
    }
    done += static_cast<std::size_t>(n);
  }
  buffer_.clear();
  if (::fsync(fd_) != 0 && errno != EINVAL) throw_os_error("cannot flush history", path_, errno);
  last_flush_ = std::chrono::steady_clock::now();
}

void HistoryWriter::close() {
  if (fd_ < 0) return;
  flush();
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) throw_os_error("cannot close history", path_, errno);
}

}  // namespace dsdem::io
