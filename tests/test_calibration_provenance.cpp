// The provenance `calibrate` records (issue 14: built in the library, not the CLI): the run's
// robot, level and seed, and each input file given with its SHA-256 (FIPS 180-4 test vector).

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "refusal.hpp"
#include "robcal/identify/calibration_output.hpp"

namespace robcal {
namespace {

TEST(CalibrationProvenance, RecordsTheRunAndEveryInputGiven) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(::testing::TempDir());
  const fs::path tool = dir / "prov-tool.yaml", data = dir / "prov-data.csv";
  std::ofstream(tool) << "abc";
  std::ofstream(data) << "";
  CalibrationRun run;
  run.result.robot.model.name = "ABB IRB 120";
  run.options.level = CalibrationLevel::Kinematic;
  run.options.seed = 7;
  const Provenance p = calibration_provenance(run, {"", tool.string(), data.string()});
  EXPECT_EQ(p.robot, "ABB IRB 120");
  EXPECT_EQ(p.level, "kinematic");
  ASSERT_TRUE(p.seed);
  EXPECT_EQ(*p.seed, 7u);
  ASSERT_EQ(p.files.size(), 2u);  // no model file given: none recorded
  EXPECT_EQ(p.files[0].role, "tool");
  EXPECT_EQ(p.files[0].sha256,  // SHA-256("abc"), FIPS 180-4 appendix B.1
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(p.files[1].role, "measurements");
  EXPECT_EQ(p.files[1].sha256,  // SHA-256 of the empty string
            "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_REFUSED(calibration_provenance(run, {(dir / "prov-missing.yaml").string(), "", ""}),
                 InputError, "prov-missing.yaml");
}

}  // namespace
}  // namespace robcal
