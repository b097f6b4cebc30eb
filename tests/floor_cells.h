// Photon counts on a floor grid, for closed-form tests: nx x nz square cells of side `cell` [m] in the plane y = 0,
// the first with its corner at (x0, z0). A photon of flux Phi / N lands in a cell as often as N / Phi times the
// integral of the irradiance over it, so expected counts follow from the closed-form E(x, z) [W/m^2].
#pragma once

#include <algorithm>
#include <functional>
#include <vector>

namespace pb::test {

struct FloorCells {
  int nx = 1, nz = 1;
  double cell = 1, x0 = 0, z0 = 0;

  size_t Count() const { return size_t(nx) * size_t(nz); }
  // The cell holding (x, z); points on the far edges go to the last cell.
  size_t Of(double x, double z) const {
    const int i = std::clamp(int((x - x0) / cell), 0, nx - 1), k = std::clamp(int((z - z0) / cell), 0, nz - 1);
    return size_t(i) * size_t(nz) + size_t(k);
  }
  // photonsPerWatt x the integral of E over each cell, by the midpoint rule on sub x sub points (E smooth in
  // each cell).
  std::vector<double> ExpectedCounts(const std::function<double(double, double)>& irradiance, double photonsPerWatt,
                                     int sub = 16) const {
    std::vector<double> counts(Count(), 0.0);
    for (int i = 0; i < nx; ++i)
      for (int k = 0; k < nz; ++k) {
        double flux = 0;
        for (int a = 0; a < sub; ++a)
          for (int b = 0; b < sub; ++b)
            flux += irradiance(x0 + (i + (a + 0.5) / sub) * cell, z0 + (k + (b + 0.5) / sub) * cell);
        counts[size_t(i) * size_t(nz) + size_t(k)] = flux * cell * cell / (sub * sub) * photonsPerWatt;
      }
    return counts;
  }
};

}  // namespace pb::test
