#include "estimators/scatter.h"

namespace pb {
namespace {

ScatterSample ScatterMirror(const Material& m, Rgb albedo, Vector3 wo, Normal3 side, float uEvent, Point2 uDirection) {
  float pDiffuse = albedo.Max(), pMirror = m.specular.Max();
  if (const float total = pDiffuse + pMirror; total > 1.0f) {
    pDiffuse /= total;
    pMirror /= total;
  }
  ScatterSample s;
  s.expectedAbsorbed = Rgb{1, 1, 1} - albedo - m.specular;
  if (uEvent < pDiffuse) {
    s.event = ScatterEvent::kDiffuse;
    s.wi = SampleLambertian(albedo, side, uDirection).wi;
    s.weight = albedo / pDiffuse;
  } else if (uEvent < pDiffuse + pMirror) {
    s.event = ScatterEvent::kMirror;
    s.wi = Reflect(wo, side);
    s.weight = m.specular / pMirror;
  }
  return s;
}

ScatterSample ScatterGlass(const Material& m, Vector3 wo, Normal3 side, bool entering, TransportMode mode,
                           float uEvent) {
  const float eta = entering ? m.ior : 1.0f / m.ior;  // n_t / n_i
  const float cosI = std::clamp(Dot(wo, side), 0.0f, 1.0f);
  const std::optional<float> cosT = RefractedCosine(cosI, eta);
  const float fresnel = cosT ? FresnelDielectric(cosI, eta) : 1.0f;
  const float transmit = m.transmittance.Max();
  ScatterSample s;
  s.expectedAbsorbed = (Rgb{1, 1, 1} - m.transmittance) * (1.0f - fresnel);
  if (uEvent < fresnel) {
    s.event = ScatterEvent::kFresnelReflection;
    s.wi = Reflect(wo, side);
    s.weight = {1, 1, 1};
  } else if (uEvent < fresnel + (1.0f - fresnel) * transmit) {
    s.event = ScatterEvent::kRefraction;
    s.wi = Refract(wo, side, eta, *cosT);
    s.weight = m.transmittance / transmit;
    if (mode == TransportMode::kRadiance) s.weight = s.weight / (eta * eta);
    s.transmitted = true;
  }
  return s;
}

}  // namespace

ScatterSample SampleScatter(const Material& material, Rgb albedo, Vector3 wo, Normal3 front, TransportMode mode,
                            float uEvent, Point2 uDirection) {
  const bool onFront = Dot(wo, front) > 0;
  const Normal3 side = onFront ? front : -front;
  switch (material.kind) {
    case MaterialClass::kMirror: return ScatterMirror(material, albedo, wo, side, uEvent, uDirection);
    case MaterialClass::kGlass: return ScatterGlass(material, wo, side, onFront, mode, uEvent);
    case MaterialClass::kDiffuse: break;
  }
  return ScatterDiffuse(albedo, side, uEvent, uDirection);
}

}  // namespace pb
