#include "io/atomic_file.hpp"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <stdexcept>

#include "io/io_test_util.hpp"

namespace dsdem::io {
namespace {

using test::list_dir;
using test::read_text;
using test::ScratchDir;

// Runs `f`, expects a std::runtime_error, returns its message.
template <class F>
std::string runtime_error_message(F&& f) {
  try {
    f();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no std::runtime_error thrown";
  return {};
}

TEST(AtomicFile, WritesAndReplacesContentsLeavingNoTemporary) {
  ScratchDir dir;
  const auto target = dir / "summary.json";
  write_file_atomically(target, "first");
  EXPECT_EQ(read_text(target), "first");
  write_file_atomically(target, "second, longer contents");
  EXPECT_EQ(read_text(target), "second, longer contents");
  EXPECT_EQ(list_dir(dir.path()), std::vector<std::string>{"summary.json"});
}

TEST(AtomicFile, ChunkedWritesAppearOnlyAtCommit) {
  ScratchDir dir;
  const auto target = dir / "a.txt";
  AtomicFile file(target);
  file.write("abc");
  file.write("def");
  EXPECT_FALSE(std::filesystem::exists(target));
  EXPECT_TRUE(std::filesystem::exists(file.temporary()));
  file.commit();
  EXPECT_EQ(read_text(target), "abcdef");
  EXPECT_FALSE(std::filesystem::exists(file.temporary()));
}

TEST(AtomicFile, AbandonedWriteKeepsOldTargetAndRemovesTemporary) {
  ScratchDir dir;
  const auto target = dir / "frame.vtu";
  write_file_atomically(target, "old");
  {
    AtomicFile file(target);
    file.write("half of the new fi");
    // No commit: as if an exception unwound the writer.
  }
  EXPECT_EQ(read_text(target), "old");
  EXPECT_EQ(list_dir(dir.path()), std::vector<std::string>{"frame.vtu"});
}

TEST(AtomicFile, MissingDirectoryThrowsWithPathAndOsError) {
  ScratchDir dir;
  const auto target = dir / "no_such_dir" / "out.vtu";
  const std::string msg = runtime_error_message([&] { write_file_atomically(target, "x"); });
  EXPECT_CONTAINS(msg, (target.string()));
  EXPECT_CONTAINS(msg, ("No such file or directory"));
  EXPECT_FALSE(std::filesystem::exists(target));
  EXPECT_TRUE(list_dir(dir.path()).empty());
}

TEST(AtomicFile, ParentThatIsAFileThrowsWithPathAndOsError) {
  ScratchDir dir;
  write_file_atomically(dir / "plain_file", "x");
  const auto target = dir / "plain_file" / "out.vtu";
  const std::string msg = runtime_error_message([&] { write_file_atomically(target, "x"); });
  EXPECT_CONTAINS(msg, (target.string()));
  EXPECT_CONTAINS(msg, ("Not a directory"));
  EXPECT_EQ(list_dir(dir.path()), std::vector<std::string>{"plain_file"});
}

TEST(AtomicFile, ReadOnlyDirectoryThrowsAndLeavesNoFile) {
  if (::geteuid() == 0) GTEST_SKIP() << "root writes into read-only directories";
  ScratchDir dir;
  const auto locked = dir / "locked";
  std::filesystem::create_directory(locked);
  std::filesystem::permissions(locked, std::filesystem::perms::owner_read |
                                           std::filesystem::perms::owner_exec);
  const auto target = locked / "out.vtu";
  const std::string msg = runtime_error_message([&] { write_file_atomically(target, "x"); });
  EXPECT_CONTAINS(msg, (target.string()));
  EXPECT_CONTAINS(msg, ("Permission denied"));
  std::filesystem::permissions(locked, std::filesystem::perms::owner_all);
  EXPECT_TRUE(list_dir(locked).empty());
}

TEST(AtomicFile, RenameOntoADirectoryThrowsAndRemovesTemporary) {
  ScratchDir dir;
  std::filesystem::create_directory(dir / "taken");
  std::filesystem::create_directory(dir / "taken" / "child");  // a non-empty directory
  const std::string msg =
      runtime_error_message([&] { write_file_atomically(dir / "taken", "x"); });
  EXPECT_CONTAINS(msg, ((dir / "taken").string()));
  EXPECT_EQ(list_dir(dir.path()), std::vector<std::string>{"taken"});
}

// The child's own exit: its scratch folder (made by the child's ScratchDir, whose
// destructor _Exit skips) removed first.
[[noreturn]] void leave(const std::filesystem::path& dir, int code) {
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
  std::_Exit(code);
}

// A write that fails half-way (the disk fills up) must throw, keep the previous target
// and remove the temporary. The file size limit stands in for a full disk (EFBIG on the
// write, like ENOSPC); it is set in a child process so that it does not leak.
void write_past_file_size_limit(const std::filesystem::path& dir) {
  const auto target = dir / "big.vtu";
  write_file_atomically(target, "old");
  std::signal(SIGXFSZ, SIG_IGN);  // get EFBIG from write() instead of a signal
  rlimit limit{4096, 4096};
  if (::setrlimit(RLIMIT_FSIZE, &limit) != 0) leave(dir, 2);
  try {
    write_file_atomically(target, std::string(1 << 20, 'x'));
    std::fputs("no exception\n", stderr);
    leave(dir, 3);
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    if (msg.find(target.string()) == std::string::npos ||
        msg.find("File too large") == std::string::npos) {
      std::fprintf(stderr, "bad message: %s\n", msg.c_str());
      leave(dir, 4);
    }
  }
  if (read_text(target) != "old") leave(dir, 5);
  if (list_dir(dir) != std::vector<std::string>{"big.vtu"}) leave(dir, 6);
  leave(dir, 0);
}

TEST(AtomicFileDeathTest, WriteFailureMidwayKeepsOldTargetAndRemovesTemporary) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  ScratchDir dir;
  EXPECT_EXIT(write_past_file_size_limit(dir.path()), ::testing::ExitedWithCode(0), "");
}

TEST(EnsureWritableDirectory, CreatesMissingParents) {
  ScratchDir dir;
  const auto out = dir / "a" / "b" / "out";
  ensure_writable_directory(out);
  EXPECT_TRUE(std::filesystem::is_directory(out));
  EXPECT_TRUE(list_dir(out).empty());  // the probe file is gone
  ensure_writable_directory(out);      // existing directory: fine
}

TEST(EnsureWritableDirectory, ThrowsOnPathUnderAFile) {
  ScratchDir dir;
  write_file_atomically(dir / "file", "x");
  const auto out = dir / "file" / "out";
  const std::string msg = runtime_error_message([&] { ensure_writable_directory(out); });
  EXPECT_CONTAINS(msg, (out.string()));
  EXPECT_CONTAINS(msg, ("Not a directory"));
}

TEST(EnsureWritableDirectory, ThrowsOnAFile) {
  ScratchDir dir;
  write_file_atomically(dir / "file", "x");
  const std::string msg =
      runtime_error_message([&] { ensure_writable_directory(dir / "file"); });
  EXPECT_CONTAINS(msg, ((dir / "file").string()));
}

TEST(NameWithUnit, AppendsUnitUnlessDimensionless) {
  EXPECT_EQ(name_with_unit("stress", "Pa"), "stress_Pa");
  EXPECT_EQ(name_with_unit("velocity", "m_per_s"), "velocity_m_per_s");
  EXPECT_EQ(name_with_unit("damage", ""), "damage");
}

}  // namespace
}  // namespace dsdem::io
