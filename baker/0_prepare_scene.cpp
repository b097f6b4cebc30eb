#include "baker/0_prepare_scene.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "baker/runtime/progress.h"
#include "estimators/warps.h"
#include "mesh/errors.h"
#include "mesh/color.h"

#include <algorithm>
#include <optional>
#include "mesh/scene_file.h"

namespace pb {
namespace {

std::vector<Triangle2> ChartTriangles(const SurfaceSet& surfaces, const Surface& surface) {
  std::vector<Triangle2> triangles;
  triangles.reserve(surface.triangles.size());
  for (uint32_t t : surface.triangles) triangles.push_back(surfaces.cornerUv[t]);
  return triangles;
}

std::string RecentringNote(const Scene& scene) {
  return fmt::format("{}: note: the scene lies far from the origin; it is traced about ({:.6g}, {:.6g}, {:.6g}) m "
                     "for float precision, and written back in world coordinates",
                     scene.path, scene.origin[0], scene.origin[1], scene.origin[2]);
}

// A hint when the scene's size suggests it was modelled in other units than metres: over 500 m across (the
// diagonal of its box), with the --scale that millimetres, centimetres or inches would need; under 5 mm, with the
// power of ten that brings it to metres (a scene shrunk on export). Empty when its size is plausible in metres.
std::string UnitsNote(const Scene& scene) {
  const double across = scene.Diagonal();
  if (across > 500)
    return fmt::format("{}: warning: the scene is {:.3g} m across; lengths are read as metres (and --h is in metres): "
                       "if it was modelled in millimetres, centimetres or inches, bake with --scale 0.001, 0.01 or "
                       "0.0254 (it would be {:.3g}, {:.3g} or {:.3g} m across)",
                       scene.path, across, across * 1e-3, across * 1e-2, across * 0.0254);
  if (!(across > 0 && across < 5e-3)) return {};
  const double up = std::pow(10.0, std::ceil(-std::log10(across)));
  return fmt::format("{}: warning: the scene is {:.3g} m across; lengths are read as metres (and --h is in metres): "
                     "if it was shrunk on export or modelled in larger units, bake with --scale {:g} (it would be "
                     "{:.3g} m across); in a scene this small a triangle under about 1e-19 m^2 is lost to float and "
                     "skipped", scene.path, across, up, across * up);
}

// Largest flux of one light [W]: float ends at 3.4e38, and fluxes are summed over lights and multiplied by
// exposures, so a light must leave room below it.
// A light below the least flux emits nothing the bake could carry: its photons' power would underflow float.
constexpr double kMaxLightFlux = 1e30, kMinLightFlux = 1e-30;

void RequireLight(const Scene& scene, const std::vector<Light>& lights) {
  if (lights.empty())
    throw InputError(scene.path, 0, fmt::format("scene has no light: no face uses a material with Ke > 0, and no light "
                                                "is declared{}", scene.degenerateTrianglesSkipped == 0 ? ""
                                                : fmt::format(" (of its faces, {} were skipped as zero-area, in a scene "
                                                              "{:.3g} m across: a light among them is lost with them)",
                                                              scene.degenerateTrianglesSkipped, scene.Diagonal())));
  const auto flux = [](const Light& light) { return double(light.Power().Max()); };
  if (std::none_of(lights.begin(), lights.end(), [&](const Light& light) { return flux(light) >= kMinLightFlux; }))
    throw InputError(scene.path, 0, fmt::format("the scene's lights emit nothing: each of its {} emits less than {:.0e} "
                                                "W (its intensity or Ke times its colour)", lights.size(), kMinLightFlux));
  for (const Light& light : lights) {
    const Rgb power = light.Power();
    const double flux = std::max({power.r, power.g, power.b});
    if (flux <= kMaxLightFlux) continue;
    if (light.IsArea())
      throw InputError(scene.path, 0, fmt::format("the light of material '{}' emits {:.3g} W (pi Ke A, with A = {:.4g} "
                                                  "m^2), above the {:.0e} W a light may have; lower its Ke",
                                                  LightName(scene, light), flux, light.area, kMaxLightFlux));
    throw InputError(light.analytic.source, 0, fmt::format("the {} light '{}' emits {:.3g} W, above the {:.0e} W a "
                                                           "light may have; lower its intensity", LightKindName(light.kind),
                                                           LightName(scene, light), flux, kMaxLightFlux));
  }
}

// A scene refused after it loaded ("no light") is often explained by what the loader defaulted (a material
// library not found, a material no library defines): the error carries the loader's first warnings.
InputError WithLoaderWarnings(const InputError& e, const std::vector<std::string>& warnings) {
  if (warnings.empty()) return e;
  constexpr size_t kShown = 5;
  std::string message = e.message() + "; the loader warned:";
  for (size_t i = 0; i < warnings.size() && i < kShown; ++i) message += "\n  " + warnings[i];
  if (warnings.size() > kShown) message += fmt::format("\n  ... and {} more", warnings.size() - kShown);
  return InputError(e.file(), e.line(), message);
}

}  // namespace

SurfaceRegions BuildRegions(const SurfaceSet& surfaces, const std::vector<SurfaceCover>& covers, const Log* log) {
  SurfaceRegions regions(surfaces.surfaces.size());
  std::optional<Progress> progress;
  if (log != nullptr) progress.emplace(*log, "surface regions", regions.size());
  tbb::parallel_for(size_t(0), regions.size(), [&](size_t s) {
    regions[s] = std::make_unique<SurfaceRegion>(ChartTriangles(surfaces, surfaces.surfaces[s]), covers[s].Pieces());
    if (progress) progress->Advance(1);
  });
  return regions;
}

std::vector<bool> PointByPointCovers(const Scene& scene, const SurfaceSet& surfaces,
                                     const std::vector<SurfaceCover>& covers, const CoverSettings& settings) {
  std::vector<bool> tested(covers.size(), false);
  if (!(settings.spacing > 0)) return tested;
  for (size_t s = 0; s < covers.size(); ++s)
    tested[s] = covers[s].ProbedPoints() == 0 && !scene.materials[surfaces.surfaces[s].material].IsEmissive();
  return tested;
}

SurfaceRegions BuildCoveredRegions(const std::vector<SurfaceCover>& covers) {
  SurfaceRegions regions(covers.size());
  for (size_t s = 0; s < covers.size(); ++s)
    if (!covers[s].Empty()) regions[s] = std::make_unique<SurfaceRegion>(covers[s].Pieces());
  return regions;
}

namespace {

// Turns each portal to face into the scene. From a point just off each side of its centre, kPortalProbes fixed
// directions about that side's normal (CosineSpiralDirection): the side whose probes meet more geometry is its inside
// (a window's room closes round it; its outside opens to the sky). A portal whose corners ran the other way is
// turned (u and v swapped: the same parallelogram), with a warning naming the lights file: wound clockwise seen
// from inside, the daylight office read -6.7% of its mean H and 81% of its photons escaped (issue 60).
constexpr int kPortalProbes = 16;
std::vector<std::string> OrientPortals(Scene& scene, const RayScene& rays) {
  std::vector<std::string> warnings;
  for (size_t i = 0; i < scene.portals.size(); ++i) {
    Portal& portal = scene.portals[i];
    const Point3 centre = portal.origin + (portal.u + portal.v) * 0.5f;
    const float offset = 1e-4f * (Length(portal.u) + Length(portal.v));
    const auto met = [&](Vector3 side) {
      const Frame frame = Frame::FromNormal(NormalFrom(side));
      int n = 0;
      for (int k = 0; k < kPortalProbes; ++k)
        n += rays.Occluded(centre + side * offset, frame.ToWorld(CosineSpiralDirection(k, kPortalProbes)));
      return n;
    };
    const Vector3 in = AsVector(portal.Inward());
    const int front = met(in), back = met(in * -1.0f);
    if (front >= back) continue;
    std::swap(portal.u, portal.v);
    warnings.push_back(fmt::format("{}: warning: portal {} faced out of the scene (its corners ran clockwise seen from "
                                   "inside: {} of {} probes met geometry in front of it, {} behind); it is turned to "
                                   "face in", scene.lightsFile.empty() ? scene.path : scene.lightsFile, i, front,
                                   kPortalProbes, back));
  }
  return warnings;
}

}  // namespace

PreparedScene PrepareScene(Scene scene, const EffectOverrides& effects, StageClock& clock, const CoverSettings& cover,
                           const Log* log) {
  PreparedScene p{std::move(scene)};
  if (p.scene.Recentred()) p.warnings.push_back(RecentringNote(p.scene));
  if (const std::string note = UnitsNote(p.scene); !note.empty()) p.warnings.push_back(note);
  p.warningsShown = log != nullptr && !log->Quiet();
  if (p.warningsShown) log->Warnings(p.warnings);
  p.surfaces = clock.Time("surfaces", [&] {
    std::unique_ptr<Progress> progress;
    return BuildSurfaces(p.scene, {}, ShowProgress(log, "surfaces (triangle passes)", progress));
  });
  p.rays = clock.Time("bvh", [&] {
    std::unique_ptr<Progress> progress;
    return std::make_unique<RayScene>(p.scene, ShowProgress(log, "build bvh (thousandths)", progress));
  });
  const std::vector<std::string> turned = OrientPortals(p.scene, *p.rays);
  if (p.warningsShown) log->Warnings(turned);
  p.warnings.insert(p.warnings.end(), turned.begin(), turned.end());
  p.lights = clock.Time("lights", [&] { return CollectLights(p.scene, p.surfaces); });
  RequireLight(p.scene, p.lights);
  p.plan = clock.Time("plan", [&] { return PlanTransport(p.scene, p.surfaces, p.lights, effects); });
  p.covers = clock.Time("covers", [&] {
    std::unique_ptr<Progress> progress;
    return FindCovers(p.scene, p.surfaces, *p.rays, cover, ShowProgress(log, "find covers", progress));
  });
  p.regions = clock.Time("regions", [&] { return BuildRegions(p.surfaces, p.covers, log); });
  p.coveredRegions = BuildCoveredRegions(p.covers);
  p.enclosureByPoint = PointByPointCovers(p.scene, p.surfaces, p.covers, cover);
  return p;
}


PreparedScene PrepareScene(const SceneSettings& settings, StageClock& clock, const Log* log) {
  LoadedScene loaded = clock.Time("load", [&] {
    std::unique_ptr<Progress> progress;
    LoadedScene l = LoadScene(settings.path, {settings.scale, settings.luminousEfficacy, ShowProgress(log, "read scene (bytes)", progress)});
    AddLightsFile(l.scene, settings.lightsPath);
    return l;
  });
  const bool show = log != nullptr && !log->Quiet();
  if (show) log->Warnings(loaded.warnings);
  try {
    PreparedScene p = PrepareScene(std::move(loaded.scene), settings.effects, clock, settings.cover, log);
    p.warnings.insert(p.warnings.begin(), loaded.warnings.begin(), loaded.warnings.end());
    return p;
  } catch (const InputError& e) {
    throw show ? e : WithLoaderWarnings(e, loaded.warnings);  // shown just above, or carried by the error
  }
}

}  // namespace pb
