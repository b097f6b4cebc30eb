// Automatic bandwidth h [m] for one surface, from its own photons: the plug-in rule that minimises the
// asymptotic mean integrated *relative* squared error of the estimate (Silverman 1986, "Density Estimation",
// sec. 3.4 and 4.3; Wand and Jones 1995, "Kernel Smoothing", ch. 3). Relative, because a display shows ratios:
// an error of 0.01 W/m^2 matters where H is 0.1, not where it is 10. For a kernel with roughness R and second
// moment mu2 (estimators/kernels.h), the error of the estimate at x is
//   variance / H^2 = phi2(x) R / (H^2 h^2)   (phi2: density of squared photon flux [W^2/m^2])
//   bias / H       = h^2 mu2 lap(H) / (2 H),
// and integrating both over the surface and minimising over h gives
//   h^6 = 2 R integral(phi2 / H^2) / (mu2^2 integral((lap H / H)^2)).
// The histogram's bias is first order instead (a point's offset from its bucket's centre times grad H): for a
// bucket of side b, bias^2 averages b^2 |grad H|^2 / 12, and b^4 = 12 integral(phi2 / H^2) / integral(|grad H / H|^2).
// Both integrals come from a pilot histogram of ~400 photons per cell (a power of two of cells per axis, 4 to 64;
// estimators/pilot_histogram.h, whose exact sums let the processes of a distributed bake choose alike),
// and the roughness (lap H by the 5-point stencil, grad H by central differences, on cells whose neighbours lie
// wholly on the surface) from the finest level of that pilot's pyramid (cells merged 2 x 2, down to 4 per axis)
// where it stands 3 standard errors above 0: a stencil's signal grows with the cell's side and its noise falls,
// so fine cells of many photons measure only noise (the single pilot at 400 photons per cell did, and h came out
// by luck). Each stencil's own noise variance is subtracted and the sum clipped at 0 only as a whole. Where no
// level measures it, the least roughness no level can rule out (estimate plus 3 standard errors) sets an h no
// wider than the photons vouch for. Where no stencil fits at any level (a strip narrower than three cells, a ring,
// a wall that a floor slab cuts across: the pilot's cells are square, on the surface's longer side), nothing is
// measured, and h is the finest pilot's cell side, the scale it looked at (it was once the surface's size: the
// atrium's 12 x 8 m walls, cut by their galleries' floor, took h = 9.7 m and read their ground floor 3.5% bright
// and their first floor 2.5% dark). h is at most the surface's own size (the square root of its area); where
// photons are too few for a pilot (under 3,600), h holds 1,000 photons on average (a noise of about 3%), up to that
// size; it is never below the radius that holds 20 photons.
#pragma once

#include <span>

#include "estimators/density_estimator.h"
#include "estimators/pilot_histogram.h"

namespace pb {

// h for the surface of `pilot` (its region), from its pilot of all its photons.
float ChooseBandwidth(EstimatorKind kind, Kernel kernel, const PilotHistogram& pilot);

// The smoothing bias that the same pilot predicts for the surface's estimate of H's luminance at bandwidth h [m]:
// its RMS over the surface [W/m^2 of (u,v)], h^2 mu2 sqrt(integral((lap H)^2) / area) / 2 for the kernels and
// b sqrt(integral(|grad H|^2) / (12 area)) for the histogram (b = h): Hachisuka, Jarosz and Jensen 2010 ("A
// progressive error estimation framework for photon density estimation") estimate the bias from the Laplacian
// alike. 0 where no level of the pilot measures the roughness significantly (a bias below what the photons can
// show), where photons are too few for a pilot, and for k nearest neighbours, whose radius is its own. At most the
// RMS of H's departure from the surface's mean (the second-order term grows without bound as h nears the surface's
// size, where the estimate tends to that mean: a 1.3 m^2 surface of the office at h = 1.13 m predicted 230% of its
// mean). Leaves out
// what the pilot's interior stencils cannot see: the light curving up into a concave corner at the surface's edge.
double PredictedBias(EstimatorKind kind, Kernel kernel, const PilotHistogram& pilot, float h);

}  // namespace pb
