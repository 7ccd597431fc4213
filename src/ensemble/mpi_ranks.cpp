#include "ensemble/mpi_ranks.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "io/atomic_file.hpp"

#ifdef DSDEM_HAVE_MPI
#include <mpi.h>
#endif

namespace dsdem::ensemble {

namespace fs = std::filesystem;

namespace {

int env_int(const char* name, int fallback) {
  const char* v = std::getenv(name);
  if (!v || !*v) return fallback;
  try {
    return std::stoi(v);
  } catch (...) {
    return fallback;
  }
}

}  // namespace

Ranks start_ranks() {
  Ranks r;
  const int world = env_int("OMPI_COMM_WORLD_SIZE", 0);
  if (world <= 0) return r;
#ifdef DSDEM_HAVE_MPI
  int initialised = 0;
  MPI_Initialized(&initialised);
  if (!initialised) MPI_Init(nullptr, nullptr);
  MPI_Comm_rank(MPI_COMM_WORLD, &r.rank);
  MPI_Comm_size(MPI_COMM_WORLD, &r.size);
  r.local_size = std::max(1, env_int("OMPI_COMM_WORLD_LOCAL_SIZE", 1));
  r.mpi = true;
  return r;
#else
  throw std::runtime_error("started by mpirun, but this dsdem was built without MPI (install libopenmpi-dev and rebuild)");
#endif
}

void finish_ranks(const Ranks& r) {
#ifdef DSDEM_HAVE_MPI
  if (r.mpi) MPI_Finalize();
#else
  (void)r;
#endif
}

void barrier(const Ranks& r) {
#ifdef DSDEM_HAVE_MPI
  if (r.mpi) MPI_Barrier(MPI_COMM_WORLD);
#else
  (void)r;
#endif
}

std::vector<std::size_t> members_of_rank(std::size_t members, const Ranks& r) {
  std::vector<std::size_t> out;
  for (std::size_t i = static_cast<std::size_t>(r.rank); i < members; i += static_cast<std::size_t>(r.size)) out.push_back(i);
  return out;
}

int max_over_ranks(const Ranks& r, int v) {
#ifdef DSDEM_HAVE_MPI
  if (!r.mpi) return v;
  int out = v;
  MPI_Allreduce(&v, &out, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  return out;
#else
  (void)r;
  return v;
#endif
}

void abort_ranks(const Ranks& r, int code) {
#ifdef DSDEM_HAVE_MPI
  if (r.mpi) MPI_Abort(MPI_COMM_WORLD, code);
#else
  (void)r;
  (void)code;
#endif
}

#ifdef DSDEM_HAVE_MPI
namespace {

constexpr int kTag = 36;

void send_string(const std::string& s) {
  const std::uint64_t n = s.size();
  MPI_Send(&n, 1, MPI_UINT64_T, 0, kTag, MPI_COMM_WORLD);
  // In pieces below 2^31 bytes (MPI counts are int).
  for (std::uint64_t off = 0; off < n; off += 1u << 30) {
    const int len = static_cast<int>(std::min<std::uint64_t>(n - off, 1u << 30));
    MPI_Send(s.data() + off, len, MPI_CHAR, 0, kTag, MPI_COMM_WORLD);
  }
}

std::string recv_string(int from) {
  std::uint64_t n = 0;
  MPI_Recv(&n, 1, MPI_UINT64_T, from, kTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  std::string s(n, '\0');
  for (std::uint64_t off = 0; off < n; off += 1u << 30) {
    const int len = static_cast<int>(std::min<std::uint64_t>(n - off, 1u << 30));
    MPI_Recv(s.data() + off, len, MPI_CHAR, from, kTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  }
  return s;
}

}  // namespace
#endif

void gather_member_files(const Ranks& r, const std::vector<fs::path>& member_dirs, const std::vector<std::string>& files,
                         const std::string& last_file) {
#ifdef DSDEM_HAVE_MPI
  if (!r.mpi || r.size == 1) return;
  std::vector<std::string> order = files;
  order.push_back(last_file);
  if (r.rank != 0) {
    // (path, contents) pairs, then an empty path to end.
    for (const auto& d : member_dirs)
      for (const auto& f : order) {
        const fs::path p = d / f;
        std::ifstream in(p, std::ios::binary);
        if (!in) continue;
        std::stringstream buf;
        buf << in.rdbuf();
        send_string(p.string());
        send_string(buf.str());
      }
    send_string("");
  } else {
    for (int from = 1; from < r.size; ++from) {
      for (;;) {
        const std::string path = recv_string(from);
        if (path.empty()) break;
        const std::string data = recv_string(from);
        const fs::path p(path);
        // A marker here already: a shared file system, the rank wrote them all here itself.
        if (fs::exists(p.parent_path() / last_file)) continue;
        fs::create_directories(p.parent_path());
        io::write_file_atomically(p, data);
      }
    }
  }
#else
  (void)r;
  (void)member_dirs;
  (void)files;
  (void)last_file;
#endif
}

}  // namespace dsdem::ensemble
