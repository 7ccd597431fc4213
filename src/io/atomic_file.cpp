#include "io/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>

namespace dsdem::io {
namespace fs = std::filesystem;

namespace {

// Unique per process and per call, so concurrent writers (threads, or two runs writing
// into the same directory) never share a temporary. Hidden (leading dot) so ParaView's
// file dialog and `ls` do not show the rare leftover of a killed process.
fs::path temporary_name_for(const fs::path& target) {
  static std::atomic<unsigned long> counter{0};
  const auto n = counter.fetch_add(1, std::memory_order_relaxed);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  return dir / fmt::format(".{}.tmp-{}-{}", target.filename().string(),
                           static_cast<long>(::getpid()), n);
}

// Loops over partial writes and EINTR; returns 0 or the errno of the failure.
int write_all(int fd, std::string_view bytes) {
  const char* p = bytes.data();
  std::size_t left = bytes.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  return 0;
}

// EINVAL means the file system cannot sync this kind of file: nothing to report.
int sync_fd(int fd) {
  if (::fsync(fd) == 0 || errno == EINVAL) return 0;
  return errno;
}

// Makes a rename durable. Best effort: the contents are already complete and correct
// whatever happens here, so a failure is not worth aborting a run for.
void sync_directory(const fs::path& dir) noexcept {
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  (void)::fsync(fd);
  (void)::close(fd);
}

}  // namespace

void throw_os_error(std::string_view action, const fs::path& path, int err) {
  throw std::runtime_error(fmt::format("{} '{}': {}", action, path.string(), std::strerror(err)));
}

AtomicFile::AtomicFile(fs::path target) : target_(std::move(target)) {
  if (target_.empty() || !target_.has_filename())
    throw std::runtime_error(fmt::format("cannot write '{}': not a file name", target_.string()));
  temp_ = temporary_name_for(target_);
  // 0666 minus the umask, like any ordinary output file (mkstemp would give 0600).
  fd_ = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd_ < 0) throw_os_error("cannot create a temporary file to write", target_, errno);
}

AtomicFile::~AtomicFile() {
  if (!committed_) discard();
}

void AtomicFile::discard() noexcept {
  if (fd_ >= 0) (void)::close(fd_);
  fd_ = -1;
  if (!temp_.empty()) (void)::unlink(temp_.c_str());
}

void AtomicFile::write(std::string_view bytes) {
  if (fd_ < 0) throw std::logic_error("AtomicFile::write after commit or failure");
  if (const int err = write_all(fd_, bytes); err != 0) {
    discard();
    throw_os_error("cannot write", target_, err);
  }
}

void AtomicFile::commit() {
  if (fd_ < 0) throw std::logic_error("AtomicFile::commit after commit or failure");
  // Sync before rename: otherwise a crash could leave the new name on empty data.
  if (const int err = sync_fd(fd_); err != 0) {
    discard();
    throw_os_error("cannot flush to disk", target_, err);
  }
  // close() reports deferred write errors (NFS, quota): check it too.
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) {
    const int err = errno;
    discard();
    throw_os_error("cannot close", target_, err);
  }
  if (::rename(temp_.c_str(), target_.c_str()) != 0) {
    const int err = errno;
    discard();
    throw_os_error("cannot rename the temporary file onto", target_, err);
  }
  committed_ = true;
  sync_directory(target_.parent_path());
}

void write_file_atomically(const fs::path& path, std::string_view contents) {
  AtomicFile file(path);
  file.write(contents);
  file.commit();
}

void ensure_writable_directory(const fs::path& dir) {
  const fs::path d = dir.empty() ? fs::path(".") : dir;
  std::error_code ec;
  if (!fs::exists(d, ec)) {
    fs::create_directories(d, ec);
    if (ec) throw_os_error("cannot create output directory", d, ec.value());
  }
  if (!fs::is_directory(d, ec)) throw_os_error("output path is not a directory", d, ENOTDIR);
  // Permission bits alone do not answer the question (root, ACLs, read-only mounts):
  // try it.
  const fs::path probe = d / fmt::format(".dsdem-write-probe-{}", static_cast<long>(::getpid()));
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) throw_os_error("cannot write into output directory", d, errno);
  int err = write_all(fd, "x");
  if (::close(fd) != 0 && err == 0) err = errno;
  (void)::unlink(probe.c_str());
  if (err != 0) throw_os_error("cannot write into output directory", d, err);
}

std::string name_with_unit(std::string_view quantity, std::string_view unit) {
  if (unit.empty()) return std::string(quantity);
  return fmt::format("{}_{}", quantity, unit);
}

}  // namespace dsdem::io
