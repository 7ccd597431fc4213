#pragma once
// CSV time histories (docs/user-guide.md): gauge displacements and velocities, energy balance,
// plate loads. One file per history, a fixed list of columns declared up front.
//
// Format: one header line of column names carrying their units by the `<quantity>_<unit>`
// convention of io/atomic_file.hpp (e.g. `time_s,kinetic_energy_J_per_m`), then one line
// per row, comma-separated, each number in the shortest form that parses back to the
// same double (non-finite values as nan, inf, -inf). Reads directly with
// numpy.genfromtxt(names=True), pandas.read_csv or a spreadsheet.
//
// Durability: the header is written atomically when the writer is created, so the file
// always exists with a complete header. Rows are buffered in memory and written whole
// lines at a time, with fsync, at least every `flush_interval` and on flush()/close():
// a run that is killed keeps its history up to the last flush, with no partial line.
#include <chrono>
#include <cstddef>
#include <filesystem>
#include <initializer_list>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace dsdem::io {

struct HistoryColumn {
  std::string quantity;  // snake_case, e.g. "gauge1_displacement_x"
  std::string unit;      // SI unit token, "" if dimensionless
  std::string name() const;  // name_with_unit(quantity, unit)
};

struct HistoryOptions {
  // Rows reach the disk at least this often (checked when a row is appended).
  std::chrono::duration<double> flush_interval = std::chrono::seconds(2);
};

// A history that does not fit the run resuming it (missing, other columns, fewer rows): the
// checkpoint or the scenario's --set options are not the first run's.
struct HistoryResumeError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class HistoryWriter {
 public:
  // Creates (or truncates) `path` and writes the header. Throws std::invalid_argument on
  // an empty column list, a duplicate name or a name with a comma, quote or line break;
  // std::runtime_error if the file cannot be created.
  HistoryWriter(std::filesystem::path path, std::vector<HistoryColumn> columns,
                HistoryOptions options = {});
  // Resuming a run from a checkpoint: `path` must exist with the same header;
  // its first `keep_rows` rows are kept and any later ones (written after the checkpoint,
  // before the run was stopped or killed) are dropped, atomically; appends follow them.
  // Throws HistoryResumeError naming the path if the file is missing, has another header
  // (the first column that differs) or fewer than `keep_rows` complete rows.
  struct Resume {
    std::size_t keep_rows = 0;
  };
  HistoryWriter(std::filesystem::path path, std::vector<HistoryColumn> columns, Resume resume,
                HistoryOptions options = {});
  HistoryWriter(const HistoryWriter&) = delete;
  HistoryWriter& operator=(const HistoryWriter&) = delete;
  // Closes; an error here is logged, not thrown (call close() to see it).
  ~HistoryWriter();

  // Appends one row, one value per column in declaration order. Throws
  // std::invalid_argument on a wrong count, std::runtime_error if a due flush fails.
  void append(std::span<const double> row);
  void append(std::initializer_list<double> row) { append(std::span(row.begin(), row.size())); }

  // Writes the buffered rows and fsyncs. Throws std::runtime_error naming the path.
  void flush();
  // flush() then close the file; later appends throw std::logic_error. Idempotent.
  void close();

  const std::filesystem::path& path() const { return path_; }
  const std::vector<HistoryColumn>& columns() const { return columns_; }
  std::size_t rows_written() const { return rows_; }  // appended so far (flushed or not)
  std::string header() const;  // without the line break

 private:
  std::filesystem::path path_;
  std::vector<HistoryColumn> columns_;
  HistoryOptions options_;
  std::string buffer_;  // complete lines not yet written
  int fd_ = -1;
  std::size_t rows_ = 0;
  std::chrono::steady_clock::time_point last_flush_;
};

}  // namespace dsdem::io
