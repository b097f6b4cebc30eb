// IES LM-63-2002 files written for tests (mesh/ies_file.h): a table of candela values over given angles [deg],
// each value written on its own line after the angles so that a test can name the line a fault is on.
#pragma once

#include <fmt/format.h>

#include <functional>
#include <string>
#include <vector>

namespace pb::test {

struct IesTable {
  std::vector<double> vertical, horizontal;           // [deg]
  std::function<double(double gamma, double c)> cd;   // [cd] at angles in degrees
  double multiplier = 1, ballast = 1;
  std::string tilt = "TILT=NONE\n";                   // with its table, for TILT=INCLUDE
};

// The file's text. Line 1 is the version, 2-3 keywords, 4 the TILT line (and its table), then the counts line,
// the factors line, one line of vertical angles, one of horizontal angles, then one candela value per line, for
// each horizontal angle every vertical angle.
inline std::string IesText(const IesTable& t) {
  std::string s = "IESNA:LM-63-2002\n[TEST] photonbake #1\n[MANUFAC] tests\n" + t.tilt;
  s += fmt::format("1 -1 {:g} {} {} 1 2 0 0 0\n{:g} 1 10\n", t.multiplier, t.vertical.size(), t.horizontal.size(),
                   t.ballast);
  for (double v : t.vertical) s += fmt::format("{:g} ", v);
  s += "\n";
  for (double h : t.horizontal) s += fmt::format("{:g} ", h);
  s += "\n";
  for (double h : t.horizontal)
    for (double v : t.vertical) s += fmt::format("{:.17g}\n", t.cd(v, h));
  return s;
}

// Angles from `first` to `last` in steps of `step` degrees.
inline std::vector<double> Degrees(double first, double last, double step) {
  std::vector<double> a;
  for (double x = first; x <= last + 1e-9; x += step) a.push_back(x);
  return a;
}

}  // namespace pb::test
