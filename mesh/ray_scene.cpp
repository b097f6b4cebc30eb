#include "mesh/ray_scene.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstring>

#include "mesh/errors.h"

namespace pb {
namespace {

// Embree reports API misuse and allocation failures here; each one is a bug on our side, so abort loudly.
void OnEmbreeError(void*, RTCError code, const char* message) {
  if (code == RTC_ERROR_NONE) return;
  std::fprintf(stderr, "embree error %d: %s\n", int(code), message ? message : "");
  CheckFailed("Embree call succeeded", __FILE__, __LINE__, message ? message : "");
}

// 2^-18 of the largest coordinate: about 32 float ulps there, far above Embree's intersection error
// (a few ulps) and far below any feature of a real scene (2 micrometres for the 0.56 m Cornell box).
constexpr float kRelativeSpawnOffset = 0x1p-18f;

// Embree's build progress, n in [0, 1] from its build threads, as thousandths told to a WorkProgress: each
// thousandth once, by whichever thread passes it first.
constexpr uint64_t kBuildSteps = 1000;
struct BuildProgress {
  const WorkProgress& tell;
  std::atomic<uint64_t> told{0};
};
bool OnBuildProgress(void* ptr, double n) {
  auto& p = *static_cast<BuildProgress*>(ptr);
  const uint64_t now = std::min(kBuildSteps, uint64_t(std::clamp(n, 0.0, 1.0) * double(kBuildSteps)));
  uint64_t before = p.told.load();
  while (before < now && !p.told.compare_exchange_weak(before, now)) {
  }
  if (before < now) p.tell(now - before, kBuildSteps);
  return true;  // go on
}

}  // namespace

RayScene::RayScene(const Scene& scene, const WorkProgress& progress) {
  // One device per scene; "" lets Embree pick the ISA and thread settings. TBB is shared with our own work.
  device_ = rtcNewDevice("");
  PB_CHECK(device_ != nullptr, "rtcNewDevice failed");
  rtcSetDeviceErrorFunction(device_, OnEmbreeError, nullptr);  // always set: errors must not pass silently.

  scene_ = rtcNewScene(device_);
  rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);  // static geometry traced millions of times.

  RTCGeometry mesh = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
  // Embree owns these buffers (padded as it requires); we copy positions and indices in once.
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(mesh, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                               3 * sizeof(float), scene.positions.size()));
  for (size_t i = 0; i < scene.positions.size(); ++i) {
    vertices[3 * i + 0] = scene.positions[i].x;
    vertices[3 * i + 1] = scene.positions[i].y;
    vertices[3 * i + 2] = scene.positions[i].z;
  }
  auto* indices = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(mesh, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                 3 * sizeof(uint32_t), scene.triangles.size()));
  for (size_t t = 0; t < scene.triangles.size(); ++t) std::memcpy(&indices[3 * t], scene.triangles[t].v.data(), 12);
  vertices_ = vertices, indices_ = indices;
  rtcCommitGeometry(mesh);
  rtcAttachGeometryByID(scene_, mesh, 0);  // one geometry: primID is then our triangle index.
  rtcReleaseGeometry(mesh);                // the scene holds the reference now.
  BuildProgress monitor{progress};
  if (progress) rtcSetSceneProgressMonitorFunction(scene_, OnBuildProgress, &monitor);
  rtcCommitScene(scene_);  // builds the BVH.
  if (progress) {
    rtcSetSceneProgressMonitorFunction(scene_, nullptr, nullptr);
    if (const uint64_t left = kBuildSteps - monitor.told.load(); left > 0) progress(left, kBuildSteps);
  }

  spawnOffset_ = kRelativeSpawnOffset * std::max(scene.LargestCoordinate(), 1e-30f);
}

RayScene::~RayScene() {
  if (scene_) rtcReleaseScene(scene_);
  if (device_) rtcReleaseDevice(device_);
}

namespace {

RTCRay MakeRay(Point3 origin, Vector3 direction, float tFar) {
  RTCRay ray;
  ray.org_x = origin.x;
  ray.org_y = origin.y;
  ray.org_z = origin.z;
  ray.dir_x = direction.x;
  ray.dir_y = direction.y;
  ray.dir_z = direction.z;
  ray.tnear = 0.0f;  // the origin is already offset off its surface by SpawnPoint.
  ray.tfar = tFar;
  ray.time = 0.0f;
  ray.mask = ~0u;  // all geometry.
  ray.flags = 0;
  ray.id = 0;
  return ray;
}

}  // namespace

std::optional<RayHit> RayScene::Intersect(Point3 origin, Vector3 direction, float tFar) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);  // default flags: incoherent rays.
  RTCRayHit rh;
  rh.ray = MakeRay(origin, direction, tFar);
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene_, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  return RayHit{rh.ray.tfar, rh.hit.primID, rh.hit.u, rh.hit.v};
}

bool RayScene::Occluded(Point3 origin, Vector3 direction, float tFar) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray = MakeRay(origin, direction, tFar);
  rtcOccluded1(scene_, &context, &ray);
  return ray.tfar < 0;  // Embree sets tfar to -inf on a hit
}

namespace {

// A point query's question to each triangle near it: MayMeetInFront's test. Past kMostLookedAt triangles it answers
// "may": a finely tessellated surface puts thousands of its own triangles within reach, all behind the origin's
// plane, and looking at each would cost more than the rays the answer spares (a flat light of 200,000 triangles:
// each of its vertices looked at every one, and doubling the triangles quadrupled the estimate).
constexpr uint32_t kMostLookedAt = 512;
struct FrontQuery {
  const float* vertices;
  const uint32_t* indices;
  Point3 origin;
  Normal3 n;
  float slack;  // [m]: how far behind the origin's plane a corner may lie and still count
  bool found = false;
  uint32_t lookedAt = 0;
};

bool MeetsFront(RTCPointQueryFunctionArguments* args) {
  auto& q = *static_cast<FrontQuery*>(args->userPtr);
  if (++q.lookedAt > kMostLookedAt) {  // "may", conservatively
    q.found = true;
    args->query->radius = 0;
    return true;
  }
  const RTCPointQuery& point = *args->query;
  float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  float front = -INFINITY;
  for (int c = 0; c < 3; ++c) {
    const float* v = q.vertices + 3 * size_t(q.indices[3 * size_t(args->primID) + c]);
    front = std::max(front, Dot(Point3{v[0], v[1], v[2]} - q.origin, q.n));
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], v[k]), hi[k] = std::max(hi[k], v[k]);
  }
  const float at[3] = {point.x, point.y, point.z};
  float distance2 = 0;  // from the origin to the triangle's bounding box
  for (int k = 0; k < 3; ++k) {
    const float d = std::max({lo[k] - at[k], at[k] - hi[k], 0.0f});
    distance2 += d * d;
  }
  if (front < -q.slack || distance2 > point.radius * point.radius) return false;
  q.found = true;
  args->query->radius = 0;  // the answer is known: the traversal can stop looking
  return true;
}

}  // namespace

namespace {

// A point query's question to each triangle near it: TrianglesNear's collection. Embree calls this for each
// reference in the leaves its traversal reaches; with spatial splits (RTC_BUILD_QUALITY_HIGH) a triangle can have
// several, so the caller removes repeats.
bool CollectNear(RTCPointQueryFunctionArguments* args) {
  static_cast<std::vector<uint32_t>*>(args->userPtr)->push_back(args->primID);
  return false;  // the query's radius stays as it is
}

}  // namespace

void RayScene::TrianglesNear(Point3 centre, float radius, std::vector<uint32_t>& out) const {
  const size_t first = out.size();
  RTCPointQuery query{centre.x, centre.y, centre.z, 0.0f, radius};
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(scene_, &query, &context, CollectNear, &out);
  std::sort(out.begin() + std::ptrdiff_t(first), out.end());
  out.erase(std::unique(out.begin() + std::ptrdiff_t(first), out.end()), out.end());
}

bool RayScene::MayMeetInFront(Point3 origin, Normal3 n, float reach) const {
  RTCPointQuery query{origin.x, origin.y, origin.z, 0.0f, reach};
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  FrontQuery q{vertices_, indices_, origin, n, 0.25f * spawnOffset_};
  rtcPointQuery(scene_, &query, &context, MeetsFront, &q);
  return q.found;
}

}  // namespace pb
