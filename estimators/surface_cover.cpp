#include "estimators/surface_cover.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>

#include "estimators/cover_band.h"
#include "estimators/cover_pieces.h"
#include "estimators/cover_probe.h"

namespace pb {

// Builds one surface's cover: classifies the lattice, bisects its changing edges, and cuts the covered cells'
// polygons to the surface's triangles.
class CoverBuilder {
 public:
  CoverBuilder(const Scene& scene, const SurfaceSet& surfaces, const RayScene& rays, uint32_t s,
               const CoverSettings& settings)
      : scene_(scene), surfaces_(surfaces), rays_(rays), surfaceIndex_(s), settings_(settings),
        probe_(scene, surfaces, rays, s) {}

  SurfaceCover Build() {
    const Bounds2& b = probe_.Whole().Bounds();
    const double su = double(b.hi.u) - b.lo.u, sv = double(b.hi.v) - b.lo.v;
    // A surface narrower than two lattice spacings holds at most a row of lattice points: too few to find a cover.
    if (!(std::min(su, sv) >= 2 * double(settings_.spacing))) return {};
    double spacing = settings_.spacing;
    while ((su / spacing + 3) * (sv / spacing + 3) > double(settings_.maxPointsPerSurface)) spacing *= 2;
    c_.spacing_ = float(spacing);
    c_.lo_ = {float(b.lo.u - spacing / 2), float(b.lo.v - spacing / 2)};
    c_.nu_ = int(std::ceil(su / spacing)) + 2;  // from half a spacing before the chart to at least half after
    c_.nv_ = int(std::ceil(sv / spacing)) + 2;
    const std::vector<uint64_t> band = BandPoints(CellsWhereTheCoverCanChange(
        {scene_, surfaces_, rays_, surfaceIndex_}, {c_.lo_, c_.spacing_, c_.nu_, c_.nv_}, probe_.Whole().Bounds()));
    ClassifyLattice(band);
    if (c_.runs_.empty()) {
      SurfaceCover empty;
      empty.probed_ = band.size();
      return empty;
    }
    c_.probed_ = band.size();
    const std::vector<LatticeEdge> changing = ChangingEdges();
    FindCrossings(changing);
    CoverPieces pieces(c_, probe_, surfaces_, surfaceIndex_);
    pieces.FindCorners(changing);
    pieces.CutPieces();
    return std::move(c_);
  }

 private:

  // The band's lattice points: the corners of the marked cells, sorted. A point that is not one has no marked cell
  // about it; every lattice edge that a footprint touches is a side of a cell that MarkPolygon marks, so the edges
  // from such a point touch none, and its class is its neighbours'.
  std::vector<uint64_t> BandPoints(std::vector<uint64_t> marked) const {
    std::sort(marked.begin(), marked.end());
    marked.erase(std::unique(marked.begin(), marked.end()), marked.end());
    std::vector<uint64_t> points;
    points.reserve(marked.size() * 4);
    for (uint64_t cell : marked) {
      const int i = int(cell % uint64_t(c_.nu_)), j = int(cell / uint64_t(c_.nu_));
      for (int dj = 0; dj <= 1; ++dj)
        for (int di = 0; di <= 1; ++di) points.push_back(c_.Key(i + di, j + dj));  // cells stop one short of the rim
    }
    std::sort(points.begin(), points.end());
    points.erase(std::unique(points.begin(), points.end()), points.end());
    return points;
  }

  // Casts the rays at the band's points; every other point of a row takes the class of the band point before it
  // in the row (open before the first: the row's start is off the surface). Fills the cover's runs.
  void ClassifyLattice(const std::vector<uint64_t>& band) {
    std::vector<uint8_t> covered(band.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, band.size()), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t k = r.begin(); k != r.end(); ++k)
        covered[k] = probe_.CoveredAt(c_.Lattice(int(band[k] % uint64_t(c_.nu_)), int(band[k] / uint64_t(c_.nu_))));
    });
    std::vector<std::pair<int, SurfaceCover::Run>> runs;  // (row, run)
    for (size_t k = 0; k < band.size(); ++k) {
      if (!covered[k]) continue;
      const int i = int(band[k] % uint64_t(c_.nu_)), j = int(band[k] / uint64_t(c_.nu_));
      const bool nextInRow = k + 1 < band.size() && band[k + 1] / uint64_t(c_.nu_) == uint64_t(j);
      const int last = nextInRow ? int(band[k + 1] % uint64_t(c_.nu_)) - 1 : i;
      if (!runs.empty() && runs.back().first == j && runs.back().second.last + 1 == i) runs.back().second.last = last;
      else runs.push_back({j, {i, last}});
    }
    if (runs.empty()) return;
    c_.firstRow_ = runs.front().first;
    const int rows = runs.back().first - c_.firstRow_ + 1;
    c_.rowStart_.assign(size_t(rows) + 1, 0);
    for (const auto& [j, run] : runs) {
      ++c_.rowStart_[size_t(j - c_.firstRow_) + 1];
      c_.runs_.push_back(run);
    }
    for (size_t k = 1; k < c_.rowStart_.size(); ++k) c_.rowStart_[k] += c_.rowStart_[k - 1];
  }

  // The lattice edges whose ends differ: at each run's ends along its row, and where two neighbouring rows' runs
  // differ (their symmetric difference), found from the runs alone.
  std::vector<LatticeEdge> ChangingEdges() const {
    std::vector<LatticeEdge> edges;
    const int rows = int(c_.rowStart_.size()) - 1;
    for (int j = c_.firstRow_; j < c_.firstRow_ + rows; ++j)
      for (const SurfaceCover::Run& run : c_.RowRuns(j)) {
        if (run.first > 0) edges.push_back({run.first - 1, j, 0});
        if (run.last + 1 < c_.nu_) edges.push_back({run.last, j, 0});
      }
    for (int j = std::max(c_.firstRow_ - 1, 0); j < std::min(c_.firstRow_ + rows, c_.nv_ - 1); ++j) {
      std::vector<int> ends;  // half-open [first, last + 1) of both rows' runs; equal ends cancel
      for (int row : {j, j + 1})
        for (const SurfaceCover::Run& run : c_.RowRuns(row)) ends.push_back(run.first), ends.push_back(run.last + 1);
      std::sort(ends.begin(), ends.end());
      std::vector<int> toggles;
      for (int e : ends) {
        if (!toggles.empty() && toggles.back() == e) toggles.pop_back();
        else toggles.push_back(e);
      }
      for (size_t k = 0; k + 1 < toggles.size(); k += 2)
        for (int i = toggles[k]; i < toggles[k + 1]; ++i) edges.push_back({i, j, 1});
    }
    return edges;
  }

  // On each changing lattice edge, the fraction of the way from its first end where the cover changes.
  void FindCrossings(const std::vector<LatticeEdge>& edges) {
    std::vector<float> at(edges.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, edges.size()), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t k = r.begin(); k != r.end(); ++k) {
        const LatticeEdge& e = edges[k];
        const int i1 = e.i + (e.axis == 0), j1 = e.j + (e.axis == 1);
        at[k] = probe_.Bisect(c_.Lattice(e.i, e.j), c_.Lattice(i1, j1), c_.CoveredPoint(e.i, e.j));
      }
    });
    c_.crossing_.reserve(edges.size());
    for (size_t k = 0; k < edges.size(); ++k)
      c_.crossing_.emplace(SurfaceCover::EdgeKey(c_.Key(edges[k].i, edges[k].j), edges[k].axis), at[k]);
  }

  const Scene& scene_;
  const SurfaceSet& surfaces_;
  const RayScene& rays_;
  uint32_t surfaceIndex_;
  CoverSettings settings_;
  CoverProbe probe_;
  SurfaceCover c_;
};

std::array<SurfaceCover::CellEdge, 4> SurfaceCover::EdgesOf(int i, int j) const {
  const std::array<std::array<int, 2>, 4> corner = {{{i, j}, {i + 1, j}, {i + 1, j + 1}, {i, j + 1}}};
  // Each edge's crossing is stored at its first end (the lower i or j) and computed from there, so the two cells
  // that share an edge share the point bit for bit.
  const std::array<std::array<int, 3>, 4> stored = {{{i, j, 0}, {i + 1, j, 1}, {i, j + 1, 0}, {i, j, 1}}};
  const std::array<Point2, 4> inward = {{{0, 1}, {-1, 0}, {0, -1}, {1, 0}}};
  std::array<CellEdge, 4> edges;
  for (int k = 0; k < 4; ++k) {
    const auto [ia, ja] = corner[k];
    const auto [ib, jb] = corner[(k + 1) % 4];
    CellEdge& e = edges[k];
    e = {Lattice(ia, ja), Lattice(ib, jb), CoveredPoint(ia, ja), CoveredPoint(ib, jb), inward[k], {}};
    if (e.coveredA == e.coveredB) continue;
    const auto [ei, ej, axis] = stored[k];
    const float t = crossing_.at(EdgeKey(Key(ei, ej), axis));
    const Point2 p = Lattice(ei, ej), q = Lattice(ei + (axis == 0), ej + (axis == 1));
    e.crossing = {p.u + t * (q.u - p.u), p.v + t * (q.v - p.v)};
  }
  return edges;
}

std::vector<Point2> SurfaceCover::CellPolygon(int i, int j, const Point2* corner) const {
  if (corner == nullptr) {
    const auto found = corners_.find(size_t(j) * nu_ + i);
    if (found != corners_.end()) corner = &found->second;
  }
  std::vector<Point2> polygon;
  for (const CellEdge& e : EdgesOf(i, j)) {
    if (e.coveredA) polygon.push_back(e.a);
    if (e.coveredA == e.coveredB) continue;
    polygon.push_back(e.crossing);
    if (e.coveredA && corner != nullptr) polygon.push_back(*corner);  // the line turns before it re-enters
  }
  return polygon;
}

std::span<const SurfaceCover::Run> SurfaceCover::RowRuns(int j) const {
  const int k = j - firstRow_;
  if (k < 0 || k + 1 >= int(rowStart_.size())) return {};
  return {runs_.data() + rowStart_[size_t(k)], runs_.data() + rowStart_[size_t(k) + 1]};
}

bool SurfaceCover::CoveredPoint(int i, int j) const {
  const std::span<const Run> row = RowRuns(j);
  const auto after = std::upper_bound(row.begin(), row.end(), i, [](int x, const Run& run) { return x < run.first; });
  return after != row.begin() && i <= std::prev(after)->last;
}

bool SurfaceCover::InCell(Point2 uv, int i, int j) const {
  const Point2 lo = Lattice(i, j), hi = Lattice(i + 1, j + 1);
  return uv.u > lo.u && uv.u < hi.u && uv.v > lo.v && uv.v < hi.v;
}

bool SurfaceCover::Covered(Point2 uv) const {
  if (pieces_.empty()) return false;
  const float fu = (uv.u - lo_.u) / spacing_, fv = (uv.v - lo_.v) / spacing_;
  if (!(fu >= 0 && fv >= 0 && fu <= float(nu_ - 1) && fv <= float(nv_ - 1))) return false;
  const int i = std::min(int(fu), nu_ - 2), j = std::min(int(fv), nv_ - 2);
  const std::vector<Point2> polygon = CellPolygon(i, j);
  if (polygon.size() < 3) return false;
  for (size_t k = 0; k < polygon.size(); ++k) {
    const Point2 a = polygon[k], b = polygon[(k + 1) % polygon.size()];
    if ((double(b.u) - a.u) * (double(uv.v) - a.v) - (double(b.v) - a.v) * (double(uv.u) - a.u) < 0) return false;
  }
  return true;
}

double SurfaceCover::Area() const {
  double area = 0;
  for (const Triangle2& t : pieces_) area += SignedArea(t[0], t[1], t[2]);
  return area;
}

std::vector<SurfaceCover> FindCovers(const Scene& scene, const SurfaceSet& surfaces, const RayScene& rays,
                                     const CoverSettings& settings, const WorkProgress& advance) {
  std::vector<SurfaceCover> covers(surfaces.surfaces.size());
  if (!(settings.spacing > 0)) return covers;
  CoverSettings scaled = settings;
  if (settings.maxSpacingPerDiagonal > 0) {
    const double diagonal = scene.Diagonal();
    if (diagonal > 0) scaled.spacing = float(std::min(double(settings.spacing), settings.maxSpacingPerDiagonal * diagonal));
  }
  if (!(scaled.spacing < FLT_MAX)) return covers;  // a scene of no extent, whose spacing only the diagonal set
  const auto tested = [&](const Surface& surface) {
    return surface.planar && !scene.materials[surface.material].IsEmissive();
  };
  uint64_t total = 0;
  for (const Surface& surface : surfaces.surfaces) total += tested(surface) ? surface.triangles.size() : 0;
  for (uint32_t s = 0; s < surfaces.surfaces.size(); ++s) {
    const Surface& surface = surfaces.surfaces[s];
    if (!tested(surface)) continue;
    covers[s] = CoverBuilder(scene, surfaces, rays, s, scaled).Build();
    if (advance) advance(surface.triangles.size(), total);
  }
  return covers;
}

}  // namespace pb
