#include "tools/accuracy_report.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <ostream>
#include <utility>

#include "baker/files/atomic_file.h"

namespace pb::accuracy {

void WriteCsv(const std::string& path, const std::vector<Run>& runs) {
  pb::WriteFileAtomically(path, [&](std::ostream& out) {
    out << "estimator,kernel,h_m,auto_h,k,edge_correction,photons,seconds,trace_s,estimate_s,peak_mib,rmse_rel,"
           "rmse_interior_rel,rmse_edge_rel,mean_bias_rel,max_error_rel,noise_rel,bias_rel,direct,direct_samples,"
           "reference_paths,truth_noise_rel,edge_vertices,edge_bias_rel,covered_vertices,covered_mean_rel,direct_noise,target_noise,"
           "predicted_rel,predicted_noise_rel,predicted_bias_rel\n";
    for (const Run& r : runs) {
      const pb::EstimatorSettings& e = r.config.estimator;
      out << fmt::format("{},{},{},{},{},{},{},{:.4f},{:.4f},{:.4f},{:.1f},{:.5f},{:.5f},{:.5f},{:.5f},{:.5f},{:.5f},{:.5f},"
                         "{},{},{},{:.5f},{},{:.5f},{},{:.5f},{},{},{:.5f},{:.5f},{:.5f}\n",
                         pb::EstimatorName(e.kind), pb::KernelName(e.kernel), e.bandwidth ? fmt::format("{}", *e.bandwidth) : "auto", !e.bandwidth,
                         e.neighbours, e.edgeCorrection, r.config.photons, r.seconds, r.traceSeconds,
                         r.estimateSeconds, r.peakMiB, r.error.rmse, r.error.rmseInterior, r.error.rmseEdge,
                         r.error.bias, r.error.maxError, r.error.noise, r.error.systematic,
                         pb::DirectLightName(r.config.direct.mode), r.config.direct.samples, r.config.referencePaths,
                         r.error.truthNoise, r.error.edgeVertices, r.error.edgeBias, r.error.coveredVertices,
                         r.error.coveredMean, r.config.direct.noise, r.config.targetNoise.value_or(0),
                         r.error.predicted.Total(), r.error.predicted.noise, r.error.predicted.bias);
    }
  });
}

// Log-log SVG of relative RMSE against seconds: every run as a dot, and each estimator's lower envelope (the
// best error reachable in a given time) as a line.
void WriteSvg(const std::string& path, const std::vector<Run>& runs, Bench bench) {
  constexpr double kW = 720, kH = 480, kLeft = 70, kBottom = 50, kTop = 20, kRight = 160;
  double t0 = 1e9, t1 = 0, e0 = 1e9, e1 = 0;
  for (const Run& r : runs) {
    t0 = std::min(t0, r.seconds), t1 = std::max(t1, r.seconds);
    e0 = std::min(e0, r.error.rmse), e1 = std::max(e1, r.error.rmse);
  }
  const double lt0 = std::floor(std::log10(t0)), lt1 = std::ceil(std::log10(t1));
  const double le0 = std::floor(std::log10(e0)), le1 = std::ceil(std::log10(e1));
  const auto X = [&](double t) { return kLeft + (std::log10(t) - lt0) / (lt1 - lt0) * (kW - kLeft - kRight); };
  const auto Y = [&](double e) { return kH - kBottom - (std::log10(e) - le0) / (le1 - le0) * (kH - kBottom - kTop); };
  std::vector<std::string> groups;  // in order of first appearance
  for (const Run& r : runs)
    if (std::find(groups.begin(), groups.end(), r.config.Group(bench)) == groups.end()) groups.push_back(r.config.Group(bench));
  const std::vector<std::string> colours = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e"};
  std::string svg = fmt::format("<svg xmlns='http://www.w3.org/2000/svg' width='{}' height='{}' font-family='sans-serif' "
                                "font-size='12'>\n<rect width='100%' height='100%' fill='white'/>\n", kW, kH);
  for (double l = lt0; l <= lt1; ++l)
    svg += fmt::format("<line x1='{0}' x2='{0}' y1='{1}' y2='{2}' stroke='#ddd'/><text x='{0}' y='{3}' "
                       "text-anchor='middle'>{4:g} s</text>\n", X(std::pow(10, l)), kTop, kH - kBottom,
                       kH - kBottom + 16, std::pow(10, l));
  for (double l = le0; l <= le1; ++l)
    svg += fmt::format("<line x1='{0}' x2='{1}' y1='{2}' y2='{2}' stroke='#ddd'/><text x='{3}' y='{2}' "
                       "text-anchor='end'>{4:g}%</text>\n", kLeft, kW - kRight, Y(std::pow(10, l)), kLeft - 6,
                       100 * std::pow(10, l));
  svg += fmt::format("<text x='{}' y='{}' text-anchor='middle'>wall time of one bake (2 cores)</text>\n",
                     (kLeft + kW - kRight) / 2, kH - 10);
  svg += fmt::format("<text x='14' y='{}' transform='rotate(-90 14 {})' text-anchor='middle'>relative RMSE of H</text>\n",
                     kH / 2, kH / 2);
  int legend = 0;
  for (size_t g = 0; g < groups.size(); ++g) {
    const std::string& c = colours[g % colours.size()];
    std::vector<const Run*> mine;
    for (const Run& r : runs)
      if (r.config.Group(bench) == groups[g]) mine.push_back(&r);
    std::sort(mine.begin(), mine.end(), [](const Run* a, const Run* b) { return a->seconds < b->seconds; });
    std::string envelope;
    double best = 1e300;
    for (const Run* r : mine) {
      svg += fmt::format("<circle cx='{:.1f}' cy='{:.1f}' r='3' fill='{}' fill-opacity='0.45'/>\n", X(r->seconds),
                         Y(r->error.rmse), c);
      if (r->error.rmse < best) {
        best = r->error.rmse;
        envelope += fmt::format("{:.1f},{:.1f} ", X(r->seconds), Y(best));
      }
    }
    svg += fmt::format("<polyline points='{}' fill='none' stroke='{}' stroke-width='2'/>\n", envelope, c);
    svg += fmt::format("<rect x='{}' y='{}' width='12' height='12' fill='{}'/><text x='{}' y='{}'>{}</text>\n",
                       kW - kRight + 12, kTop + 20 * legend, c, kW - kRight + 30, kTop + 20 * legend + 11,
                       groups[g]);
    ++legend;
  }
  svg += "</svg>\n";
  pb::WriteFileAtomically(path, [&](std::ostream& out) { out << svg; });
}

// The cheapest run reaching each error target.
void WriteCheapest(const std::string& path, const std::vector<Run>& runs) {
  std::string md = "| target RMSE | cheapest run | photons | seconds | RMSE | peak MiB |\n|---|---|---|---|---|---|\n";
  for (double target : {0.10, 0.05, 0.03, 0.02, 0.01}) {
    const Run* cheapest = nullptr;
    for (const Run& r : runs)
      if (r.error.rmse <= target && (!cheapest || r.seconds < cheapest->seconds)) cheapest = &r;
    md += cheapest ? fmt::format("| {:.0f}% | {} | {} | {:.3f} | {:.2f}% | {:.0f} |\n", 100 * target,
                                 cheapest->config.Label(),
                                 cheapest->config.referencePaths > 0 ? std::string("-") : std::to_string(cheapest->config.photons),
                                 cheapest->seconds,
                                 100 * cheapest->error.rmse, cheapest->peakMiB)
                   : fmt::format("| {:.0f}% | none in the sweep | | | | |\n", 100 * target);
  }
  pb::WriteFileAtomically(path, [&](std::ostream& out) { out << md; });
}

// Every run's error per object (objects.csv), and a table of each object's error in the most accurate run of each
// method (objects.md).
void WriteObjects(const std::string& dir, const std::vector<Run>& runs, const Truth& truth, Bench bench) {
  const size_t count = std::min(truth.objects.size(), kMaxObjects);
  pb::WriteFileAtomically(dir + "/objects.csv", [&](std::ostream& out) {
    out << "run,photons,seconds,object,vertices,mean_truth_w_m2,rmse_rel,mean_bias_rel,truth_noise_rel\n";
    for (const Run& r : runs)
      for (size_t k = 0; k < count; ++k)
        if (const ObjectError& o = r.objects[k]; o.vertices > 0)
          out << fmt::format("{},{},{:.4f},{},{},{:.6g},{:.5f},{:.5f},{:.5f}\n", r.config.Label(), r.config.photons,
                             r.seconds, truth.objects[k], o.vertices, o.meanTruth, o.rmse, o.bias, o.truthNoise);
  });
  std::vector<const Run*> best;  // the least RMSE of each method, in order of first appearance
  for (const Run& r : runs) {
    const auto same = std::find_if(best.begin(), best.end(),
                                   [&](const Run* b) { return b->config.Group(bench) == r.config.Group(bench); });
    if (same == best.end()) best.push_back(&r);
    else if (r.error.rmse < (*same)->error.rmse) *same = &r;
  }
  std::string md = "| object | vertices | mean true H [W/m²] | truth's noise |";
  for (const Run* r : best) md += fmt::format(" {} ({:.2f} s): RMSE, bias |", r->config.Label(), r->seconds);
  md += "\n|---|---|---|---|";
  for (size_t b = 0; b < best.size(); ++b) md += "---|";
  md += "\n";
  const auto row = [&](const std::string& name, uint32_t vertices, double mean, double truthNoise,
                       const auto& errorOf) {
    md += fmt::format("| {} | {} | {:.4g} | {:.2f}% |", name, vertices, mean, 100 * truthNoise);
    for (const Run* r : best) {
      const auto [rmse, bias] = errorOf(*r);
      md += fmt::format(" {:.2f}%, {:+.2f}% |", 100 * rmse, 100 * bias);
    }
    md += "\n";
  };
  for (size_t k = 0; k < count; ++k) {
    const ObjectError& o = best.front()->objects[k];
    if (o.vertices == 0) continue;
    row(truth.objects[k], o.vertices, o.meanTruth, o.truthNoise,
        [&](const Run& r) { return std::pair{r.objects[k].rmse, r.objects[k].bias}; });
  }
  const ErrorSplit& all = best.front()->error;
  row("**all**", uint32_t(truth.reference.size()), all.meanTruth, all.truthNoise,
      [](const Run& r) { return std::pair{r.error.rmse, r.error.bias}; });
  md += fmt::format("| **edge vertices**: mean bias, of the mean H | {} | | |", all.edgeVertices);
  for (const Run* r : best) md += fmt::format(" {:+.2f}% |", 100 * r->error.edgeBias);
  md += fmt::format("\n| **covered vertices** (true H = 0): mean H, of the mean H | {} | 0 | |", all.coveredVertices);
  for (const Run* r : best) md += fmt::format(" {:.2f}% |", 100 * r->error.coveredMean);
  md += "\n";
  pb::WriteFileAtomically(dir + "/objects.md", [&](std::ostream& out) { out << md; });
}

}  // namespace pb::accuracy
