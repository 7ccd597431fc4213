#include "io/pvd.hpp"

#include <vtkNew.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLDataParser.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

#include <fmt/format.h>

#include "io/atomic_file.hpp"

namespace dsdem::io {
namespace fs = std::filesystem;

namespace {

fs::path directory_of(const fs::path& file) {
  return file.has_parent_path() ? file.parent_path() : fs::path(".");
}

// Absolute, normalised, without a trailing separator, so that lexically_relative
// compares path elements one to one.
fs::path normalised_absolute(const fs::path& p) {
  fs::path n = fs::absolute(p).lexically_normal();
  if (!n.has_filename() && n.has_parent_path() && n != n.root_path()) n = n.parent_path();
  return n;
}

std::string relative_name(const fs::path& data_file, const fs::path& pvd_dir) {
  const fs::path rel = normalised_absolute(data_file).lexically_relative(normalised_absolute(pvd_dir));
  if (rel.empty())
    throw std::invalid_argument(fmt::format("PVD: cannot express '{}' relative to '{}'",
                                            data_file.string(), pvd_dir.string()));
  return rel.generic_string();
}

const char* required_attribute(vtkXMLDataElement* e, const char* name, const fs::path& path) {
  const char* value = e->GetAttribute(name);
  if (value == nullptr)
    throw std::runtime_error(
        fmt::format("cannot read '{}': a DataSet has no '{}' attribute", path.string(), name));
  return value;
}

// Reads the (time, file) pairs of an existing index, in file order.
std::vector<PvdSeries::Entry> read_entries(const fs::path& path) {
  vtkNew<vtkXMLDataParser> parser;
  parser->SetFileName(path.c_str());
  if (parser->Parse() != 1 || parser->GetRootElement() == nullptr)
    throw std::runtime_error(fmt::format("cannot read '{}': not a valid XML file", path.string()));
  vtkXMLDataElement* root = parser->GetRootElement();
  const char* type = root->GetAttribute("type");
  vtkXMLDataElement* collection = root->FindNestedElementWithName("Collection");
  if (std::string_view(root->GetName()) != "VTKFile" || type == nullptr ||
      std::string_view(type) != "Collection" || collection == nullptr)
    throw std::runtime_error(
        fmt::format("cannot read '{}': not a VTK Collection (.pvd) file", path.string()));

  std::vector<PvdSeries::Entry> entries;
  for (int i = 0; i < collection->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* e = collection->GetNestedElement(i);
    if (std::string_view(e->GetName()) != "DataSet") continue;
    const char* time_text = required_attribute(e, "timestep", path);
    char* end = nullptr;
    errno = 0;
    const double t = std::strtod(time_text, &end);
    if (end == time_text || *end != '\0' || errno == ERANGE)
      throw std::runtime_error(
          fmt::format("cannot read '{}': bad timestep \"{}\"", path.string(), time_text));
    entries.push_back({t, required_attribute(e, "file", path)});
  }
  return entries;
}

}  // namespace

std::string xml_escape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string pvd_document(const std::vector<PvdSeries::Entry>& entries) {
  std::string xml =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      "  <!-- written by dsdem; timestep in s (simulated time); file relative to this index -->\n"
      "  <Collection>\n";
  for (const auto& e : entries)
    xml += fmt::format("    <DataSet timestep=\"{}\" group=\"\" part=\"0\" file=\"{}\"/>\n",
                       e.time_s, xml_escape(e.file));
  xml += "  </Collection>\n</VTKFile>\n";
  return xml;
}

PvdSeries::PvdSeries(fs::path pvd_path) : PvdSeries(std::move(pvd_path), {}) {}

PvdSeries::PvdSeries(fs::path pvd_path, std::vector<Entry> entries)
    : path_(std::move(pvd_path)), entries_(std::move(entries)) {
  ensure_writable_directory(frame_directory());
}

PvdSeries PvdSeries::resume(fs::path pvd_path, double up_to_time_s, std::size_t max_frames) {
  std::vector<Entry> kept;
  std::error_code ec;
  if (fs::exists(pvd_path, ec)) {
    for (Entry& e : read_entries(pvd_path))
      if (e.time_s <= up_to_time_s && kept.size() < max_frames) kept.push_back(std::move(e));
  }
  PvdSeries series(std::move(pvd_path), std::move(kept));
  series.rewrite();  // the dropped frames must disappear from the index now
  return series;
}

fs::path PvdSeries::frame_directory() const { return directory_of(path_) / path_.stem(); }

fs::path PvdSeries::frame_path(std::size_t frame, std::string_view extension) const {
  const std::string stem = path_.stem().string();
  return frame_directory() / fmt::format("{}_{:06d}{}", stem, frame, extension);
}

void PvdSeries::add(double time_s, const fs::path& data_file) {
  if (!std::isfinite(time_s))
    throw std::invalid_argument(fmt::format("PVD '{}': time {} is not finite", path_.string(), time_s));
  if (!entries_.empty() && time_s < entries_.back().time_s)
    throw std::invalid_argument(fmt::format("PVD '{}': time {} s before the previous frame's {} s",
                                            path_.string(), time_s, entries_.back().time_s));
  entries_.push_back({time_s, relative_name(data_file, directory_of(path_))});
  try {
    rewrite();
  } catch (...) {
    entries_.pop_back();  // keep the object consistent with the file on disk
    throw;
  }
}

void PvdSeries::rewrite() const { write_file_atomically(path_, pvd_document(entries_)); }

}  // namespace dsdem::io
