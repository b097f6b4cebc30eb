// The error of linear interpolation over a triangle: |sum_k b_k f(p_k) - f(p)| at the points p of a regular
// barycentric lattice (n divisions per edge; the corners, where the error is 0, are left out), for any scalar
// field f. The lattice is the set of points at which refinement and decimation judge a face; its spacing is the
// longest edge / n. Units are those of f.
#pragma once

#include <OpenMesh/Core/Geometry/VectorT.hh>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

namespace pb {

struct InterpolationError {
  double max = 0;   // largest error at a lattice point
  double sum = 0;   // summed over the lattice points
  size_t points = 0;
  void Add(const InterpolationError& o) {
    max = std::max(max, o.max);
    sum += o.sum;
    points += o.points;
  }
};

// Divisions per edge so that lattice points lie at most `spacing` apart along the longest edge, within [2, cap].
inline int LatticeDivisions(const std::array<OpenMesh::Vec3d, 3>& corners, double spacing, int cap) {
  const double longest = std::max({(corners[1] - corners[0]).norm(), (corners[2] - corners[1]).norm(),
                                   (corners[0] - corners[2]).norm()});
  return int(std::clamp(std::ceil(longest / spacing), 2.0, double(cap)));
}

// f(p) -> double at a point of the triangle; `values` are f at the corners.
template <typename Field>
InterpolationError LatticeError(const std::array<OpenMesh::Vec3d, 3>& corners, const std::array<double, 3>& values,
                                int divisions, Field&& f) {
  InterpolationError e;
  for (int i = 0; i <= divisions; ++i)
    for (int j = 0; i + j <= divisions; ++j) {
      const int k = divisions - i - j;
      if (i == divisions || j == divisions || k == divisions) continue;  // a corner
      const double b0 = double(i) / divisions, b1 = double(j) / divisions, b2 = double(k) / divisions;
      const OpenMesh::Vec3d p = b0 * corners[0] + b1 * corners[1] + b2 * corners[2];
      const double error = std::fabs(b0 * values[0] + b1 * values[1] + b2 * values[2] - f(p));
      e.max = std::max(e.max, error);
      e.sum += error;
      ++e.points;
    }
  return e;
}

}  // namespace pb
