// Stage 2: photon hits grouped per surface (the paper's "hits are binned per surface"). Only hits on a
// surface's front side are kept for estimation: that side is the one the display mesh shows. Hits on back sides
// are counted per surface. Arrays are structure-of-arrays in surface order: (u,v) [m] and flux [W].
//
// Words for a photon's light, used alike in every file: its "attenuation" is the dimensionless fraction of its
// emitted flux that it still carries (1 at emission); its "flux" [W] is Phi_l / N_l times that; a light's
// "power" Phi [W] is what all its photons share (Light::Power).
//
// Binning while tracing. Where every surface the kernel can bin is binned whatever its photons' density
// (PlanBinning: a kernel estimate with a fixed h and edge correction, whose node lattices together cost at most a
// quarter of a store of one hit per photon), the photons of those surfaces can be binned onto their nodes as they are traced
// (PhotonBinner, a HitSink of stage 1) and dropped: the bake's memory then stops growing with its photon count.
// The node sums are exact integers (estimators/binned_photons.h), so the estimate is the same, bit for bit, as
// that of the same photons stored and binned here afterwards, on any number of threads. The photons of the other
// surfaces (narrower than 2 h) stay in the store.
#pragma once

#include "baker/runtime/progress.h"

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "baker/1_trace_photons.h"
#include "estimators/binned_photons.h"
#include "estimators/density_estimator.h"
#include "estimators/incident_moments.h"
#include "estimators/photon_map.h"

namespace pb {

// The flux unit of a bake's node sums [W]: the largest channel of the brightest photon at emission, Phi_l / N_l
// over lights with N_l > 0 photons (1 when none has).
double FluxUnit(const std::vector<Rgb>& lightPower, const std::vector<uint64_t>& photonsPerLight);

// Which surfaces are binned on which lattice: per surface, its open domain (0) and its covered one (1,
// estimators/surface_cover.h).
struct BinningPlan {
  bool wide = false;  // every surface that can be is binned (KernelEstimator::Binning::kWide), else by density
  double fluxUnit = 1;  // [W]
  std::vector<uint64_t> photonsPerLight;  // N_l of the bake (estimators/emission.h, AllocatePhotons)
  std::vector<std::array<std::optional<NodeLattice>, 2>> lattices;  // with `wide`: the lattices of binned domains
};

// The plan for a bake of `photons` photons with these estimator settings; fluxUnit from the photons each light
// will emit.
BinningPlan PlanBinning(const PreparedScene& scene, const EstimatorSettings& settings,
                        uint64_t photons);

// What reached surface s, binned or stored: hits on its front and back sides and the front side's flux.
struct SurfaceTally {
  uint64_t frontHits = 0, backHits = 0;
  FluxTally frontFlux;
};

// A surface's node sums, per domain (open, covered), null where that domain is not binned.
using DomainSums = std::array<std::unique_ptr<BinnedPhotons>, 2>;

// Surfaces with fewer front hits than this are sparse: with --h auto they are estimated from photons pooled with
// their sparse neighbours' (estimators/pooled_estimator.h), since their own could not read below 10% noise.
inline constexpr uint64_t kPooledBelowHits = 100;

struct SurfaceBins {
  std::vector<uint32_t> start;  // surface s owns entries [start[s], start[s+1]) of the stored hits
  std::vector<Point2> uv;       // chart position [m]
  std::vector<Rgb> flux;        // [W]
  // With directions (--sh), per stored hit: the unit world direction back toward where the photon came from, and
  // its cosine to the hit triangle's front normal; else empty.
  std::vector<Vector3> from;
  std::vector<float> cosine;
  bool directions = false;  // whether from and cosine are filled
  std::vector<SurfaceTally> tally;  // per surface, every hit (stored or binned while traced)
  double fluxUnit = 1;              // of the tallies and node sums [W]
  bool wide = false;                // BinningPlan::wide
  // Per surface and domain: the photons binned while they were traced (none when they were stored).
  std::vector<DomainSums> traced;
  // With directions, the same for each of their weighted fluxes (estimators/incident_moments.h, MomentFluxes).
  std::array<std::vector<DomainSums>, kMomentFluxes> tracedMoments;

  // The stored front hits of the sparse surfaces (PoolSparseHits), at their positions in the scene [m], with their
  // side's normal and flux [W], in store order; empty until pooled.
  std::vector<MapPhoton> pooled;
  std::vector<uint32_t> pooledTriangles;  // the triangle each pooled hit lies on

  size_t SurfaceCount() const { return start.size() - 1; }
  bool Sparse(size_t s) const { return FrontHits(s) < kPooledBelowHits; }
  uint64_t FrontHits(size_t s) const { return tally[s].frontHits; }
  uint64_t BackHits(size_t s) const { return tally[s].backHits; }
  std::span<const Point2> Uv(size_t s) const { return {uv.data() + start[s], start[s + 1] - start[s]}; }
  std::span<const Rgb> Flux(size_t s) const { return {flux.data() + start[s], start[s + 1] - start[s]}; }
  std::span<const Vector3> From(size_t s) const { return {from.data() + start[s], start[s + 1] - start[s]}; }
  std::span<const float> Cosine(size_t s) const { return {cosine.data() + start[s], start[s + 1] - start[s]}; }
  // The flux [W] that reached surface s's front side.
  Rgb FrontFlux(size_t s) const { return tally[s].frontFlux.ToRgb(fluxUnit); }
  // How surface s's domain d is estimated by a kernel (density_estimator.h).
  KernelBinning BinningOf(size_t s, int d) const { return {wide, fluxUnit, traced.empty() ? nullptr : traced[s][d].get()}; }
  // How weighted flux m of surface s's domain d is estimated: from its node sums when binned while traced, else
  // binned (where the kernel bins) in a unit of its own.
  KernelBinning MomentBinningOf(size_t s, int d, int m) const {
    const auto& sums = tracedMoments[size_t(m)];
    return sums.empty() ? KernelBinning{wide, 0, nullptr} : KernelBinning{wide, fluxUnit, sums[s][d].get()};
  }
};

// Bins the photons of the planned surfaces as they are traced (stage 1 calls Take on its threads) and takes them
// out of their blocks; tallies what it takes.
class PhotonBinner final : public HitSink {
 public:
  // `scene` must outlive the binner; plan.wide must be set. With `directions`, each photon's weighted fluxes
  // (estimators/incident_moments.h, MomentFluxes) are binned too.
  PhotonBinner(const PreparedScene& scene, const BinningPlan& plan, bool directions = false);
  void Take(uint32_t light, HitBlock& hits, size_t from) const override;
  // Replaces every integer sum and count by sum(span) over the processes (baker/distribution.h), after tracing.
  void SumWith(const std::function<void(std::span<int64_t>)>& sum);
  // The node sums and tallies, handed to BinPhotons.
  std::vector<DomainSums> TakeSums() { return std::move(sums_); }
  std::array<std::vector<DomainSums>, kMomentFluxes> TakeMomentSums() { return std::move(momentSums_); }
  std::vector<SurfaceTally> TakeTallies() { return std::move(tallies_); }

 private:
  bool Binned(uint32_t s) const { return sums_[s][0] || sums_[s][1]; }
  // Bins the weighted fluxes of `hit`, of `flux` [W], on surface s's domain at uv.
  void AddMoments(const PhotonHit& hit, uint32_t s, int domain, Point2 uv, Rgb flux) const;
  const PreparedScene& scene_;
  std::vector<Rgb> photonFlux_;  // Phi_l / N_l [W] per light
  double fluxUnit_;
  std::vector<DomainSums> sums_;
  std::array<std::vector<DomainSums>, kMomentFluxes> momentSums_;  // with directions; else empty
  mutable std::vector<SurfaceTally> tallies_;  // of the hits taken; added to atomically
};

// Groups the store's hits per surface. Stable: within a surface, hits keep their trace order, so sums over them
// are reproducible. The flux unit is FluxUnit of the store's photons. With `directionsIn`, the hits' scene, their
// directions too.
SurfaceBins BinPhotons(const SurfaceSet& surfaces, const PhotonStore& hits, const Scene* directionsIn = nullptr);
// The same, with its progress on `log` (two passes over the hits; 10^8 hits take seconds), and with the binner's
// sums and tallies when the photons were binned while traced (then `plan` is the binner's).
SurfaceBins BinPhotons(const SurfaceSet& surfaces, const PhotonStore& hits, const Log& log, const BinningPlan& plan,
                       PhotonBinner* binner = nullptr, const Scene* directionsIn = nullptr);

// Fills bins.pooled from the hits `store` holds on the front of sparse surfaces (SurfaceBins::Sparse).
void PoolSparseHits(const Scene& scene, const SurfaceSet& surfaces, const PhotonStore& store, SurfaceBins& bins);

}  // namespace pb
