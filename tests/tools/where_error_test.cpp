// The summary's `where` line and the report's per-surface predicted error (docs/bake.md, "where the error sits"):
// the line names exactly the surfaces of at least 1% of the area, not black on the display (a thousandth of the
// scene's mean H), whose own predicted error passes twice the bake's, as the report gives them, largest first.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <regex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/ply_reader.h"
#include "tests/run_tool.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

TEST(WhereLine, NamesTheSurfacesWhoseOwnErrorPassesTwiceTheBakesLargestFirst) {
  const std::string dir = test::TempDirectory("where-line");
  const test::ToolRun run = test::RunBake(PB_SOURCE_DIR "/data/box/box.obj -o " + dir + "/out.ply --photons 200000 "
                                          "--report-all --report " + dir + "/r.json");
  ASSERT_EQ(run.status, 0) << run.output;
  const nlohmann::json report = nlohmann::json::parse(test::ReadBytes(dir + "/r.json"));
  const double bake = report.at("predicted_error").at("total").get<double>();
  double area = 0, light = 0;
  const auto luminance = [](const nlohmann::json& rgb) {
    return 0.2126 * rgb[0].get<double>() + 0.7152 * rgb[1].get<double>() + 0.0722 * rgb[2].get<double>();
  };
  for (const nlohmann::json& s : report.at("surfaces"))
    area += s.at("area_m2").get<double>(), light += s.at("area_m2").get<double>() * luminance(s.at("mean_irradiance_W_m2"));
  std::vector<std::pair<double, int>> expected;  // (error, surface) of those the line should count
  for (const nlohmann::json& s : report.at("surfaces")) {
    const double own = s.at("predicted_error").at("total").get<double>();
    EXPECT_GE(own, 0.0);
    EXPECT_NEAR(own, std::hypot(s.at("predicted_error").at("noise").get<double>(),
                                s.at("predicted_error").at("smoothing_bias").get<double>()), 1e-9);
    const bool shown = luminance(s.at("mean_irradiance_W_m2")) >= 1e-3 * light / area;  // not black on the display
    if (s.at("area_m2").get<double>() >= 0.01 * area && shown && own > 2 * bake)
      expected.push_back({own, s.at("surface").get<int>()});
  }
  // 200,000 photons leave the blocks' sides, small and dim, well above the bake's figure.
  ASSERT_FALSE(expected.empty()) << "no surface reads twice the bake's error; the test scene no longer shows the line";
  std::stable_sort(expected.begin(), expected.end(), [](auto a, auto b) { return a.first > b.first; });
  std::smatch where;
  ASSERT_TRUE(std::regex_search(run.output, where, std::regex("  where     (\\d+) of the surfaces[^\n]*"))) << run.output;
  EXPECT_EQ(std::stoul(where[1]), expected.size());
  std::vector<int> named;
  const std::string line = where[0];
  const std::regex surface("surface (\\d+) \\(");
  for (std::sregex_iterator it(line.begin(), line.end(), surface), end; it != end; ++it)
    named.push_back(std::stoi((*it)[1]));
  ASSERT_EQ(named.size(), std::min<size_t>(3, expected.size()));
  for (size_t k = 0; k < named.size(); ++k) EXPECT_EQ(named[k], expected[k].second) << line;
}

}  // namespace
}  // namespace pb
