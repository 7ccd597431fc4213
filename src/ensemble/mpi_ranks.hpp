#pragma once
// MPI for ensembles only (docs/theory.md §13): members dealt to ranks, their files gathered on
// rank 0. MPI is initialised only when the process was started by mpirun (Open MPI sets
// OMPI_COMM_WORLD_SIZE), so a plain `dsdem` never touches it; built without Open MPI, every
// call is the one-rank case.
#include <filesystem>
#include <string>
#include <vector>

namespace dsdem::ensemble {

struct Ranks {
  int rank = 0, size = 1;
  int local_size = 1;  // ranks on this machine
  bool mpi = false;    // MPI_Init was called (call finish_ranks)
};

// Initialises MPI when launched under mpirun; throws when launched so but built without MPI.
Ranks start_ranks();
void finish_ranks(const Ranks& r);
void barrier(const Ranks& r);
// The members of rank r: every size-th from r.
std::vector<std::size_t> members_of_rank(std::size_t members, const Ranks& r);
// Sends the listed files of this rank's member folders to rank 0, which writes those it lacks
// (ranks on other machines; on a shared file system they are already there). The marker
// `last_file` goes last, so rank 0 never sees a marker before the files it vouches for.
void gather_member_files(const Ranks& r, const std::vector<std::filesystem::path>& member_dirs,
                         const std::vector<std::string>& files, const std::string& last_file);
// Largest of `v` over the ranks, on every rank.
int max_over_ranks(const Ranks& r, int v);
// Ends every rank of the job with exit code `code` (MPI_Abort): what a rank does on an
// error the others cannot learn of, which would otherwise leave them waiting for it for
// ever. Members already complete stay on disk. Returns only without MPI.
void abort_ranks(const Ranks& r, int code);

}  // namespace dsdem::ensemble
