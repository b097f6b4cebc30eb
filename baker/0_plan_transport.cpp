#include "baker/0_plan_transport.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "estimators/enum_names.h"
#include "mesh/errors.h"

namespace pb {
namespace {

// Fraction of a photon's flux below which further diffuse bounces are not worth naming in the report.
constexpr double kNegligibleFlux = 1e-3;

// What the scene's materials contain, over the materials some triangle uses.
struct MaterialCensus {
  float largestAlbedo = 0;
  int mirrors = 0, glasses = 0, transmissive = 0;
};

MaterialCensus CountMaterials(const Scene& scene) {
  std::vector<bool> used(scene.materials.size(), false);
  for (const Triangle& t : scene.triangles) used[t.material] = true;
  MaterialCensus c;
  for (size_t i = 0; i < scene.materials.size(); ++i) {
    if (!used[i]) continue;
    const Material& m = scene.materials[i];
    const Rgb textureMaximum = m.albedoTexture >= 0 ? scene.textures[size_t(m.albedoTexture)].maximum : Rgb{1, 1, 1};
    c.largestAlbedo = std::max(c.largestAlbedo, (m.albedo * textureMaximum).Max());
    c.mirrors += m.kind == MaterialClass::kMirror && !m.specular.IsBlack();
    c.glasses += m.kind == MaterialClass::kGlass;
    c.transmissive += m.kind == MaterialClass::kGlass && !m.transmittance.IsBlack();
  }
  return c;
}

// Where the scene's triangles reach farthest: their box, and in each of 26 directions (the axes, the box's edge
// and corner diagonals) the triangle corner farthest along it. Lets PlanLights decide most lights in O(1):
// a plane that the box lies behind has nothing in front; one with an extreme corner of another surface in front
// faces that surface. Only a light that neither decides scans every triangle.
struct SceneExtent {
  Point3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  std::vector<std::pair<uint32_t, int>> extremes;  // (triangle, corner), one per direction

  explicit SceneExtent(const Scene& scene) {
    std::vector<Vector3> directions;
    for (int x = -1; x <= 1; ++x)
      for (int y = -1; y <= 1; ++y)
        for (int z = -1; z <= 1; ++z)
          if (x || y || z) directions.push_back({float(x), float(y), float(z)});
    std::vector<float> farthest(directions.size(), -INFINITY);
    extremes.assign(directions.size(), {0, 0});
    for (uint32_t t = 0; t < scene.triangles.size(); ++t)
      for (int k = 0; k < 3; ++k) {
        const Point3 p = scene.Corner(t, k);
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
        for (size_t d = 0; d < directions.size(); ++d) {
          const float along = Dot(p - Point3{0, 0, 0}, directions[d]);
          if (along > farthest[d]) farthest[d] = along, extremes[d] = {t, k};
        }
      }
  }
  // The box's farthest reach along n, beyond `origin`.
  float Support(Normal3 n, Point3 origin) const {
    const Vector3 a = lo - origin, b = hi - origin;
    return std::max(a.x * n.x, b.x * n.x) + std::max(a.y * n.y, b.y * n.y) + std::max(a.z * n.z, b.z * n.z);
  }
};

// True unless `light` is a planar area light and every vertex of every other surface lies on or behind its plane.
// Lights that are not surfaces are assumed to reach something.
bool ReachesAnyReceiver(const Scene& scene, const SurfaceSet& surfaces, const SceneExtent& extent,
                        const Light& light, float tolerance) {
  if (!light.IsArea()) return true;
  const Surface& surface = surfaces.surfaces[light.surface];
  if (!surface.planar) return true;  // conservative: a curved light is assumed to see something
  const SurfaceChart& plane = surface.chart;
  const auto inFront = [&](uint32_t t, int k) {
    return surfaces.surfaceOfTriangle[t] != light.surface &&
           Dot(scene.Corner(t, k) - plane.origin, plane.frame.n) > tolerance;
  };
  if (extent.Support(plane.frame.n, plane.origin) <= tolerance) return false;
  for (const auto& [t, k] : extent.extremes)
    if (inFront(t, k)) return true;
  for (uint32_t t = 0; t < scene.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k)
      if (inFront(t, k)) return true;
  return false;
}

EffectDecision Decide(bool needed, std::string whyOn, std::string whyOff) {
  return needed ? EffectDecision{true, false, std::move(whyOn)} : EffectDecision{false, false, std::move(whyOff)};
}

EffectDecision DecideInterreflection(float largestAlbedo, uint32_t bounces) {
  if (largestAlbedo >= 1.0f)
    return {true, false, "largest Kd is 1: no bounce is negligible; paths end only by escaping"};
  return Decide(largestAlbedo > 0,
                fmt::format("largest Kd {:.2f}: {} bounces carry all but 0.1% of the flux", largestAlbedo, bounces),
                "every surface is black (Kd 0): photons stop at the first surface they reach");
}

void ApplyOverrides(TransportPlan& plan, const EffectOverrides& overrides) {
  for (Effect e : kAllEffects) {
    const std::optional<bool>& forced = overrides.forced[size_t(e)];
    EffectDecision& d = plan.effects[size_t(e)];
    if (!forced || *forced == d.simulated) continue;
    d.reason = fmt::format("{} by --effects (the scene alone: {})", *forced ? "forced on" : "forbidden", d.reason);
    d.simulated = *forced;
    d.overridden = true;
  }
}

// Blender renders emissive faces from both sides, so a lamp modelled facing away looks right there and is dark here.
constexpr const char* kFlipHint =
    ". A light emits from its front side only, the side its corners wind counter-clockwise about; Blender shows "
    "emissive faces from both sides. Flip the light's normals (Blender: Edit Mode, Mesh > Normals > Flip) and export "
    "again";

void PlanLights(TransportPlan& plan, const Scene& scene, const SurfaceSet& surfaces,
                const std::vector<Light>& lights) {
  const float tolerance = 1e-5f * scene.LargestCoordinate();
  const SceneExtent extent(scene);
  int reaching = 0;
  for (const Light& light : lights) {
    const bool reaches = ReachesAnyReceiver(scene, surfaces, extent, light, tolerance);
    reaching += reaches;
    plan.lightReaches.push_back(reaches);
    plan.lightNotes.push_back(reaches ? "" : "no photons: every other surface lies behind its emitting side" +
                                                 std::string(kFlipHint));
  }
  if (reaching == 0)
    throw InputError(scene.path, 0, "no light reaches any surface: every light faces away from the rest of the scene" +
                                        std::string(kFlipHint));
  plan.effects[size_t(Effect::kDirect)] = {true, false, fmt::format("{} of {} lights reach a surface", reaching, lights.size())};
}

}  // namespace

std::string EffectName(Effect e) {
  switch (e) {
    case Effect::kDirect: return "direct";
    case Effect::kInterreflection: return "interreflection";
    case Effect::kReflection: return "reflection";
    case Effect::kRefraction: return "refraction";
    case Effect::kCaustics: return "caustics";
  }
  return "?";
}

EffectOverrides ParseEffectOverrides(std::string_view text) {
  EffectOverrides o;
  if (text == "auto") return o;
  if (text == "all") {
    for (auto& f : o.forced) f = true;
    return o;
  }
  for (size_t start = 0; start <= text.size();) {
    const size_t comma = std::min(text.find(',', start), text.size());
    std::string_view item = text.substr(start, comma - start);
    start = comma + 1;
    const bool on = item.empty() || item[0] != '-';
    if (!item.empty() && (item[0] == '-' || item[0] == '+')) item.remove_prefix(1);
    const std::optional<Effect> e = ParseName(item, kAllEffects, EffectName);
    if (!e)
      throw InputError("--effects", 0,
                       fmt::format("unknown effect '{}'; use auto, all, or a list of NAME, +NAME, -NAME with NAME one "
                                   "of: {}", item, JoinNames(kAllEffects, EffectName)));
    if (*e == Effect::kDirect && !on) throw InputError("--effects", 0, "direct light cannot be turned off");
    o.forced[size_t(*e)] = on;
  }
  return o;
}

std::string TransportPlan::Describe(Effect e) const {
  const EffectDecision& d = effects[size_t(e)];
  return (d.simulated ? "simulated: " : "skipped: ") + d.reason;
}

TransportPlan PlanTransport(const Scene& scene, const SurfaceSet& surfaces, const std::vector<Light>& lights,
                            const EffectOverrides& overrides) {
  TransportPlan plan;
  PlanLights(plan, scene, surfaces, lights);
  const MaterialCensus c = CountMaterials(scene);
  plan.largestAlbedo = c.largestAlbedo;
  plan.specularMaterials = c.mirrors + c.glasses > 0;
  if (c.largestAlbedo > 0 && c.largestAlbedo < 1)
    plan.significantBounces = uint32_t(std::ceil(std::log(kNegligibleFlux) / std::log(double(c.largestAlbedo))));
  plan.effects[size_t(Effect::kInterreflection)] = DecideInterreflection(c.largestAlbedo, plan.significantBounces);
  plan.effects[size_t(Effect::kReflection)] =
      Decide(c.mirrors + c.glasses > 0, fmt::format("{} mirror and {} glass materials", c.mirrors, c.glasses),
             "no mirror or glass material");
  plan.effects[size_t(Effect::kRefraction)] =
      Decide(c.transmissive > 0, fmt::format("{} transmissive glass materials", c.transmissive),
             "no transmissive material");
  ApplyOverrides(plan, overrides);  // caustics follow the specular effects as the user left them
  const bool specular = plan.On(Effect::kReflection) || plan.On(Effect::kRefraction);
  plan.effects[size_t(Effect::kCaustics)] =
      Decide(specular, "light reaching diffuse surfaces by mirrors or glass",
             c.mirrors + c.glasses > 0 ? "reflection and refraction are off" : "no mirror or glass surface");
  EffectOverrides causticsOnly;
  causticsOnly.forced[size_t(Effect::kCaustics)] = overrides.forced[size_t(Effect::kCaustics)];
  ApplyOverrides(plan, causticsOnly);
  return plan;
}

}  // namespace pb
