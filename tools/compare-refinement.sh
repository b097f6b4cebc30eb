#!/usr/bin/env bash
# Adaptive refinement against uniform subdivision on a scene (default: the box), as issue 4 asks: the
# displayed-luminance interpolation error (against the estimator itself, at lattice points at most h/2 apart:
# largest, 99th percentile by area, mean by area) against the written mesh's vertex count, with the seconds the
# mesh stage took.
# Usage: tools/compare-refinement.sh [SCENE.obj] [OUT_DIR]   (after tools/build.sh)
# Environment: PHOTONS (2000000), H (0.05), LEVELS (1,2,3), TOLERANCES (0.08,0.04,0.02,0.01,0.005,0.0025,0.001).
# Writes OUT_DIR/table.md: one row per run, then, per uniform level, the fewest vertices with which an adaptive
# run is at least as accurate, by the 99th percentile and by the largest error, and the ratios.
set -euo pipefail
cd "$(dirname "$0")/.."
scene=${1:-data/box/box.obj}
out=${2:-out/refinement}
photons=${PHOTONS:-2000000}
h=${H:-0.05}
levels=${LEVELS:-1,2,3}
tolerances=${TOLERANCES:-0.08,0.04,0.02,0.01,0.005,0.0025,0.001}
mkdir -p "$out"

common=("$scene" --photons "$photons" --h "$h" --seed 1 --direct photons -q)  # as the table in docs/bake.md was measured
for level in ${levels//,/ }; do
  build/bake "${common[@]}" -o "$out/uniform_$level.ply" --subdivide "$level" --report "$out/uniform_$level.json"
done
for tolerance in ${tolerances//,/ }; do
  build/bake "${common[@]}" -o "$out/adaptive_$tolerance.ply" --refine --tolerance "$tolerance" \
    --max-vertices 10000000 --report "$out/adaptive_$tolerance.json"
done

python3 - "$out" "$levels" "$tolerances" <<'PY'
import json, sys
out, levels, tolerances = sys.argv[1], sys.argv[2].split(","), sys.argv[3].split(",")
def row(name):
    r = json.load(open(f"{out}/{name}.json"))
    m = r["refine"]
    return {"v": r["output"]["vertices"], "max": m["max_error"], "p99": m["p99_error"], "mean": m["mean_error"],
            "s": m["seconds"]}
runs = [(f"uniform, {l} levels", row(f"uniform_{l}")) for l in levels]
adaptive = [(f"adaptive, tolerance {t}", row(f"adaptive_{t}")) for t in tolerances]
lines = ["| mesh | vertices | largest error | 99% of the area | mean | mesh stage s |", "|---|---|---|---|---|---|"]
for name, r in runs + adaptive:
    lines.append(f"| {name} | {r['v']} | {r['max']:.4f} | {r['p99']:.4f} | {r['mean']:.4f} | {r['s']:.2f} |")
lines += ["", "| uniform | by | its error | fewest adaptive vertices at least as accurate | uniform / adaptive |",
          "|---|---|---|---|---|"]
for name, u in runs:
    for by in ("p99", "max"):
        fits = [a["v"] for _, a in adaptive if a[by] <= u[by]]
        ratio = f"{u['v'] / min(fits):.1f}" if fits else "—"
        lines.append(f"| {name}, {u['v']} vertices | {by} | {u[by]:.4f} | {min(fits) if fits else 'none'} | {ratio} |")
open(f"{out}/table.md", "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
PY
