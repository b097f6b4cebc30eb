#include "baker/diagnostics.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "baker/5_write_ply.h"
#include "baker/photons/progressive.h"
#include "baker/tone_map.h"

namespace pb {

std::vector<std::string> BandwidthWarnings(const IrradianceField& field, const SurfaceBins& bins,
                                           const EstimatorSettings& estimator) {
  const PreparedScene& p = field.Prepared();
  std::vector<std::string> warnings;
  if (estimator.kind == EstimatorKind::kNearest || !estimator.bandwidth) return warnings;
  for (uint32_t s = 0; s < p.surfaces.surfaces.size(); ++s) {
    const double area = p.surfaces.surfaces[s].area;
    const double open = area - (p.coveredRegions[s] ? p.coveredRegions[s]->Area() : 0.0);
    if (bins.FrontHits(s) == 0 || open <= 0.01 * area) continue;
    const double spacing = std::sqrt(open / double(bins.FrontHits(s)));
    if (field.Bandwidth(s) >= 0.5 * spacing) continue;
    warnings.push_back(fmt::format("{}: warning: surface {} ({}): h = {:.3g} m is below the photon spacing "
                                   "({:.3g} m): most vertices see no photon and the photons' H reads 0 there; raise --h or --photons",
                                   p.scene.path, s, p.scene.materials[p.surfaces.surfaces[s].material].name,
                                   field.Bandwidth(s), spacing));
  }
  return warnings;
}

namespace {

// The unlit lights named one by one, and the back-lit surfaces.
constexpr size_t kNamedUnlit = 3;

// "the light of material 'NAME' (P W" and what follows in `rest`, then ")".
std::string UnlitLightName(const PreparedScene& scene, const Light& light, const std::string& rest = "") {
  const std::string which = light.IsArea() ? "the light of material" : fmt::format("the {} light", LightKindName(light.kind));
  return fmt::format("{} '{}' ({:.3g} W{})", which, LightName(scene.scene, light), light.Power().Mean(), rest);
}

}  // namespace

std::vector<std::string> UnlitLightWarnings(const PreparedScene& scene, const PhotonStore& photons, bool sampled) {
  double total = 0, unlitFlux = 0, weakest = INFINITY;
  std::vector<size_t> unlit;
  for (size_t l = 0; l < scene.lights.size(); ++l) {
    if (!scene.plan.lightReaches[l]) continue;
    const double power = scene.lights[l].Power().Mean();
    total += power;
    if (photons.emitted[l] > 0 || !(power > 0)) continue;  // a light that emits nothing misses nothing
    unlit.push_back(l), unlitFlux += power, weakest = std::min(weakest, power);
  }
  const std::string missing = sampled ? "interreflected light is missing (the direct light is sampled)" : "light is missing";
  std::vector<std::string> warnings;
  if (unlit.size() <= kNamedUnlit) {
    for (size_t l : unlit)
      warnings.push_back(fmt::format("{}: warning: {} got no photon, so its {}; raise --photons to at least {:.0f}",
                                     scene.scene.path, UnlitLightName(scene, scene.lights[l], fmt::format(" of {:.3g} W", total)),
                                     missing, std::ceil(total / scene.lights[l].Power().Mean())));
    return warnings;
  }
  std::stable_sort(unlit.begin(), unlit.end(), [&](size_t a, size_t b) {
    return scene.lights[a].Power().Mean() > scene.lights[b].Power().Mean();
  });
  std::string brightest;
  for (size_t i = 0; i < kNamedUnlit; ++i)  // with its index: many lights share a material's name
    brightest += (i ? ", " : "") + UnlitLightName(scene, scene.lights[unlit[i]], fmt::format(", light {}", unlit[i]));
  warnings.push_back(fmt::format("{}: warning: {} of {} lights got no photon: {:.3g} W of {:.3g} W ({:.2g}% of the "
                                 "flux), so their {}; the brightest: {}; raise --photons to at least {:.0f} for every "
                                 "light to get one", scene.scene.path, unlit.size(), scene.lights.size(), unlitFlux,
                                 total, 100 * unlitFlux / total, missing, brightest, std::ceil(total / weakest)));
  return warnings;
}

namespace {

// Noise that shows as blotches: above 2% of the displayed light, about 5 of 255 grey levels.
constexpr double kVisibleNoise = 0.02;

// Rounded up to two significant digits: 3,456,789 -> 3,500,000.
uint64_t TwoDigits(double x) {
  const double unit = std::pow(10.0, std::max(0.0, std::floor(std::log10(std::max(x, 1.0))) - 1));
  return uint64_t(std::ceil(x / unit) * unit);
}

}  // namespace

std::vector<std::string> ExposureWarnings(std::optional<float> exposure, const BakedMesh& baked) {
  if (!exposure) return {};
  bool black = true, white = true, lit = false;
  for (size_t v = 0; v < baked.mesh.VertexCount(); ++v) {
    const Rgb radiance = baked.Radiance(v);
    if (!(radiance.Max() > 0)) continue;
    const std::array<uint8_t, 3> shown = ToneMap(radiance, *exposure);
    lit = true;
    black = black && shown == std::array<uint8_t, 3>{0, 0, 0};
    const float channels[3] = {radiance.r, radiance.g, radiance.b};
    for (int c = 0; c < 3; ++c) white = white && (shown[c] == 255 || !(channels[c] > 0));
  }
  if (!lit || !(black || white)) return {};
  return {fmt::format("--exposure {}: warning: the display colours show every lit vertex {}; the automatic exposure "
                      "would be {:.4g}", *exposure, black ? "black" : "white", DisplayExposure(baked, std::nullopt))};
}

std::vector<std::string> DarkBakeWarnings(const std::string& scenePath, const BakedMesh& baked) {
  if (std::any_of(baked.irradiance.begin(), baked.irradiance.end(), [](Rgb h) { return h.Max() > 0; })) return {};
  return {fmt::format("{}: warning: every vertex reads 0 W/m^2: no light reached the front side of any surface (a "
                      "light behind or in the plane of the surfaces, a sun from below); the outputs are black",
                      scenePath)};
}

namespace {
// The back hits that make a surface lit only from behind.
constexpr uint64_t kBackLitHits = 20;

// The largest kNamedUnlit of `surfaces`, each "surface S ('MATERIAL', A m^2" and what `more(s)` adds, then ")".
template <typename More>
std::string TheLargest(const PreparedScene& scene, std::vector<uint32_t> surfaces, More more) {
  std::stable_sort(surfaces.begin(), surfaces.end(), [&](uint32_t a, uint32_t b) {
    return scene.surfaces.surfaces[a].area > scene.surfaces.surfaces[b].area;
  });
  std::string named;
  for (size_t i = 0; i < std::min(surfaces.size(), kNamedUnlit); ++i) {
    const Surface& surface = scene.surfaces.surfaces[surfaces[i]];
    named += fmt::format("{}surface {} ('{}', {:.3g} m^2{})", i ? ", " : "", surfaces[i],
                         scene.scene.materials[surface.material].name, surface.area, more(surfaces[i]));
  }
  return named;
}
}  // namespace

std::vector<std::string> BackLitWarnings(const PreparedScene& scene, const SurfaceBins& bins, const BakedMesh& baked) {
  std::vector<bool> lit(bins.SurfaceCount(), false);
  for (size_t v = 0; v < baked.mesh.VertexCount(); ++v)
    if (baked.irradiance[v].Max() > 0) lit[baked.mesh.surface[v]] = true;
  std::vector<uint32_t> dark;
  double area = 0;
  uint64_t hits = 0;
  for (uint32_t s = 0; s < bins.SurfaceCount(); ++s) {
    if (lit[s] || bins.BackHits(s) < kBackLitHits || bins.FrontHits(s) > 0) continue;
    dark.push_back(s), area += scene.surfaces.surfaces[s].area, hits += bins.BackHits(s);
  }
  if (dark.empty()) return {};
  const std::string named = TheLargest(scene, dark, [&](uint32_t s) { return fmt::format(", {} back hits", bins.BackHits(s)); });
  return {fmt::format("{}: warning: {} surface{} of {:.3g} m^2 in all lit only from behind: {} photons reached the "
                      "back and none the front, so the front reads black; its faces may be wound the wrong way round "
                      "(the front is the side from which the corners run counter-clockwise); the largest: {}",
                      scene.scene.path, dark.size(), dark.size() == 1 ? "" : "s", area, hits, named)};
}

namespace {
// A surface whose vertices show less than this share of the light that its photons brought reads dark. (At a half,
// the side of a block standing on a floor warned: its two lower corners lie in the dark of the contact line.)
constexpr double kShownShare = 0.25;

// Per surface, the mean H luminance its vertices show, interpolated across its faces [W/m^2]; NaN where it has no
// face in the mesh (--only left it out).
std::vector<double> ShownIrradiance(const BakedMesh& baked, size_t surfaces) {
  const std::vector<double> area = VertexAreas(baked.mesh);
  std::vector<double> shown(surfaces, 0.0), total(surfaces, 0.0);
  for (size_t v = 0; v < baked.mesh.VertexCount(); ++v) {
    const uint32_t s = baked.mesh.surface[v];
    shown[s] += area[v] * Luminance(baked.irradiance[v]), total[s] += area[v];
  }
  for (size_t s = 0; s < surfaces; ++s) shown[s] = total[s] > 0 ? shown[s] / total[s] : NAN;
  return shown;
}
}  // namespace

std::vector<std::string> MissedLightWarnings(const PreparedScene& scene, const SurfaceBins& bins, const BakedMesh& baked) {
  const std::vector<double> shown = ShownIrradiance(baked, bins.SurfaceCount());
  std::vector<uint32_t> dark;
  double area = 0;
  for (uint32_t s = 0; s < bins.SurfaceCount(); ++s) {
    const double brought = Luminance(bins.FrontFlux(s)) / scene.surfaces.surfaces[s].area;
    if (bins.FrontHits(s) < kPooledBelowHits || !(shown[s] < kShownShare * brought)) continue;
    dark.push_back(s), area += scene.surfaces.surfaces[s].area;
  }
  if (dark.empty()) return {};
  const std::string named = TheLargest(scene, dark, [&](uint32_t s) {
    return fmt::format(": its vertices {:.3g} W/m^2, its photons {:.3g}", shown[s],
                       Luminance(bins.FrontFlux(s)) / scene.surfaces.surfaces[s].area);
  });
  return {fmt::format("{}: warning: {} surface{} of {:.3g} m^2 in all show less than a quarter of the light their photons "
                      "brought: their vertices sit where little of it falls (in corners under other geometry, at the "
                      "ends of long faces), and the faces between them are shown as dark as their corners; --refine "
                      "adds vertices where the light is (with --max-vertices above this mesh's {}), or --maps writes "
                      "each surface's light as a texture; the largest: {}",
                      scene.scene.path, dark.size(), dark.size() == 1 ? "" : "s", area, baked.mesh.VertexCount(), named)};
}

std::vector<std::string> VisibleNoiseWarnings(const VisibleNoise& in) {
  if (in.noise <= kVisibleNoise || in.rounds) return {};
  const DirectSettings& direct = in.direct;
  const bool reference = in.referencePaths > 0;
  const uint32_t samples = reference ? in.referencePaths : direct.mode == DirectLight::kSampled ? direct.samples : 0;
  const uint64_t emitted = in.emitted;
  const NoiseRemedy r = RemedyForNoise(in.baked, kVisibleNoise, emitted, samples);
  std::vector<std::string> remedies;
  if (!reference && r.photons > emitted)
    remedies.push_back(fmt::format("--photons {}", TwoDigits(1.05 * double(r.photons))));
  // With --direct-noise the points' own noise falls by sqrt(factor) when their target does; and at most half the
  // visible noise, as the pilot's noisy estimate leaves the 95th percentile above the target (1.3x it measured).
  const bool adaptive = !reference && direct.mode == DirectLight::kSampled && direct.noise > 0;
  if (r.pointSamples > samples && adaptive)
    remedies.push_back(fmt::format("--direct-noise {:.2g}", std::min(direct.noise / std::sqrt(1.05 * r.pointSamples / samples),
                                                                  kVisibleNoise / 2)));
  else if (r.pointSamples > samples)
    remedies.push_back(fmt::format("{} {}", reference ? "--reference" : "--direct-samples",
                                   TwoDigits(1.05 * r.pointSamples)));
  // No count of photons or shadow rays brings it under: what is left is the paths gathered in narrow gaps, which
  // neither lowers (RemedyForNoise leaves their noise as it is).
  const std::string remedy =
      remedies.empty()
          ? fmt::format("no count of photons or shadow rays alone brings it under {:.0f}%: the paths gathered in "
                        "narrow gaps hold it (raise --gap-paths)", 100 * kVisibleNoise)
          : fmt::format("about {} would bring it under {:.0f}%{}",
                        remedies.size() == 1 ? remedies[0] : remedies[0] + " and " + remedies[1], 100 * kVisibleNoise,
                        reference
                            ? ""
                            : fmt::format(" (or --target-noise {} finds the photons itself)", kVisibleNoise));
  return {fmt::format("{}: warning: the bake's noise is {:.1f}% (the 95th percentile of the displayed light's "
                      "predicted relative error), enough to show as blotches; {}", in.scenePath, 100 * in.noise, remedy)};
}

}  // namespace pb
