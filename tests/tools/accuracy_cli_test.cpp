// The accuracy tool's smoke test: --quick bakes the closed-form scene twice per configuration (two seeds) and
// writes the CSV (one row per configuration, errors finite and in range), the SVG plot and the cheapest-run table.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "tests/ply_reader.h"
#include "tests/run_tool.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

TEST(AccuracyCli, QuickSweepWritesCsvPlotAndTable) {
  const std::string dir = test::TempDirectory("accuracy");
  const test::ToolRun run = test::RunTool(PB_ACCURACY_EXE, "--quick --out " + dir);
  ASSERT_EQ(run.status, 0) << run.output;
  std::istringstream csv(test::ReadBytes(dir + "/accuracy.csv"));
  std::string header, line;
  std::getline(csv, header);
  EXPECT_EQ(header.rfind("estimator,kernel,h_m,auto_h,k,edge_correction,photons,seconds", 0), 0u) << header;
  int rows = 0;
  while (std::getline(csv, line)) {
    ++rows;
    // rmse_rel is the 12th column: finite, positive, and below 100% for these runs.
    std::istringstream fields(line);
    std::string field;
    for (int i = 0; i < 12; ++i) std::getline(fields, field, ',');
    const double rmse = std::stod(field);
    EXPECT_TRUE(rmse > 0 && rmse < 1) << line;
  }
  EXPECT_EQ(rows, 2);
  EXPECT_NE(test::ReadBytes(dir + "/accuracy.svg").find("<polyline"), std::string::npos);
  EXPECT_NE(test::ReadBytes(dir + "/cheapest.md").find("| 10% |"), std::string::npos);
}

// --scene box --quick: the box gridded at 25 mm against a short path-traced truth; one --direct sampled run and one
// path-traced run, each its own curve in the plot, and each object's error.
TEST(AccuracyCli, QuickBoxSweepMeasuresSampledAndPathTracedRuns) {
  const std::string dir = test::TempDirectory("accuracy-box");
  const test::ToolRun run = test::RunTool(PB_ACCURACY_EXE, "--scene box --quick --out " + dir);
  ASSERT_EQ(run.status, 0) << run.output;
  const std::string csv = test::ReadBytes(dir + "/accuracy.csv");
  EXPECT_NE(csv.find(",sampled,16,0,"), std::string::npos) << csv;
  EXPECT_NE(csv.find(",photons,64,64,"), std::string::npos) << csv;
  const std::string svg = test::ReadBytes(dir + "/accuracy.svg");
  EXPECT_NE(svg.find(">sampled<"), std::string::npos);
  EXPECT_NE(svg.find(">path tracer<"), std::string::npos);
  // Each object's error: a row per object of the box in the table, and one per run and object in the CSV.
  const std::string objects = test::ReadBytes(dir + "/objects.md");
  for (const char* row : {"| floor | 576 |", "| tall_block_top | 64 |", "| **all** | 3937 |"})
    EXPECT_NE(objects.find(row), std::string::npos) << row << "\n" << objects;
  EXPECT_NE(test::ReadBytes(dir + "/objects.csv").find("path tracer 64 spp,1,"), std::string::npos);
}

}  // namespace
}  // namespace pb
