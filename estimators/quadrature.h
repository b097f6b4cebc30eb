// Gauss-Legendre quadrature of a smooth function on [a, b]: 16 nodes per panel, exact for polynomials of
// degree <= 31 on each panel (Abramowitz and Stegun 1964, 25.4.29, for the nodes and weights).
#pragma once

#include <array>

namespace pb {

namespace detail {
// Positive nodes and their weights on [-1, 1]; the rule is symmetric.
inline constexpr std::array<double, 8> kGaussNodes = {
    0.0950125098376374, 0.2816035507792589, 0.4580167776572274, 0.6178762444026438,
    0.7554044083550030, 0.8656312023878318, 0.9445750230732326, 0.9894009349916499};
inline constexpr std::array<double, 8> kGaussWeights = {
    0.1894506104550685, 0.1826034150449236, 0.1691565193950025, 0.1495959888165767,
    0.1246289712555339, 0.0951585116824928, 0.0622535239386479, 0.0271524594117541};
}  // namespace detail

// Integral of f over [a, b] split into `panels` equal panels. f returns a double, or any value type with +, and *
// and / by a double (several integrands evaluated at once, sharing their work at each node).
template <typename F>
auto GaussLegendre(F&& f, double a, double b, int panels = 1) {
  const double width = (b - a) / panels;
  decltype(f(a)) sum{};
  for (int p = 0; p < panels; ++p) {
    const double mid = a + (p + 0.5) * width, half = width / 2;
    for (size_t i = 0; i < detail::kGaussNodes.size(); ++i)
      sum = sum + detail::kGaussWeights[i] * (f(mid - half * detail::kGaussNodes[i]) + f(mid + half * detail::kGaussNodes[i]));
  }
  return sum * width / 2;
}

}  // namespace pb
