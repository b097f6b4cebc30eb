// Stage 0: the prepared scene, the one noun every tool, benchmark and test starts from (pbrt-v4's BasicScene:
// one scene, many back ends). Built once from the scene file: the loaded scene (lengths in metres after
// --scale, re-centred about its origin for float precision), its surfaces and their (u,v) charts, each surface's
// region in its chart (for edge correction) less the part other geometry covers, the area lights, the transport plan (which effects the scene calls
// for, baker/0_plan_transport.h) and the Embree ray scene. Nothing in it changes once built.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "baker/0_plan_transport.h"
#include "baker/runtime/stage_clock.h"
#include "estimators/surface_region.h"
#include "mesh/light_file.h"
#include "mesh/lights.h"
#include "mesh/ray_scene.h"
#include "mesh/scene.h"
#include "estimators/surface_cover.h"
#include "mesh/surfaces.h"

namespace pb {

class Log;  // baker/runtime/progress.h

// Each surface's region in its chart, by surface index: the surface less what covers it.
using SurfaceRegions = std::vector<std::unique_ptr<SurfaceRegion>>;
// With a log, its progress is shown.
SurfaceRegions BuildRegions(const SurfaceSet& surfaces, const std::vector<SurfaceCover>& covers,
                            const Log* log = nullptr);
// The covered part's region of each surface that something covers; null for the others.
SurfaceRegions BuildCoveredRegions(const std::vector<SurfaceCover>& covers);

// Per surface, whether its points are tested one by one for lying inside a closed object (PreparedScene::
// enclosureByPoint).
std::vector<bool> PointByPointCovers(const Scene& scene, const SurfaceSet& surfaces,
                                     const std::vector<SurfaceCover>& covers, const CoverSettings& settings);
// What the scene is made from.
struct SceneSettings {
  std::string path;          // OBJ file; its MTL files are found relative to it
  float scale = 1.0f;        // metres per scene unit; range (0, inf), typical 1 or 0.001 (millimetres)
  EffectOverrides effects;   // --effects; none: what the materials call for
  CoverSettings cover;       // the lattice on which covered parts are found (spacing 0: none is)
  std::string lightsPath;    // --lights: a lights file (mesh/light_file.h); empty: SCENE.lights.json if it exists
  double luminousEfficacy = kDefaultLuminousEfficacy;  // [lm/W], for glTF's photometric lights
};

struct PreparedScene {
  Scene scene;
  std::vector<std::string> warnings;  // the loader's "file:line: warning/note: ..." lines, and the re-centring note
  bool warningsShown = false;         // on the log, as they arose (a log that is not quiet)
  SurfaceSet surfaces;
  std::vector<SurfaceCover> covers;  // what other geometry covers of each surface (estimators/surface_cover.h)
  SurfaceRegions regions;            // each surface's open region: its chart triangles less its cover
  SurfaceRegions coveredRegions;     // its cover's region, or null
  // Per surface, whether its points are tested one by one for lying inside a closed object (EnclosedAt,
  // estimators/cover_probe.h): where covers are found (not --no-cover) but no lattice was laid on it (curved,
  // narrower than two spacings), and it emits nothing.
  std::vector<bool> enclosureByPoint;
  std::vector<Light> lights;  // at least one
  TransportPlan plan;
  std::unique_ptr<RayScene> rays;
};

// Loads and prepares the scene, timing each part on `clock` ("load", "surfaces", "lights", "plan", "bvh", "covers",
// "regions").
// InputError for a bad file (with file:line), a scene with no light, or no light that reaches a receiver.
// With a log, each long part's progress is shown (baker/runtime/progress.h); with one that is not quiet, the
// warnings too, as they arise (the loader's before the surfaces are built).
PreparedScene PrepareScene(const SceneSettings& settings, StageClock& clock, const Log* log = nullptr);
// The same from a scene already loaded (tests that build scenes in memory).
PreparedScene PrepareScene(Scene scene, const EffectOverrides& effects, StageClock& clock,
                           const CoverSettings& cover = {}, const Log* log = nullptr);

}  // namespace pb
