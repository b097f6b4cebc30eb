// IES LM-63 files (mesh/ies_file.h) into intensity profiles (mesh/intensity_profile.h): the table read with its
// multipliers, through a TILT table and commas; the bilinear interpolation; every lateral symmetry mirrored as
// LM-63 defines it; the flux against quadrature over the sphere; faults named by file:line.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "mesh/errors.h"
#include "mesh/ies_file.h"
#include "tests/ies_text.h"
#include "tests/test_scenes.h"

namespace pb {
namespace {

constexpr double kDeg = std::numbers::pi / 180;

IntensityProfile Load(const std::string& name, const std::string& text) {
  const std::string path = test::TempDirectory(name) + "/lamp.ies";
  test::WriteText(path, text);
  return LoadIesFile(path);
}

// An asymmetric lamp: brighter downward and toward C = 0.
double Lamp(double gamma, double c) { return (50 + 400 * std::cos(gamma * kDeg) * (gamma <= 90)) * (1 + 0.6 * std::cos(c * kDeg)); }

TEST(IesFile, ReadsTheTableWithItsMultipliersPastATiltTable) {
  test::IesTable t{test::Degrees(0, 180, 10), test::Degrees(0, 330, 30), Lamp, 2, 0.75};
  t.tilt = "TILT=INCLUDE\n1\n3\n0, 45, 90\n1.0, 0.9, 0.8\n";
  const IntensityProfile p = Load("ies-table", test::IesText(t));
  ASSERT_EQ(p.VerticalAngles().size(), 19u);
  EXPECT_EQ(p.VerticalAngles().back(), std::numbers::pi);
  EXPECT_EQ(p.HorizontalAngles().back(), 2 * std::numbers::pi) << "330 degrees' neighbour is 0's";
  for (double g : {0.0, 40.0, 90.0, 180.0})
    for (double c : {0.0, 90.0, 330.0}) EXPECT_NEAR(p.Intensity(g * kDeg, c * kDeg), 1.5 * Lamp(g, c), 1e-9) << g << ", " << c;
  // Bilinear between the nodes, and from 330 degrees round to 360 = 0.
  EXPECT_NEAR(p.Intensity(45 * kDeg, 15 * kDeg), 1.5 * 0.25 * (Lamp(40, 0) + Lamp(50, 0) + Lamp(40, 30) + Lamp(50, 30)), 1e-9);
  EXPECT_NEAR(p.Intensity(0, 345 * kDeg), 1.5 * 0.5 * (Lamp(0, 330) + Lamp(0, 0)), 1e-9);
  EXPECT_EQ(p.Source().substr(p.Source().size() - 8), "lamp.ies");
}

TEST(IesFile, SymmetriesMirrorTheMeasuredPlanes) {
  const auto profile = [](const std::string& name, std::vector<double> c) {
    return Load(name, test::IesText({test::Degrees(0, 90, 15), std::move(c), Lamp}));
  };
  const IntensityProfile axial = profile("ies-axial", {0});
  const IntensityProfile quadrant = profile("ies-quadrant", {0, 30, 60, 90});
  const IntensityProfile bilateral = profile("ies-bilateral", test::Degrees(0, 180, 45));
  const IntensityProfile across = profile("ies-90-270", test::Degrees(90, 270, 45));
  const IntensityProfile full = profile("ies-full", test::Degrees(0, 360, 60));
  constexpr double pi = std::numbers::pi;
  for (double g : {0.1, 0.5, 1.2}) {
    for (double c : {0.0, 0.2, 0.7, 1.4}) {
      EXPECT_NEAR(axial.Intensity(g, c), axial.Intensity(g, c + 4.5), 1e-9) << "the same all round";
      for (double image : {pi - c, pi + c, 2 * pi - c}) EXPECT_NEAR(quadrant.Intensity(g, image), quadrant.Intensity(g, c), 1e-9);
      EXPECT_NEAR(bilateral.Intensity(g, 2 * pi - c), bilateral.Intensity(g, c), 1e-9);
      EXPECT_NEAR(across.Intensity(g, pi - c), across.Intensity(g, c), 1e-9) << "mirrored about the 90-270 plane";
      EXPECT_NEAR(full.Intensity(g, 2 * pi - 1e-12), full.Intensity(g, 0), 1e-6) << "360 is 0";
    }
  }
  // The mirrored planes carry the measured values: quadrant's 150 degrees is its 30, the 90-270 file's 0 is its 180.
  EXPECT_NEAR(quadrant.Intensity(15 * kDeg, 150 * kDeg), Lamp(15, 30), 1e-9);
  EXPECT_NEAR(across.Intensity(30 * kDeg, 0), Lamp(30, 180), 1e-9);
  EXPECT_NEAR(across.Intensity(30 * kDeg, 315 * kDeg), Lamp(30, 225), 1e-9);
  EXPECT_EQ(quadrant.Intensity(100 * kDeg, 0), 0) << "a downlight measured to 90 degrees sends nothing up";
}

// The flux against the midpoint rule over (gamma, C) on a grid much finer than the table's.
double QuadratureFlux(const IntensityProfile& p, int n) {
  double sum = 0;
  const double dg = std::numbers::pi / n, dc = 2 * std::numbers::pi / n;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double g = (i + 0.5) * dg;
      sum += p.Intensity(g, (j + 0.5) * dc) * std::sin(g) * dg * dc;
    }
  return sum;
}

TEST(IesFile, FluxIsTheIntegralOverTheSphere) {
  const auto constant = [](double, double) { return 100.0; };
  EXPECT_NEAR(Load("ies-iso", test::IesText({{0, 90, 180}, {0}, constant})).Flux(), 400 * std::numbers::pi, 1e-9);
  EXPECT_NEAR(Load("ies-down", test::IesText({{0, 45, 90}, {0}, constant})).Flux(), 200 * std::numbers::pi, 1e-9);
  const IntensityProfile lamp = Load("ies-flux", test::IesText({test::Degrees(0, 180, 10), test::Degrees(0, 330, 30), Lamp}));
  EXPECT_NEAR(lamp.Flux(), QuadratureFlux(lamp, 2000), 1e-4 * lamp.Flux());
  const IntensityProfile narrow = Load("ies-narrow", test::IesText({{0, 2.5, 5, 90}, {0, 90}, Lamp}));
  EXPECT_NEAR(narrow.Flux(), QuadratureFlux(narrow, 2000), 1e-4 * narrow.Flux()) << "cells of 2.5 degrees at the pole";
  ASSERT_EQ(lamp.CellCdf().size(), lamp.CellCount());
  EXPECT_EQ(lamp.CellCdf().back(), 1);
}

TEST(IesFile, FaultsNameTheLine) {
  const test::IesTable good{{0, 45, 90}, {0, 90}, Lamp};
  const std::string text = test::IesText(good);
  // Lines: 1 version, 2-3 keywords, 4 TILT, 5 counts, 6 factors, 7 vertical angles, 8 horizontal, 9.. candela.
  const auto replaceLine = [&](int number, const std::string& with) {
    std::string s = text;
    size_t at = 0;
    for (int i = 1; i < number; ++i) at = s.find('\n', at) + 1;
    return s.replace(at, s.find('\n', at) - at, with);
  };
  const std::pair<std::string, std::string> cases[] = {
      {"IESNA:LM-63-2002\n1 2 3\n", "lamp.ies: error: no 'TILT=' line"},
      {replaceLine(11, "-5"), "lamp.ies:11: error: candela values must lie in [0, 1e+30], not -5"},
      {replaceLine(11, "1.2.3"), "lamp.ies:11: error: malformed number '1.2.3' for the candela values"},
      {replaceLine(12, "nan"), "lamp.ies:12: error: non-finite number 'nan'"},
      {text.substr(0, text.rfind("\n", text.size() - 2) + 1), "lamp.ies:13: error: the file ends after 5 of its 6 candela values"},
      {replaceLine(5, "1 -1 1 3 2 2 2 0 0 0"), "lamp.ies:5: error: photometric type 2: only type C (1) is read"},
      {replaceLine(5, "1 -1 1 2000000000 2 1 2 0 0 0"), "lamp.ies:5: error: the vertical angle count must be a whole number in [2, "},
      {replaceLine(7, "0 90 45"), "lamp.ies:7: error: the vertical angles must increase: angle 3"},
      // Two angles apart in degrees (100 and the next double) that are one in radians (issue 60: it aborted).
      {replaceLine(7, "0 100 100.00000000000001"), "lamp.ies:7: error: the vertical angles must increase: angle 3"},
      {replaceLine(7, "0 45 190"), "lamp.ies:7: error: vertical angles must lie in [0, 180], not 190"},
      {replaceLine(8, "0 120"), "lamp.ies:8: error: horizontal angles from 0 to 120 degrees: LM-63 allows"},
      {replaceLine(6, "-1 1 10"), "lamp.ies:6: error: ballast factor and ballast-lamp photometric factor must lie in"},
      {replaceLine(4, "TILT=INCLUDE"), "lamp.ies:5: error: the tilt's angle count must be a whole number"},
  };
  for (const auto& [bad, fragment] : cases) {
    try {
      Load("ies-fault", bad);
      ADD_FAILURE() << bad << " was read";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace pb
