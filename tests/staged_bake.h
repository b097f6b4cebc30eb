// A bake run stage by stage up to the estimate (trace, bin, regions, bandwidths, estimators, the base mesh), for
// tests that refine the mesh or evaluate the estimator at chosen points.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "baker/2_bin_photons.h"
#include "baker/3_estimate_irradiance.h"
#include "baker/4_refine_mesh.h"
#include "baker/5_write_ply.h"
#include "mesh/split_mesh.h"
#include "tests/traced_scene.h"

namespace pb::test {

struct StagedBake {
  TracedScene traced;
  PhotonHits hits;
  SurfaceBins bins;
  SurfaceRegions regions;
  std::vector<float> bandwidths;
  SurfaceEstimators estimators;
  BakedMesh base;
  float exposure;

  // exposure: the display exposure refinement measures in; unset = the PLY's automatic one.
  StagedBake(const std::string& objPath, uint64_t photons, const EstimatorSettings& settings,
             std::optional<float> displayExposure = std::nullopt, uint64_t seed = 1)
      : traced(objPath),
        hits(traced.Trace(photons, seed)),
        bins(BinPhotons(traced.surfaces, hits)),
        regions(BuildRegions(traced.surfaces)),
        bandwidths(SurfaceBandwidths(regions, bins, settings, false)),
        estimators(BuildEstimators(regions, bins, settings, bandwidths)),
        base(EstimateIrradiance(traced.scene, traced.surfaces, estimators, SplitBySurface(traced.scene, traced.surfaces),
                                Log(true))),
        exposure(DisplayExposure(base, displayExposure)) {}

  BakedMesh Refine(const RefineSettings& settings, RefineReport& report) const {
    return RefineMesh({traced.scene, traced.surfaces, estimators, bandwidths, base.mesh, exposure}, settings, report,
                      Log(true));
  }

  // The light of surface s at a point of a planar surface, straight from its estimator.
  PointLight LightOnPlane(uint32_t s, Point3 p) const {
    return LightAt(traced.scene, traced.surfaces, estimators, s, traced.surfaces.surfaces[s].chart.ToUv(p), {}, 1.0f);
  }
};

}  // namespace pb::test
