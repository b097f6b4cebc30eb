// Adaptive refinement of a half-edge mesh by longest-edge bisection: a face that needs refining is split by
// cutting the longest edge on its longest-edge propagation path at its midpoint (Rivara 1984, "Algorithms for
// refining triangular grids suitable for adaptive and multigrid techniques"; Rivara 1997, "New longest-edge
// algorithms for the refinement and/or improvement of unstructured triangulations"). Every cut splits both
// faces on its edge, so the mesh never has a T-junction; and because a face's longest edge is always cut
// first, angles stay bounded away from 0 however deep the refinement goes. New vertices lie on their edges,
// so the geometry does not change.
//
// What gets refined is decided by small pluggable modules, in the style of OpenMesh's Decimater (STYLE.md):
// exactly one priority module ranks faces (the worst first) and says which need no refining, and any number of
// constraint modules may refuse a cut (a minimum edge length, a vertex budget). The engine only orders and
// cuts. This is the meshing step of Shirley et al. 1995 ("Monte Carlo techniques for direct lighting
// calculations", and the density-estimation papers after it): refine where the light changes.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "mesh/half_edge_mesh.h"

namespace pb {

class RefineModule {
 public:
  static constexpr double kNoSplit = -1;  // Priority(): this face needs no refining
  virtual ~RefineModule() = default;
  virtual std::string_view Name() const = 0;
  // Priority modules: how badly face f needs refining (any value >= 0, larger first), or kNoSplit.
  virtual double Priority(const HalfEdgeMesh& /*mesh*/, HalfEdgeMesh::FaceHandle /*f*/) { return 0; }
  // Constraint modules: whether edge e may be cut at its midpoint now.
  virtual bool AllowsSplit(const HalfEdgeMesh& /*mesh*/, HalfEdgeMesh::EdgeHandle /*e*/) { return true; }
  // Every module hears of each new vertex, after its edge is cut.
  virtual void OnSplit(const HalfEdgeMesh& /*mesh*/, HalfEdgeMesh::VertexHandle /*v*/) {}
};

// Refuses to cut an edge whose halves would be shorter than its surfaces' minimum edge length [m] (the
// smallest over the faces on the edge). `minimumBySurface` is indexed by surface.
class MinimumEdgeLength : public RefineModule {
 public:
  explicit MinimumEdgeLength(std::vector<double> minimumBySurface) : minimum_(std::move(minimumBySurface)) {}
  std::string_view Name() const override { return "minimum edge length"; }
  bool AllowsSplit(const HalfEdgeMesh& mesh, HalfEdgeMesh::EdgeHandle e) override;

 private:
  std::vector<double> minimum_;
};

// Keeps the display mesh (mesh/half_edge_mesh.h, ToSplitMesh) within `budget` vertices. It counts each new
// vertex once per surface it touches, and once per base triangle on textured surfaces (which may split at a
// texture seam): an upper bound on the copies ToSplitMesh makes, so the budget is never exceeded.
class VertexBudget : public RefineModule {
 public:
  VertexBudget(size_t budget, size_t displayVertices, std::vector<bool> texturedSurface)
      : budget_(budget), count_(displayVertices), textured_(std::move(texturedSurface)) {}
  std::string_view Name() const override { return "vertex budget"; }
  bool AllowsSplit(const HalfEdgeMesh&, HalfEdgeMesh::EdgeHandle) override { return count_ + 2 <= budget_; }
  void OnSplit(const HalfEdgeMesh& mesh, HalfEdgeMesh::VertexHandle v) override;
  size_t Count() const { return count_; }

 private:
  size_t budget_, count_;
  std::vector<bool> textured_;
};

struct RefineStats {
  size_t splits = 0;         // edges cut (= vertices added)
  size_t refusedFaces = 0;   // faces that needed refining but whose cut a constraint refused
  std::vector<std::pair<std::string, size_t>> refusedBy;  // constraint module name -> cuts it refused
};

// Cuts edges until no face has a priority >= 0, or every such face's cut is refused. Deterministic: faces of
// equal priority are taken in index order.
RefineStats RefineAdaptive(HalfEdgeMesh& mesh, RefineModule& priority, std::span<RefineModule* const> constraints);

}  // namespace pb
