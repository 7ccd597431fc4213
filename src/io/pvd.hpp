#pragma once
// ParaView collection index (.pvd) of one time series of files (docs/user-guide.md): open
// OUT/<name>.pvd in ParaView and scrub through time.
//
// The index is rewritten atomically after every frame, so it is valid at any moment:
// a run that is killed, or watched live in ParaView, shows every frame written so far.
// File names are stored relative to the directory of the .pvd, with '/' separators, so
// an output folder can be moved or copied to another machine as a whole.
//
// Typical use in the output phase:
//   PvdSeries fields(out / "fields.pvd");            // frames go to out/fields/
//   auto file = fields.frame_path(fields.size());    // out/fields/fields_000000.vtu
//   write_triangles_vtu(file, ...);
//   fields.add(time_s, file);                        // index rewritten atomically
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace dsdem::io {

class PvdSeries {
 public:
  struct Entry {
    double time_s;     // simulated time of the frame, s
    std::string file;  // relative to the .pvd's directory, '/'-separated
  };

  // Starts an empty series (an existing index is overwritten at the first add()).
  // Creates the frames directory frame_directory() if absent. Throws std::runtime_error
  // if it cannot be created or written into.
  explicit PvdSeries(std::filesystem::path pvd_path);

  // Resuming a run from a checkpoint: loads an existing index (as written by this class)
  // and keeps the frames with time <= up_to_time_s, dropping the ones the resumed run
  // will write again. A missing index gives an empty series. Throws std::runtime_error
  // on an unreadable or malformed index.
  // `max_frames` also caps the frames kept (the count at the checkpoint: a frame written
  // at the checkpoint's time after it, e.g. the last state of a stopped run, is dropped).
  static PvdSeries resume(std::filesystem::path pvd_path, double up_to_time_s,
                          std::size_t max_frames = static_cast<std::size_t>(-1));

  // Appends a frame and rewrites the index. `data_file` is a path to the file already
  // written (absolute, or relative to the current directory, like any path); it is
  // stored relative to the .pvd's directory. Times must not decrease (a ParaView series
  // is ordered): throws std::invalid_argument otherwise.
  void add(double time_s, const std::filesystem::path& data_file);

  // <dir of pvd>/<stem>/<stem>_<frame, 6 digits><extension>, e.g. out/fields/fields_000012.vtu.
  std::filesystem::path frame_path(std::size_t frame, std::string_view extension = ".vtu") const;
  std::filesystem::path frame_directory() const;

  const std::filesystem::path& path() const { return path_; }
  const std::vector<Entry>& entries() const { return entries_; }
  std::size_t size() const { return entries_.size(); }

 private:
  PvdSeries(std::filesystem::path pvd_path, std::vector<Entry> entries);
  void rewrite() const;

  std::filesystem::path path_;
  std::vector<Entry> entries_;
};

// The XML text of a PVD index listing `entries` (times at round-trip precision).
std::string pvd_document(const std::vector<PvdSeries::Entry>& entries);

// Escapes & < > " ' for an XML attribute value.
std::string xml_escape(std::string_view text);

}  // namespace dsdem::io
