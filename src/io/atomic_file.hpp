#pragma once
// Atomic file output shared by every writer in io/ (docs/user-guide.md: a killed or failed
// run must never leave a half-written VTU, PVD or JSON file behind).
//
// Contract: the target either keeps its previous contents (or stays absent) or holds
// the complete new contents. Bytes go to a hidden temporary file in the target's own
// directory (rename is only atomic within one file system), which is fsync'ed, closed
// and then renamed over the target. Every failure throws std::runtime_error whose
// message names the target path and the OS error (strerror), and removes the temporary.
//
// Not thread-safe per object; distinct objects may be used from distinct threads.
#include <filesystem>
#include <string>
#include <string_view>

namespace dsdem::io {

class AtomicFile {
 public:
  // Creates the temporary file next to `target`. Throws if the directory is missing or
  // not writable. Nothing is visible under `target` until commit().
  explicit AtomicFile(std::filesystem::path target);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  // Without commit() (e.g. an exception unwinding): the temporary is deleted and the
  // target is left untouched.
  ~AtomicFile();

  // Appends bytes to the temporary file (no user-space buffering: pass large chunks).
  void write(std::string_view bytes);
  // fsync, close, rename over the target, then fsync the directory (best effort) so the
  // rename itself survives a power cut. Call at most once.
  void commit();

  const std::filesystem::path& target() const { return target_; }
  const std::filesystem::path& temporary() const { return temp_; }

 private:
  void discard() noexcept;

  std::filesystem::path target_;
  std::filesystem::path temp_;
  int fd_ = -1;
  bool committed_ = false;
};

// The whole of `contents` to `path`, atomically (see AtomicFile).
void write_file_atomically(const std::filesystem::path& path, std::string_view contents);

// Makes sure output can go to `dir` before step 0 rather than failing hours into a run:
// creates it (and its parents) if absent, then creates and removes a probe file in it.
// Throws std::runtime_error naming the directory and the OS error.
void ensure_writable_directory(const std::filesystem::path& dir);

// Throws std::runtime_error("<action> '<path>': <strerror(err)>").
[[noreturn]] void throw_os_error(std::string_view action, const std::filesystem::path& path,
                                 int err);

// ---------------------------------------------------------------------------------
// Naming convention for every output quantity (VTU array names, CSV column headers,
// JSON keys that hold a dimensional number): `<quantity>_<unit>`.
//   - quantity: snake_case, e.g. "displacement", "von_mises_stress", "kinetic_energy".
//   - unit: SI symbol, ASCII only; "_per_" for a division and a trailing digit for a
//     power: "m", "s", "Pa", "N", "J", "m_per_s", "m_per_s2", "N_per_m", "J_per_m".
//     Two-dimensional extensive quantities are per unit thickness and say so
//     (a 2D contact force is "N_per_m", a 2D energy "J_per_m").
//   - dimensionless quantities (strain, damage, ratios) and identifiers or codes
//     (group_id, zone, state) have an empty unit and keep the bare quantity name.
// Examples: "stress_Pa", "velocity_m_per_s", "time_s", "strain", "group_id".
std::string name_with_unit(std::string_view quantity, std::string_view unit);

}  // namespace dsdem::io
