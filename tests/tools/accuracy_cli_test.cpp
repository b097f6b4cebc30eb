// The accuracy tool's smoke test: --quick bakes the closed-form scene twice per configuration (two seeds) and
// writes the CSV (one row per configuration, errors finite and in range), the SVG plot and the cheapest-run table.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
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

// The quality targets against a path-traced truth, as the accuracy issue asks of --target-error: the error the
// accuracy tool measures, the relative RMSE of H over the vertices, net of the truth's own noise (its predicted
// sigma_H, in quadrature: sqrt(rmse^2 - truth^2)), within 1.5 times the target both ways. Box (a 2,048-path truth,
// 2.4% of its own noise): draft (8%) and production (2%); the office with books (1,024 paths, 3.5%): draft.
// Measured against 16,384-path truths, 2026-12-05: 6.27%, 1.70% and 7.18%; against these: 6.26%, 1.72%, 7.08%.
// The net figure's own uncertainty is small beside the bounds: the path tracer's predicted noise lies within 3% of
// its noise measured between two seeds (the box's sweep: 3.36% against 3.44% at 1,024 paths, 1.68% against 1.72%
// at 4,096), which would move the box's production figure by 0.1%.
double NetError(const std::string& dir, const std::string& args) {
  const test::ToolRun run = test::RunTool(PB_ACCURACY_EXE, args + " --out " + dir + " --truth-cache " + dir + "/truth");
  EXPECT_EQ(run.status, 0) << run.output;
  std::istringstream csv(test::ReadBytes(dir + "/accuracy.csv"));
  std::string header, line, field;
  std::getline(csv, header), std::getline(csv, line);
  std::istringstream names(header), values(line);
  std::map<std::string, double> row;
  while (std::getline(names, header, ',') && std::getline(values, field, ','))
    row[header] = std::strtod(field.c_str(), nullptr);
  const double rmse = row["rmse_rel"], truth = row["truth_noise_rel"];
  EXPECT_GT(rmse, truth) << args;
  return std::sqrt(rmse * rmse - truth * truth);
}

void ExpectWithinOneAndAHalf(double error, double target, const std::string& what) {
  std::printf("%s: %.2f%% net of the truth's noise, target %.2f%%\n", what.c_str(), 100 * error, 100 * target);
  EXPECT_GT(error, target / 1.5) << what;
  EXPECT_LT(error, target * 1.5) << what;
}

TEST(AccuracyCli, QualityTargetsAreReachedWithinOneAndAHalfOfThePathTracedTruthOnTheBox) {
  const std::string dir = test::TempDirectory("accuracy-box-targets");
  ExpectWithinOneAndAHalf(NetError(dir, "--scene box --truth-paths 2048 --quality draft"), 0.08, "box, draft");
  ExpectWithinOneAndAHalf(NetError(dir, "--scene box --truth-paths 2048 --quality production"), 0.02, "box, production");
}

TEST(AccuracyCli, QualityTargetsAreReachedWithinOneAndAHalfOfThePathTracedTruthOnTheOffice) {
  const std::string dir = test::TempDirectory("accuracy-office-targets");
  ExpectWithinOneAndAHalf(NetError(dir, "--scene office --truth-paths 1024 --quality draft"), 0.08, "office, draft");
}

}  // namespace
}  // namespace pb
