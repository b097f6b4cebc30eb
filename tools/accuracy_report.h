// The accuracy tool's outputs (tools/accuracy.cpp), each written atomically: accuracy.csv (one row per run), the
// log-log plot accuracy.svg of relative RMSE against seconds with each curve's lower envelope, cheapest.md (the
// cheapest run reaching each error target) and, on a bundled scene, objects.csv and objects.md (each object's
// relative RMSE and mean bias).
#pragma once

#include <string>
#include <vector>

#include "tools/accuracy_runs.h"

namespace pb::accuracy {

void WriteCsv(const std::string& path, const std::vector<Run>& runs);
// Each curve (Config::Group) in its own colour.
void WriteSvg(const std::string& path, const std::vector<Run>& runs, Bench bench);
void WriteCheapest(const std::string& path, const std::vector<Run>& runs);
// DIR/objects.csv: every run's error per object; DIR/objects.md: each object's error in the most accurate run of
// each curve.
void WriteObjects(const std::string& dir, const std::vector<Run>& runs, const Truth& truth, Bench bench);

}  // namespace pb::accuracy
