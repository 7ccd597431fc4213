#include "io/history_writer.hpp"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cfloat>
#include <fstream>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <thread>

#include "io/io_test_util.hpp"

namespace dsdem::io {
namespace {

using test::bits;
using test::read_text;
using test::ScratchDir;
using test::split;

const std::vector<HistoryColumn> kColumns = {{"time", "s"},
                                             {"kinetic_energy", "J_per_m"},
                                             {"gauge1_displacement_x", "m"},
                                             {"damage", ""}};

HistoryOptions never_flush() { return {.flush_interval = std::chrono::hours(1)}; }

TEST(HistoryWriter, HeaderNamesCarryUnitsAndExistsAtOnce) {
  ScratchDir dir;
  HistoryWriter h(dir / "energy.csv", kColumns, never_flush());
  EXPECT_EQ(h.header(), "time_s,kinetic_energy_J_per_m,gauge1_displacement_x_m,damage");
  EXPECT_EQ(read_text(dir / "energy.csv"), h.header() + "\n");
}

TEST(HistoryWriter, RowsRoundTripBitwise) {
  ScratchDir dir;
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<std::vector<double>> rows = {
      {0.0, 0.1, 1.0 / 3.0, -0.0},
      {1e-300, 5e-324, DBL_MAX, -DBL_MIN},
      {std::numbers::pi, -2.5e-17, 123456789.123456789, 1.0 + DBL_EPSILON},
      {std::nan(""), inf, -inf, 1e22},
  };
  {
    HistoryWriter h(dir / "h.csv", kColumns, never_flush());
    for (const auto& r : rows) h.append(r);
    EXPECT_EQ(h.rows_written(), rows.size());
  }
  const auto lines = split(read_text(dir / "h.csv"), '\n');
  ASSERT_EQ(lines.size(), rows.size() + 1);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto cells = split(lines[i + 1], ',');
    ASSERT_EQ(cells.size(), kColumns.size()) << lines[i + 1];
    for (std::size_t c = 0; c < cells.size(); ++c) {
      const double read = std::strtod(cells[c].c_str(), nullptr);
      if (std::isnan(rows[i][c]))
        EXPECT_TRUE(std::isnan(read)) << cells[c];
      else
        EXPECT_EQ(bits(read), bits(rows[i][c])) << "row " << i << " column " << c << ": " << cells[c];
    }
  }
}

TEST(HistoryWriter, RowsOnDiskAfterFlushIntervalWithoutClosing) {
  ScratchDir dir;
  HistoryWriter h(dir / "gauges.csv", kColumns, {.flush_interval = std::chrono::milliseconds(50)});
  h.append({0.0, 1.0, 2.0, 3.0});
  // Within the interval the row is still buffered: only the header is on disk.
  EXPECT_EQ(split(read_text(dir / "gauges.csv"), '\n').size(), 1u);
  std::this_thread::sleep_for(std::chrono::milliseconds(80));
  h.append({0.5, 1.5, 2.5, 3.5});  // the interval has passed: both rows go to disk
  const auto lines = split(read_text(dir / "gauges.csv"), '\n');
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[1], "0,1,2,3");
  EXPECT_EQ(lines[2], "0.5,1.5,2.5,3.5");
}

TEST(HistoryWriter, ExplicitFlushAndCloseWriteEverything) {
  ScratchDir dir;
  HistoryWriter h(dir / "h.csv", kColumns, never_flush());
  h.append({1, 2, 3, 4});
  h.flush();
  EXPECT_EQ(split(read_text(dir / "h.csv"), '\n').size(), 2u);
  h.append({5, 6, 7, 8});
  h.close();
  EXPECT_EQ(split(read_text(dir / "h.csv"), '\n').size(), 3u);
  EXPECT_THROW(h.append({1, 2, 3, 4}), std::logic_error);
  h.close();  // idempotent
}

// A run killed with SIGKILL keeps every row flushed before the kill, and no partial line.
TEST(HistoryWriter, KilledRunKeepsFlushedHistory) {
  ScratchDir dir;
  const auto path = dir / "h.csv";
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    HistoryWriter h(path, kColumns, {.flush_interval = std::chrono::seconds(0)});
    for (int i = 0; i < 100; ++i) h.append({i * 0.01, 1.0 * i, 2.0 * i, 3.0 * i});
    ::kill(::getpid(), SIGKILL);  // no destructor, no close
    std::_Exit(1);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFSIGNALED(status));
  const std::string text = read_text(path);
  EXPECT_EQ(text.back(), '\n');
  EXPECT_EQ(split(text, '\n').size(), 101u);
}

TEST(HistoryWriter, RejectsWrongRowSize) {
  ScratchDir dir;
  HistoryWriter h(dir / "h.csv", kColumns);
  EXPECT_THROW(h.append({1.0, 2.0}), std::invalid_argument);
}

TEST(HistoryWriter, RejectsBadColumns) {
  ScratchDir dir;
  EXPECT_THROW(HistoryWriter(dir / "a.csv", {}), std::invalid_argument);
  EXPECT_THROW(HistoryWriter(dir / "b.csv", {{"time", "s"}, {"time", "s"}}), std::invalid_argument);
  EXPECT_THROW(HistoryWriter(dir / "c.csv", {{"a,b", "s"}}), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(dir / "a.csv"));
}

TEST(HistoryWriter, UnwritableDirectoryThrowsWithPath) {
  ScratchDir dir;
  const auto path = dir / "missing" / "h.csv";
  try {
    HistoryWriter h(path, kColumns);
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_CONTAINS(e.what(), path.string());
  }
}

TEST(HistoryWriter, NumpyReadsColumnsByName) {
  if (!test::python_has("numpy")) GTEST_SKIP() << "no numpy in the system Python";
  ScratchDir dir;
  {
    HistoryWriter h(dir / "h.csv", kColumns);
    h.append({0.0, 0.1, 0.2, 0.3});
    h.append({1.0, 1.1, 1.2, 1.3});
  }
  const std::string cmd = std::string(test::kSystemPython) +
                          " -c 'import numpy, sys; d = numpy.genfromtxt(sys.argv[1], "
                          "delimiter=\",\", names=True); "
                          "assert d[\"kinetic_energy_J_per_m\"].tolist() == [0.1, 1.1], d' " +
                          (dir / "h.csv").string();
  EXPECT_EQ(std::system(cmd.c_str()), 0);
}


TEST(HistoryWriter, ResumeKeepsRowsUpToTheCheckpointAndAppends) {
  ScratchDir dir;
  {
    HistoryWriter h(dir / "h.csv", kColumns, never_flush());
    for (int i = 0; i < 5; ++i) h.append({0.1 * i, 1.0 * i, 2.0 * i, 0.0});
    h.close();
  }
  // A half-written last line (as if killed mid-write) must not count either.
  { std::ofstream(dir / "h.csv", std::ios::app) << "0.5,5"; }
  {
    HistoryWriter h(dir / "h.csv", kColumns, HistoryWriter::Resume{3}, never_flush());
    EXPECT_EQ(h.rows_written(), 3u);
    EXPECT_EQ(split(read_text(dir / "h.csv"), '\n').size(), 1u + 3u);  // dropped at once
    h.append({0.3, 30.0, 60.0, 0.5});
    h.close();
  }
  const auto lines = split(read_text(dir / "h.csv"), '\n');
  ASSERT_EQ(lines.size(), 5u);
  EXPECT_EQ(lines[3], "0.2,2,4,0");
  EXPECT_EQ(lines[4], "0.3,30,60,0.5");
}

TEST(HistoryWriter, ResumeRefusesAnotherHeaderOrTooFewRows) {
  ScratchDir dir;
  {
    HistoryWriter h(dir / "h.csv", kColumns, never_flush());
    h.append({0.0, 1.0, 2.0, 0.0});
  }
  std::vector<HistoryColumn> other = kColumns;
  other[1].quantity = "strain_energy";
  EXPECT_THROW(HistoryWriter(dir / "h.csv", other, HistoryWriter::Resume{1}), std::runtime_error);
  EXPECT_THROW(HistoryWriter(dir / "h.csv", kColumns, HistoryWriter::Resume{2}), std::runtime_error);
  EXPECT_THROW(HistoryWriter(dir / "missing.csv", kColumns, HistoryWriter::Resume{0}), std::runtime_error);
  // The refused resumes left the file as it was.
  EXPECT_EQ(split(read_text(dir / "h.csv"), '\n').size(), 2u);
}

}  // namespace
}  // namespace dsdem::io
