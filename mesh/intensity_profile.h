// A luminaire's luminous intensity I [cd] over the directions it emits into (a goniometric distribution, as an IES
// LM-63 file gives it: mesh/ies_file.h), in type C photometry:
//   the vertical angle gamma runs from the nadir (0, the light's "direction") to the zenith (pi);
//   the horizontal angle C runs counter-clockwise seen from above (looking along the nadir), from the C = 0 plane.
// The table holds I at a grid of (C, gamma), interpolated bilinearly in the angles; outside the vertical angles
// measured (a downlight's 0-90 degrees) I is 0. Lateral symmetries are expanded at construction, so C spans
// [0, 2 pi] whatever the file covered.
// Its flux is the integral of I over the sphere, integral I(gamma, C) sin(gamma) dgamma dC [lm], computed exactly
// for the bilinear interpolant cell by cell; the cells' shares are the CDF that photons pick a cell by
// (estimators/emission.h), before they take a direction in it in proportion to I.
#pragma once

#include <string>
#include <vector>

namespace pb {

class IntensityProfile {
 public:
  // One measured table: vertical angles gamma [rad], increasing within [0, pi], at least 2; horizontal angles C
  // [rad], increasing from 0, their last one giving the symmetry as LM-63 does (0: about the vertical axis; pi/2:
  // each quadrant mirrors the first; pi: mirrored about the C = 0-180 plane; above pi up to 2 pi: none), or
  // pi/2 to 3 pi/2 (mirrored about the C = 90-270 plane, an older type C convention); candela[h * gamma.size() +
  // v] >= 0 at (C_h, gamma_v). The caller (the file reader) has checked all this: it is PB_CHECKed here.
  IntensityProfile(std::string source, std::vector<double> gamma, std::vector<double> c, std::vector<double> candela);

  // I [cd] toward (gamma, C), angles in radians, C in [0, 2 pi].
  double Intensity(double gamma, double c) const;
  // The flux, integral of I over the sphere [lm]; > 0 unless every value is 0.
  double Flux() const { return flux_; }
  // The cells between consecutive angles: (C_i, C_i+1) x (gamma_j, gamma_j+1), cell i * (gammaCount - 1) + j.
  size_t CellCount() const { return cellCdf_.size(); }
  // Cumulative share of the flux by cell; back() == 1 (empty when the flux is 0).
  const std::vector<double>& CellCdf() const { return cellCdf_; }
  struct Cell {
    double gamma0, gamma1, c0, c1;  // [rad]
    double maxIntensity;            // the largest of its corners [cd]: I in the cell is at most this
  };
  Cell CellAt(size_t index) const;
  const std::string& Source() const { return source_; }  // the file it came from, for messages and reports
  const std::vector<double>& VerticalAngles() const { return gamma_; }
  const std::vector<double>& HorizontalAngles() const { return c_; }  // expanded to [0, 2 pi]
  const std::vector<double>& Candela() const { return candela_; }     // [cd], by horizontal then vertical angle

 private:
  double At(size_t h, size_t v) const { return candela_[h * gamma_.size() + v]; }
  double CellFlux(size_t h, size_t v) const;
  void ExpandSymmetry();

  std::string source_;
  std::vector<double> gamma_, c_, candela_;
  std::vector<double> cellCdf_;
  double flux_ = 0;
};

}  // namespace pb
