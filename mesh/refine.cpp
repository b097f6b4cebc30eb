#include "mesh/refine.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <queue>
#include <set>
#include <tuple>

namespace pb {
namespace {

using FaceHandle = HalfEdgeMesh::FaceHandle;
using EdgeHandle = HalfEdgeMesh::EdgeHandle;

double EdgeLengthSquared(const HalfEdgeMesh& mesh, EdgeHandle e) {
  const auto h = mesh.halfedge_handle(e, 0);
  return (mesh.point(mesh.to_vertex_handle(h)) - mesh.point(mesh.from_vertex_handle(h))).sqrnorm();
}

// The longest edge of f; ties go to the lower edge index, so "longest" is a strict order and propagation paths
// cannot cycle.
EdgeHandle LongestEdge(const HalfEdgeMesh& mesh, FaceHandle f) {
  EdgeHandle best;
  double bestLength = -1;
  for (auto e : mesh.fe_range(f)) {
    const double length = EdgeLengthSquared(mesh, e);
    if (length > bestLength || (length == bestLength && e.idx() < best.idx())) best = e, bestLength = length;
  }
  return best;
}

FaceHandle FaceAcross(const HalfEdgeMesh& mesh, EdgeHandle e, FaceHandle f) {
  const FaceHandle a = mesh.face_handle(mesh.halfedge_handle(e, 0)), b = mesh.face_handle(mesh.halfedge_handle(e, 1));
  return a == f ? b : a;
}

class Refiner {
 public:
  Refiner(HalfEdgeMesh& mesh, RefineModule& priority, std::span<RefineModule* const> constraints)
      : mesh_(mesh), priority_(priority), constraints_(constraints) {}

  RefineStats Run() {
    for (auto f : mesh_.faces()) Push(f);
    while (!queue_.empty()) {
      const auto [p, index, generation] = queue_.top();
      queue_.pop();
      const FaceHandle f(-index);
      if (generation != generation_[f.idx()]) continue;  // the face changed since it was queued
      if (!BisectAlongPath(f)) ++stats_.refusedFaces;
      for (FaceHandle changed : changed_) Push(changed);
      changed_.clear();
    }
    for (const auto& [name, count] : refused_) stats_.refusedBy.emplace_back(name, count);
    return stats_;
  }

 private:
  // Queue entries: (priority, -face index, generation): the largest priority first, then the lowest index.
  using Entry = std::tuple<double, int, uint32_t>;

  void Push(FaceHandle f) {
    if (generation_.size() <= size_t(f.idx())) generation_.resize(mesh_.n_faces(), 0);
    const uint32_t generation = ++generation_[f.idx()];
    const double p = priority_.Priority(mesh_, f);
    if (p >= 0) queue_.emplace(p, -f.idx(), generation);
  }

  // Cuts the terminal edges of f's longest-edge propagation path until f itself is cut. False when a constraint
  // refuses a cut first (the mesh is conforming after every cut, so stopping midway is safe).
  bool BisectAlongPath(FaceHandle f) {
    std::vector<FaceHandle> path{f};
    while (!path.empty()) {
      const FaceHandle t = path.back();
      const EdgeHandle e = LongestEdge(mesh_, t);
      const FaceHandle across = FaceAcross(mesh_, e, t);
      if (across.is_valid() && LongestEdge(mesh_, across) != e) {
        path.push_back(across);
        continue;
      }
      if (!Allowed(e)) return false;
      Split(e);
      path.pop_back();
    }
    return true;
  }

  bool Allowed(EdgeHandle e) {
    for (RefineModule* c : constraints_)
      if (!c->AllowsSplit(mesh_, e)) {
        ++refused_[std::string(c->Name())];
        return false;
      }
    return true;
  }

  void Split(EdgeHandle e) {
    const auto h = mesh_.halfedge_handle(e, 0);
    const auto mid = 0.5 * (mesh_.point(mesh_.to_vertex_handle(h)) + mesh_.point(mesh_.from_vertex_handle(h)));
    const auto v = mesh_.add_vertex(mid);
    mesh_.split_copy(e, v);  // both faces on e become two each; the new ones copy their surface and base triangle
    ++stats_.splits;
    for (FaceHandle g : mesh_.vf_range(v)) changed_.insert(g);
    priority_.OnSplit(mesh_, v);
    for (RefineModule* c : constraints_) c->OnSplit(mesh_, v);
  }

  HalfEdgeMesh& mesh_;
  RefineModule& priority_;
  std::span<RefineModule* const> constraints_;
  std::priority_queue<Entry> queue_;
  std::vector<uint32_t> generation_;
  std::set<FaceHandle> changed_;
  std::map<std::string, size_t> refused_;
  RefineStats stats_;
};

}  // namespace

RefineStats RefineAdaptive(HalfEdgeMesh& mesh, RefineModule& priority, std::span<RefineModule* const> constraints) {
  return Refiner(mesh, priority, constraints).Run();
}

bool MinimumEdgeLength::AllowsSplit(const HalfEdgeMesh& mesh, HalfEdgeMesh::EdgeHandle e) {
  double minimum = INFINITY;
  for (int side = 0; side < 2; ++side) {
    const FaceHandle f = mesh.face_handle(mesh.halfedge_handle(e, side));
    if (f.is_valid()) minimum = std::min(minimum, minimum_[mesh.Surface(f)]);
  }
  return EdgeLengthSquared(mesh, e) >= 4 * minimum * minimum;
}

void VertexBudget::OnSplit(const HalfEdgeMesh& mesh, HalfEdgeMesh::VertexHandle v) {
  std::set<std::pair<uint32_t, uint32_t>> copies;  // (surface, base triangle on textured surfaces)
  for (FaceHandle f : mesh.vf_range(v)) {
    const uint32_t s = mesh.Surface(f);
    copies.emplace(s, textured_[s] ? mesh.BaseTriangle(f) : 0);
  }
  count_ += copies.size();
}

}  // namespace pb
