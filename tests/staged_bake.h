// A bake run stage by stage up to the estimate (trace, bin, the irradiance field, the base mesh), for tests that
// refine the mesh or evaluate the field at chosen points.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "baker/2_bin_photons.h"
#include "baker/3_irradiance_field.h"
#include "baker/4_refine_mesh.h"
#include "baker/5_write_ply.h"
#include "mesh/split_mesh.h"
#include "tests/traced_scene.h"

namespace pb::test {

// The irradiance field of `bins` (h chosen per surface where settings.bandwidth is none).
inline IrradianceField FieldOf(const PreparedScene& scene, const SurfaceBins& bins, const EstimatorSettings& settings) {
  StageClock clock;
  return BuildIrradianceField(scene, bins, {.estimator = settings}, clock);
}

struct StagedBake {
  TracedScene traced;
  PhotonStore hits;
  SurfaceBins bins;
  IrradianceField field;
  BakedMesh base;
  float exposure;

  // exposure: the display exposure refinement measures in; unset = the PLY's automatic one.
  StagedBake(const std::string& objPath, uint64_t photons, const EstimatorSettings& settings,
             std::optional<float> displayExposure = std::nullopt, uint64_t seed = 1)
      : traced(objPath),
        hits(traced.Trace(photons, seed)),
        bins(BinPhotons(traced.surfaces, hits)),
        field(FieldOf(traced, bins, settings)),
        base(EstimateIrradiance(field, SplitBySurface(traced.scene, traced.surfaces), Log(true))),
        exposure(DisplayExposure(base, displayExposure)) {}

  RefinedMesh Refine(const RefineSettings& settings) const {
    return RefineMesh({field, base.mesh, exposure}, settings, Log(true));
  }
  BakedMesh Refine(const RefineSettings& settings, RefineReport& report) const {
    RefinedMesh refined = Refine(settings);
    report = std::move(refined.report);
    return std::move(refined.mesh);
  }

  // The light of surface s at a point of a planar surface, straight from the field.
  SurfaceLight LightOnPlane(uint32_t s, Point3 p) const {
    SurfacePoint point;
    point.surface = s;
    point.position = p;
    point.normal = traced.surfaces.surfaces[s].chart.frame.n;
    point.uv = traced.surfaces.surfaces[s].chart.ToUv(p);
    return field.Light(point);
  }
};

}  // namespace pb::test
