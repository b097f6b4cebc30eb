#include "tests/chi2.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace pb::test {
namespace {

// Series for P(a, x), valid for x < a + 1.
double GammaPSeries(double a, double x) {
  double term = 1.0 / a, sum = term;
  for (int n = 1; n < 10000 && std::fabs(term) > 1e-16 * std::fabs(sum); ++n) {
    term *= x / (a + n);
    sum += term;
  }
  return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

// Continued fraction (modified Lentz) for Q(a, x), valid for x >= a + 1.
double GammaQContinuedFraction(double a, double x) {
  constexpr double tiny = 1e-300;
  double b = x + 1 - a, c = 1 / tiny, d = 1 / b, f = d;
  for (int i = 1; i < 10000; ++i) {
    const double an = -i * (i - a);
    b += 2;
    d = an * d + b;
    d = std::fabs(d) < tiny ? tiny : d;
    c = b + an / c;
    c = std::fabs(c) < tiny ? tiny : c;
    d = 1 / d;
    const double delta = d * c;
    f *= delta;
    if (std::fabs(delta - 1) < 1e-16) break;
  }
  return f * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

}  // namespace

double RegularizedGammaQ(double a, double x) {
  if (x <= 0) return 1.0;
  return x < a + 1 ? 1.0 - GammaPSeries(a, x) : GammaQContinuedFraction(a, x);
}

Chi2Result Chi2Test(const std::vector<double>& observed, const std::vector<double>& expected) {
  std::vector<size_t> order(expected.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return expected[a] < expected[b]; });
  Chi2Result r;
  double pooledObserved = 0, pooledExpected = 0;
  int cells = 0;
  for (size_t i : order) {
    if (expected[i] == 0 && observed[i] > 0) {  // a sample where the pdf is zero: certain failure
      r.pValue = 0;
      r.histograms = fmt::format("cell {} observed {} where the pdf is zero\n", i, observed[i]);
      return r;
    }
    r.histograms += fmt::format("cell {:4}: observed {:10.0f} expected {:12.2f}\n", i, observed[i], expected[i]);
    if (expected[i] < 5) {
      pooledObserved += observed[i];
      pooledExpected += expected[i];
      if (pooledExpected < 5) continue;
      r.statistic += (pooledObserved - pooledExpected) * (pooledObserved - pooledExpected) / pooledExpected;
      pooledObserved = pooledExpected = 0;
    } else {
      r.statistic += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
    }
    ++cells;
  }
  if (pooledExpected > 0) {  // remaining small pool: merge its deviation as one more cell
    r.statistic += (pooledObserved - pooledExpected) * (pooledObserved - pooledExpected) / pooledExpected;
    ++cells;
  }
  r.degreesOfFreedom = std::max(1, cells - 1);
  r.pValue = RegularizedGammaQ(0.5 * r.degreesOfFreedom, 0.5 * r.statistic);
  return r;
}

}  // namespace pb::test
