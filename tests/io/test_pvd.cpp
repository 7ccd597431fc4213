#include "io/pvd.hpp"

#include <gtest/gtest.h>
#include <vtkNew.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLDataParser.h>

#include <cstdlib>
#include <stdexcept>

#include "io/atomic_file.hpp"
#include "io/io_test_util.hpp"
#include "io/vtu_writer.hpp"

namespace dsdem::io {
namespace {

using test::bits;
using test::ScratchDir;

struct ParsedEntry {
  double time;
  std::string file;
};

// Parses the index as XML (expat, via VTK) and returns its DataSet entries.
std::vector<ParsedEntry> parse_pvd(const std::filesystem::path& path) {
  vtkNew<vtkXMLDataParser> parser;
  parser->SetFileName(path.c_str());
  EXPECT_EQ(parser->Parse(), 1) << "not valid XML: " << path;
  vtkXMLDataElement* root = parser->GetRootElement();
  if (root == nullptr) return {};
  EXPECT_STREQ(root->GetName(), "VTKFile");
  EXPECT_STREQ(root->GetAttribute("type"), "Collection");
  vtkXMLDataElement* collection = root->FindNestedElementWithName("Collection");
  EXPECT_NE(collection, nullptr);
  std::vector<ParsedEntry> out;
  for (int i = 0; collection && i < collection->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* e = collection->GetNestedElement(i);
    EXPECT_STREQ(e->GetName(), "DataSet");
    out.push_back({std::strtod(e->GetAttribute("timestep"), nullptr), e->GetAttribute("file")});
  }
  return out;
}

// Writes `n` small point frames at `times` into the series, as the output phase will.
void write_frames(PvdSeries& series, const std::vector<double>& times) {
  const std::vector<Vec2> pts = {Vec2(0, 0), Vec2(1, 1)};
  for (double t : times) {
    const auto file = series.frame_path(series.size());
    write_points_vtu(file, pts, {}, {.time_s = t});
    series.add(t, file);
    // The index is complete and valid after every frame.
    EXPECT_EQ(parse_pvd(series.path()).size(), series.size());
  }
}

TEST(PvdSeries, ThreeFramesListedWithTimesAndRelativeFiles) {
  ScratchDir dir;
  const auto out = dir / "out";
  PvdSeries series(out / "fields.pvd");
  EXPECT_TRUE(std::filesystem::is_directory(out / "fields"));
  const std::vector<double> times = {0.0, 0.1, 1.0 / 3.0};
  write_frames(series, times);

  const auto entries = parse_pvd(out / "fields.pvd");
  ASSERT_EQ(entries.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(bits(entries[k].time), bits(times[k])) << "timestep at round-trip precision";
    EXPECT_EQ(entries[k].file, "fields/fields_00000" + std::to_string(k) + ".vtu");
    EXPECT_TRUE(std::filesystem::exists(out / entries[k].file));
  }
  EXPECT_EQ(series.entries()[2].file, "fields/fields_000002.vtu");
  // Units are stated in the header.
  EXPECT_CONTAINS(test::read_text(out / "fields.pvd"), "timestep in s");
}

TEST(PvdSeries, RelativePathsFromAnyWorkingDirectory) {
  ScratchDir dir;
  // The pvd given by an absolute path, a data file elsewhere in the tree.
  PvdSeries series(dir / "out" / "cracks.pvd");
  ensure_writable_directory(dir / "elsewhere");
  write_file_atomically(dir / "elsewhere" / "c.vtu", "x");
  series.add(0.5, dir / "out" / ".." / "elsewhere" / "c.vtu");
  EXPECT_EQ(series.entries()[0].file, "../elsewhere/c.vtu");
}

TEST(PvdSeries, RejectsDecreasingOrNonFiniteTime) {
  ScratchDir dir;
  PvdSeries series(dir / "s.pvd");
  series.add(1.0, dir / "s" / "a.vtu");
  EXPECT_THROW(series.add(0.5, dir / "s" / "b.vtu"), std::invalid_argument);
  EXPECT_THROW(series.add(std::nan(""), dir / "s" / "b.vtu"), std::invalid_argument);
  EXPECT_EQ(parse_pvd(dir / "s.pvd").size(), 1u);
}

TEST(PvdSeries, ResumeKeepsFramesUpToTheCheckpointTime) {
  ScratchDir dir;
  {
    PvdSeries series(dir / "fields.pvd");
    write_frames(series, {0.0, 0.5, 1.0, 1.5});
  }
  PvdSeries resumed = PvdSeries::resume(dir / "fields.pvd", 1.0);
  ASSERT_EQ(resumed.size(), 3u);
  EXPECT_EQ(parse_pvd(dir / "fields.pvd").size(), 3u);  // rewritten at once
  write_frames(resumed, {1.25});
  const auto entries = parse_pvd(dir / "fields.pvd");
  ASSERT_EQ(entries.size(), 4u);
  EXPECT_EQ(entries[3].time, 1.25);
  EXPECT_EQ(entries[3].file, "fields/fields_000003.vtu");
}

TEST(PvdSeries, ResumeWithoutIndexStartsEmpty) {
  ScratchDir dir;
  EXPECT_EQ(PvdSeries::resume(dir / "none.pvd", 3.0).size(), 0u);
}

TEST(PvdSeries, ResumeOfMalformedIndexThrows) {
  ScratchDir dir;
  write_file_atomically(dir / "bad.pvd", "<VTKFile type=\"Collection\"><Collection>");
  EXPECT_THROW(PvdSeries::resume(dir / "bad.pvd", 1.0), std::runtime_error);
}

TEST(PvdDocument, EscapesFileNames) {
  const std::string xml = pvd_document({{2.0, "a&b/\"c\".vtu"}});
  EXPECT_CONTAINS(xml, "file=\"a&amp;b/&quot;c&quot;.vtu\"");
  EXPECT_CONTAINS(xml, "timestep=\"2\"");
}

}  // namespace
}  // namespace dsdem::io
