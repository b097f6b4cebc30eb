#include "estimators/cover_pieces.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "estimators/chart_clip.h"

namespace pb {
namespace {

bool Convex(const std::vector<Point2>& polygon) {
  for (size_t k = 0; k < polygon.size(); ++k) {
    const size_t n = polygon.size();
    if (SignedArea(polygon[k], polygon[(k + 1) % n], polygon[(k + 2) % n]) < 0) return false;
  }
  return true;
}

// Where two lines meet, unless they are within 10 degrees of parallel (a straight contact line: no corner).
std::optional<Point2> Intersection(Point2 p0, Point2 p1, Point2 q0, Point2 q1) {
  const double pu = double(p1.u) - p0.u, pv = double(p1.v) - p0.v;
  const double qu = double(q1.u) - q0.u, qv = double(q1.v) - q0.v;
  const double cross = pu * qv - pv * qu;
  if (!(std::fabs(cross) > std::sin(10 * M_PI / 180) * std::hypot(pu, pv) * std::hypot(qu, qv))) return std::nullopt;
  const double a = ((double(q0.u) - p0.u) * qv - (double(q0.v) - p0.v) * qu) / cross;
  return Point2{float(p0.u + a * pu), float(p0.v + a * pv)};
}

}  // namespace

void CoverPieces::FindCorners(std::span<const LatticeEdge> changing) {
  std::vector<uint64_t> cells;
  for (const LatticeEdge& e : changing) {
    const int i = e.i - (e.axis == 1), j = e.j - (e.axis == 0);  // the cell before the edge, then the one after
    for (const auto& [ci, cj] : {std::pair{i, j}, std::pair{e.i, e.j}})
      if (ci >= 0 && cj >= 0 && ci + 1 < c_.nu_ && cj + 1 < c_.nv_) cells.push_back(c_.Key(ci, cj));
  }
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  std::vector<std::optional<Point2>> corner(cells.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, cells.size()), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t k = r.begin(); k != r.end(); ++k)
      corner[k] = CornerIn(int(cells[k] % uint64_t(c_.nu_)), int(cells[k] / uint64_t(c_.nu_)));
  });
  for (size_t k = 0; k < cells.size(); ++k)
    if (corner[k]) c_.corners_.emplace(size_t(cells[k]), *corner[k]);
}

std::optional<Point2> CoverPieces::CornerIn(int i, int j) const {
  const std::array<SurfaceCover::CellEdge, 4> edges = c_.EdgesOf(i, j);
  const SurfaceCover::CellEdge *exit = nullptr, *entry = nullptr;
  int changes = 0;
  for (const SurfaceCover::CellEdge& e : edges) {
    if (e.coveredA == e.coveredB) continue;
    ++changes;
    (e.coveredA ? exit : entry) = &e;
  }
  if (changes != 2) return std::nullopt;  // uniform, or a saddle
  const std::optional<Line2> out = ContactLineAt(*exit), in = ContactLineAt(*entry);
  if (!out || !in) return std::nullopt;
  const std::optional<Point2> x = Intersection(out->through, out->second, in->through, in->second);
  if (!x || !c_.InCell(*x, i, j)) return std::nullopt;
  if (!Convex(c_.CellPolygon(i, j, &*x))) return std::nullopt;
  const Point2 chordMiddle = Between(out->through, in->through, 0.5);
  if (!probe_.CoveredAt(Between(chordMiddle, *x, 0.5))) return std::nullopt;  // the turn is not where the lines say
  return x;
}

// The contact line through the crossing on lattice edge e, from a second crossing s / 4 into the cell along a
// parallel segment whose ends are covered as e's are. None when the line turns within s / 4 of the edge.
std::optional<CoverPieces::Line2> CoverPieces::ContactLineAt(const SurfaceCover::CellEdge& e) const {
  const float d = 0.25f * c_.spacing_;
  const Point2 a{e.a.u + d * e.inward.u, e.a.v + d * e.inward.v}, b{e.b.u + d * e.inward.u, e.b.v + d * e.inward.v};
  if (probe_.CoveredAt(a) != e.coveredA || probe_.CoveredAt(b) != e.coveredB) return std::nullopt;
  return Line2{e.crossing, Between(a, b, probe_.Bisect(a, b, e.coveredA))};
}

void CoverPieces::CutPieces() {
  const std::vector<uint64_t> cells = CellsWithACoveredCorner();
  std::vector<std::vector<uint32_t>> trianglesOfCell(cells.size());
  const auto cellOf = [&](float c, float lo, int n) { return std::clamp(int(std::floor((c - lo) / c_.spacing_)), 0, n - 2); };
  for (uint32_t t : surface_.triangles) {
    Bounds2 tb;
    for (const Point2& p : surfaces_.cornerUv[t]) tb.Extend(p);
    const int i0 = cellOf(tb.lo.u, c_.lo_.u, c_.nu_), i1 = cellOf(tb.hi.u, c_.lo_.u, c_.nu_);
    for (int j = cellOf(tb.lo.v, c_.lo_.v, c_.nv_); j <= cellOf(tb.hi.v, c_.lo_.v, c_.nv_); ++j)
      for (auto c = std::lower_bound(cells.begin(), cells.end(), c_.Key(i0, j)); c != cells.end() && *c <= c_.Key(i1, j); ++c)
        trianglesOfCell[size_t(c - cells.begin())].push_back(t);
  }
  for (size_t k = 0; k < cells.size(); ++k) {
    const std::vector<Point2> polygon = c_.CellPolygon(int(cells[k] % uint64_t(c_.nu_)), int(cells[k] / uint64_t(c_.nu_)));
    for (uint32_t t : trianglesOfCell[k]) {
      std::array<Point2, 3> tri = surfaces_.cornerUv[t];
      if (SignedArea(tri[0], tri[1], tri[2]) < 0) std::swap(tri[1], tri[2]);
      std::vector<Point2> piece = polygon;
      for (int e = 0; e < 3 && piece.size() >= 3; ++e) piece = ClipLeftOf(piece, tri[e], tri[(e + 1) % 3]);
      if (piece.size() < 3 || !(TwiceSignedArea(piece) > 1e-12 * double(c_.spacing_) * c_.spacing_)) continue;
      for (size_t m = 1; m + 1 < piece.size(); ++m) c_.pieces_.push_back({piece[0], piece[m], piece[m + 1]});
    }
  }
}

// The cells with a covered corner, from the runs: each covered point's four cells. Sorted.
std::vector<uint64_t> CoverPieces::CellsWithACoveredCorner() const {
  std::vector<uint64_t> cells;
  const int rows = int(c_.rowStart_.size()) - 1;
  for (int j = c_.firstRow_; j < c_.firstRow_ + rows; ++j)
    for (const SurfaceCover::Run& run : c_.RowRuns(j))
      for (int cj = std::max(j - 1, 0); cj <= std::min(j, c_.nv_ - 2); ++cj)
        for (int ci = std::max(run.first - 1, 0); ci <= std::min(run.last, c_.nu_ - 2); ++ci) cells.push_back(c_.Key(ci, cj));
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  return cells;
}

}  // namespace pb
