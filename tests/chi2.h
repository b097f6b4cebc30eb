// Pearson's chi-square goodness-of-fit test for samplers (Mitsuba's chi2 habit): cells whose expected count is
// below 5 are pooled, and the p-value comes from the regularised upper incomplete gamma function. On failure,
// Describe() prints both histograms so the mismatch can be seen.
#pragma once

#include <string>
#include <vector>

namespace pb::test {

struct Chi2Result {
  double statistic = 0;
  int degreesOfFreedom = 0;
  double pValue = 1;
  std::string histograms;  // observed vs expected per cell, for failure messages
};

// expected: counts per cell (summing to the number of samples).
Chi2Result Chi2Test(const std::vector<double>& observed, const std::vector<double>& expected);

// Q(a, x) = Gamma(a, x) / Gamma(a), upper regularised incomplete gamma.
double RegularizedGammaQ(double a, double x);

}  // namespace pb::test
