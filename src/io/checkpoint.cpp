#include "io/checkpoint.hpp"

#include <H5Cpp.h>
#include <fmt/format.h>

#include <stdexcept>
#include <unistd.h>

namespace dsdem::io {

namespace {
constexpr const char* kMagic = "dsdem_checkpoint_version";
// 2: joint end-point states without the recomputable tractions, break records as a
// list (memory per element). A file of another version is refused, naming both versions.
constexpr std::int64_t kVersion = 2;

// HDF5 does not create intermediate groups by itself: "nodes/u" needs group "nodes".
void ensure_groups(H5::H5File& file, const std::string& name) {
  for (std::size_t pos = name.find('/'); pos != std::string::npos; pos = name.find('/', pos + 1)) {
    const std::string group = name.substr(0, pos);
    if (!file.nameExists(group)) file.createGroup(group);
  }
}

template <class T>
void write_array(H5::H5File& file, const std::string& name, std::span<const T> values, const H5::PredType& type,
                 const std::filesystem::path& target) {
  try {
    ensure_groups(file, name);
    const hsize_t n = values.size();
    H5::DataSpace space(1, &n);
    H5::DataSet ds = file.createDataSet(name, type, space);
    if (n > 0) ds.write(values.data(), type);
  } catch (const H5::Exception& e) {
    throw std::runtime_error(fmt::format("cannot write '{}' to checkpoint '{}': {}", name, target.string(), e.getDetailMsg()));
  }
}
}  // namespace

struct CheckpointWriter::Impl {
  std::filesystem::path target, temp;
  H5::H5File file;
  bool committed = false;
};

CheckpointWriter::CheckpointWriter(std::filesystem::path path) : impl_(std::make_unique<Impl>()) {
  impl_->target = path;
  impl_->temp = path.parent_path() / fmt::format(".{}.tmp-{}", path.filename().string(), ::getpid());
  try {
    H5::Exception::dontPrint();
    impl_->file = H5::H5File(impl_->temp.string(), H5F_ACC_TRUNC);
  } catch (const H5::Exception& e) {
    throw std::runtime_error(fmt::format("cannot create checkpoint '{}': {}", path.string(), e.getDetailMsg()));
  }
  put_int(kMagic, kVersion);
}

CheckpointWriter::~CheckpointWriter() {
  if (impl_ && !impl_->committed) {
    try {
      impl_->file.close();
    } catch (...) {
    }
    std::error_code ec;
    std::filesystem::remove(impl_->temp, ec);
  }
}

void CheckpointWriter::put(const std::string& name, std::span<const double> values) {
  write_array(impl_->file, name, values, H5::PredType::NATIVE_DOUBLE, impl_->target);
}

void CheckpointWriter::put(const std::string& name, std::span<const std::int64_t> values) {
  write_array(impl_->file, name, values, H5::PredType::NATIVE_INT64, impl_->target);
}

void CheckpointWriter::commit() {
  try {
    impl_->file.flush(H5F_SCOPE_GLOBAL);
    impl_->file.close();
  } catch (const H5::Exception& e) {
    throw std::runtime_error(fmt::format("cannot write checkpoint '{}': {}", impl_->target.string(), e.getDetailMsg()));
  }
  std::error_code ec;
  std::filesystem::rename(impl_->temp, impl_->target, ec);
  if (ec) throw std::runtime_error(fmt::format("cannot write checkpoint '{}': {}", impl_->target.string(), ec.message()));
  impl_->committed = true;
}

struct CheckpointReader::Impl {
  std::string path;
  H5::H5File file;
};

CheckpointReader::CheckpointReader(const std::filesystem::path& path) : impl_(std::make_unique<Impl>()) {
  impl_->path = path.string();
  try {
    H5::Exception::dontPrint();
    impl_->file = H5::H5File(path.string(), H5F_ACC_RDONLY);
  } catch (const H5::Exception& e) {
    throw std::runtime_error(fmt::format("{}: not a readable checkpoint (HDF5: {})", path.string(), e.getDetailMsg()));
  }
  if (!has(kMagic)) throw std::runtime_error(fmt::format("{}: not a dsdem checkpoint (no '{}')", path.string(), kMagic));
  const std::int64_t version = integer(kMagic);
  if (version != kVersion)
    throw std::runtime_error(fmt::format(
        "{}: dsdem checkpoint version {}, this build reads version {} only (the saved state's layout differs): "
        "restart the run from its beginning, or continue it with the dsdem build that wrote the checkpoint",
        path.string(), version, kVersion));
}

CheckpointReader::~CheckpointReader() = default;

bool CheckpointReader::has(const std::string& name) const {
  try {
    // nameExists fails on a missing intermediate group: check each level.
    for (std::size_t pos = name.find('/'); pos != std::string::npos; pos = name.find('/', pos + 1))
      if (!impl_->file.nameExists(name.substr(0, pos))) return false;
    return impl_->file.nameExists(name);
  } catch (const H5::Exception&) {
    return false;
  }
}

std::vector<double> CheckpointReader::doubles(const std::string& name) const {
  if (!has(name)) throw std::runtime_error(fmt::format("{}: checkpoint has no '{}'", impl_->path, name));
  H5::DataSet ds = impl_->file.openDataSet(name);
  hsize_t n = 0;
  ds.getSpace().getSimpleExtentDims(&n);
  std::vector<double> v(n);
  if (n > 0) ds.read(v.data(), H5::PredType::NATIVE_DOUBLE);
  return v;
}

std::vector<std::int64_t> CheckpointReader::integers(const std::string& name) const {
  if (!has(name)) throw std::runtime_error(fmt::format("{}: checkpoint has no '{}'", impl_->path, name));
  H5::DataSet ds = impl_->file.openDataSet(name);
  hsize_t n = 0;
  ds.getSpace().getSimpleExtentDims(&n);
  std::vector<std::int64_t> v(n);
  if (n > 0) ds.read(v.data(), H5::PredType::NATIVE_INT64);
  return v;
}

double CheckpointReader::scalar(const std::string& name) const {
  const auto v = doubles(name);
  if (v.size() != 1) throw std::runtime_error(fmt::format("{}: '{}' is not a scalar", impl_->path, name));
  return v[0];
}

std::int64_t CheckpointReader::integer(const std::string& name) const {
  const auto v = integers(name);
  if (v.size() != 1) throw std::runtime_error(fmt::format("{}: '{}' is not a scalar", impl_->path, name));
  return v[0];
}

}  // namespace dsdem::io
