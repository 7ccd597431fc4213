// Bad input files end in a clear error, never a crash (fuzz regressions).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "io/scenario.hpp"
#include "mesh/gmsh_reader.hpp"
#include "seismic/accelerogram.hpp"

namespace fs = std::filesystem;

namespace {

std::string msh_error(const std::string& bytes) {
  const fs::path p = fs::temp_directory_path() / ("dsdem_faults_" + std::to_string(::getpid()) + ".msh");
  std::ofstream(p, std::ios::binary) << bytes;
  std::string msg;
  try {
    dsdem::mesh::read_msh(p.string());
  } catch (const std::runtime_error& e) {
    msg = e.what();
  }
  fs::remove(p);
  return msg;
}

const std::string kHeader = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";

}  // namespace

TEST(Faults, MshWithoutFormatHeaderIsRejectedBeforeGmsh) {
  for (const std::string& bytes : {std::string(""), std::string("garbage\n"), std::string("$Nodes\n$EndNodes\n"),
                                   std::string("\x00\x01\x02", 3)}) {
    const std::string msg = msh_error(bytes);
    EXPECT_NE(msg.find("not a Gmsh ASCII .msh file"), std::string::npos) << msg;
    EXPECT_NE(msg.find(".msh:"), std::string::npos) << "names the file and line: " << msg;
  }
}

TEST(Faults, BinaryOrUnknownVersionMshIsRejected) {
  EXPECT_NE(msh_error("$MeshFormat\n4.1 1 8\n$EndMeshFormat\n").find("binary"), std::string::npos);
  EXPECT_NE(msh_error("$MeshFormat\n9.0 0 8\n$EndMeshFormat\n").find("unsupported .msh version"), std::string::npos);
  EXPECT_NE(msh_error("$MeshFormat\nx\n$EndMeshFormat\n").find("expected 'version"), std::string::npos);
  EXPECT_NE(msh_error("$MeshFormat\n4.1 0 4\n$EndMeshFormat\n").find("data size"), std::string::npos);
}

TEST(Faults, TruncatedOrUnbalancedMshIsRejected) {
  EXPECT_NE(msh_error(kHeader + "$Nodes\n1 1 1 1\n").find("$Nodes is not closed (truncated file?)"), std::string::npos);
  EXPECT_NE(msh_error(kHeader + "$Nodes\n$Elements\n").find("$Nodes is not closed before '$Elements'"),
            std::string::npos);
  EXPECT_NE(msh_error(kHeader + "$EndNodes\n").find("without a matching $Nodes"), std::string::npos);
  EXPECT_NE(msh_error(kHeader).find("no $Nodes section"), std::string::npos);
}

TEST(Faults, GarbageScenarioIsAScenarioError) {
  for (const std::string& text : {std::string(""), std::string("["), std::string("- 1\n- 2\n"),
                                  std::string("time: {end: [1, 2]}\n"), std::string("\t\x01\xff: ?\n"),
                                  std::string("materials: !!binary x\n"), std::string("*a\n")}) {
    try {
      dsdem::io::parse_scenario(text, "g.yaml");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const dsdem::io::ScenarioError& e) {
      EXPECT_NE(std::string(e.what()).find("g.yaml"), std::string::npos) << e.what();
    }
  }
}

TEST(Faults, GarbageAccelerogramsAreRuntimeErrors) {
  using namespace dsdem::seismic;
  for (const std::string& text : {std::string(""), std::string("a,b\n1,2\n"), std::string("0,nan\n1,1\n"),
                                  std::string("0,1\n0,1\n"), std::string("0,1e400\n0.1,1\n")}) {
    std::istringstream in(text);
    EXPECT_THROW(read_accelerogram_csv(in, "g.csv", AccelUnits::G), std::runtime_error) << text;
  }
  for (const std::string& text : {std::string(""), std::string("1\n2\n3\nNPTS= -5, DT= .01 SEC\n"),
                                  std::string("1\n2\n3\nNPTS= 3, DT= 0 SEC\n1 2 3\n"),
                                  std::string("1\n2\n3\nNPTS= 99999999999, DT= .01 SEC\n1\n")}) {
    std::istringstream in(text);
    EXPECT_THROW(read_accelerogram_at2(in, "g.AT2"), std::runtime_error) << text;
  }
}

// Fuzz find: an AT2 header claiming 333 million points made the reader reserve 2.7 GB
// before reading a single value (libFuzzer out-of-memory). Now it fails on the count,
// allocating only what the file holds.
TEST(Faults, At2HeaderClaimingHugeNptsFailsWithoutReservingIt) {
  std::istringstream in("PEER\nX\nUNITS OF G\n 333333333  .01000    NPTS, DT\n  0.0 1.0 2.0\n");
  try {
    dsdem::seismic::read_accelerogram_at2(in, "huge.AT2");
    ADD_FAILURE() << "accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("file ends after 3 values; NPTS = 333333333"), std::string::npos) << e.what();
  }
}

// Fuzz find: `--set time.end.x=1` walked through the scalar time.end and yaml-cpp threw
// YAML::BadSubscript, which escaped as an unexpected error (exit 1, no file or key).
TEST(Faults, SetOverrideThroughAScalarIsAScenarioError) {
  const std::string text = "time:\n  end: 1.0\nmesh:\n  file: m.msh\n";
  for (const std::string& o : {std::string("time.end.x=1"), std::string("time.end.x.y=1"), std::string("mesh.file.a=2")}) {
    try {
      dsdem::io::parse_scenario(text, "s.yaml", {o});
      ADD_FAILURE() << o;
    } catch (const dsdem::io::ScenarioError& e) {
      EXPECT_NE(std::string(e.what()).find("is a value, not a section with keys"), std::string::npos) << e.what();
    }
  }
}

// Fuzz find: Gmsh 4.8 crashed (SEGV in GModel::setPhysicalName) on a physical name of
// dimension 4; dsdem's own .msh parser (no libgmsh since) rejects it with the line.
TEST(Faults, MshPhysicalNameOfDimensionFourIsRejectedBeforeGmsh) {
  const std::string msg = msh_error(kHeader + "$PhysicalNames\n1\n4 1 \"block\"\n$EndPhysicalNames\n$Nodes\n0 0 0 0\n$EndNodes\n");
  EXPECT_NE(msg.find("physical name with dimension 4"), std::string::npos) << msg;
}

// Fuzz find: a CSV with steps of 0.01 s and one jump to t = 540225 s was resampled at
// 0.01 s: 54 million samples, a hang of minutes. Now refused with the numbers.
TEST(Faults, CsvWhoseResamplingWouldExplodeIsRefused) {
  std::istringstream in("time_s,acc_g\n0,0\n0.01,0.1\n0.02,0.2\n540225.08,0\n");
  try {
    dsdem::seismic::read_accelerogram_csv(in, "jump.csv", dsdem::seismic::AccelUnits::G);
    ADD_FAILURE() << "accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("would need 5.4e+07 samples"), std::string::npos) << e.what();
  }
}

// Second fuzz find on the same path: 0.01 s steps over 40225 s (4 million samples) passed
// a first limit of 2e7 and then spent > 10 s in the baseline correction. Limit 1e6.
TEST(Faults, CsvResampledToMillionsOfSamplesIsRefused) {
  std::istringstream in("time_s,acc_g\n0,0\n0.01,0.1\n0.02,0.2\n40225.08,0\n");
  EXPECT_THROW(dsdem::seismic::read_accelerogram_csv(in, "long.csv", dsdem::seismic::AccelUnits::G),
               std::runtime_error);
}
