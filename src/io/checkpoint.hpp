#pragma once
// Checkpoints (HDF5): named arrays of doubles and integers, written to a temporary file
// and renamed, so a checkpoint on disk is always complete (docs/user-guide.md).
#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace dsdem::io {

class CheckpointWriter {
 public:
  explicit CheckpointWriter(std::filesystem::path path);
  ~CheckpointWriter();
  void put(const std::string& name, std::span<const double> values);
  void put(const std::string& name, std::span<const std::int64_t> values);
  void put(const std::string& name, double value) { put(name, std::span<const double>(&value, 1)); }
  void put_int(const std::string& name, std::int64_t value) { put(name, std::span<const std::int64_t>(&value, 1)); }
  // Flushes, closes and renames into place. Throws std::runtime_error naming the path.
  void commit();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

class CheckpointReader {
 public:
  // Throws std::runtime_error naming the path if it is not a dsdem checkpoint.
  explicit CheckpointReader(const std::filesystem::path& path);
  ~CheckpointReader();
  bool has(const std::string& name) const;
  std::vector<double> doubles(const std::string& name) const;
  std::vector<std::int64_t> integers(const std::string& name) const;
  double scalar(const std::string& name) const;
  std::int64_t integer(const std::string& name) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dsdem::io
