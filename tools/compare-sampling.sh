#!/usr/bin/env bash
# Photon importance sampling against BRDF sampling on a scene (default: the box, both lights), as issue 5 asks:
# relative RMSE of luminance against a converged BRDF reference, at equal samples per pixel and at equal time.
# Usage: tools/compare-sampling.sh [SCENE.obj] [OUT_DIR]   (after tools/build.sh)
# Environment: SIZE (64x64), REFERENCE_SPP (8192), SWEEP (1,2,4,8,16,32,64,128), PHOTONS (250000, render's
# default), REFERENCE (an existing reference EXR of the same scene and size, instead of rendering one).
# Writes OUT_DIR/table.md: per spp, seconds, relative RMSE, RMSE away from edges (image_error's smooth pixels) and
# mean absolute error (MAE) of each sampler; then one equal-time row: BRDF sampling rendered for as long as photon
# sampling took at the largest count.
set -euo pipefail
cd "$(dirname "$0")/.."
scene=${1:-data/box/box.obj}
out=${2:-out/compare}
size=${SIZE:-64x64}
reference_spp=${REFERENCE_SPP:-8192}
sweep=${SWEEP:-1,2,4,8,16,32,64,128}
photons=${PHOTONS:-250000}
mkdir -p "$out"

if [ -n "${REFERENCE:-}" ]; then
  cp "$REFERENCE" "$out/reference.exr"
else
  build/render "$scene" -o "$out/reference.exr" --size "$size" --spp "$reference_spp" --seed 7 -q
fi
for sampling in brdf photons; do
  build/render "$scene" -o "$out/$sampling.exr" --size "$size" --spp-sweep "$sweep" --sampling "$sampling" \
    --photons "$photons" --report "$out/$sampling.json" -q
done

python3 - "$out" "$sweep" "$scene" "$size" <<'PY'
import json, subprocess, sys
out, sweep = sys.argv[1], [int(s) for s in sys.argv[2].split(",")]
rows = {}
for sampling in ("brdf", "photons"):
    report = json.load(open(f"{out}/{sampling}.json"))
    setup = sum(v for k, v in report["seconds"].items() if k in ("trace photons", "photon map", "importance cache"))
    images = [f"{out}/{sampling}_spp{s}.exr" for s in sweep]
    errors = subprocess.run(["build/image_error", f"{out}/reference.exr"] + images, check=True,
                            capture_output=True, text=True).stdout.split("\n")
    for spp, image, line in zip(sweep, report["images"], errors):
        fields = line.split()
        rows.setdefault(spp, {})[sampling] = (image["seconds"] + setup, float(fields[1]), float(fields[5]),
                                              float(fields[3]))
lines = ["| spp | brdf s | brdf RMSE | away from edges | brdf MAE | photons s (incl. photons, cache) | photons RMSE "
         "| away from edges | photons MAE |",
         "|---|---|---|---|---|---|---|---|---|"]
def cells(r):
    return f"{r[0]:.3f} | {r[1]:.4f} | {r[2]:.4f} | {r[3]:.4f}"
for spp in sweep:
    lines.append(f"| {spp} | {cells(rows[spp]['brdf'])} | {cells(rows[spp]['photons'])} |")
# Equal time: BRDF with as many samples as fit in the time photon sampling took at the largest count.
last = sweep[-1]
matched = max(1, round(last * rows[last]["photons"][0] / rows[last]["brdf"][0]))
report = f"{out}/brdf_equal_time.json"
subprocess.run(["build/render", sys.argv[3], "-o", f"{out}/brdf_equal_time.exr", "--size", sys.argv[4], "--spp",
                str(matched), "--report", report, "-q"], check=True)
seconds = json.load(open(report))["images"][0]["seconds"]
fields = subprocess.run(["build/image_error", f"{out}/reference.exr", f"{out}/brdf_equal_time.exr"], check=True,
                        capture_output=True, text=True).stdout.split()
equal = (seconds, float(fields[1]), float(fields[5]), float(fields[3]))
p = rows[last]["photons"]
lines.append(f"| equal time: brdf {matched} spp | {cells(equal)} | photons {last} spp: {cells(p)} |")
lines.append(f"\nEqual-time ratio photons / BRDF: RMSE {p[1] / equal[1]:.2f}, away from edges {p[2] / equal[2]:.2f}, "
             f"MAE {p[3] / equal[3]:.2f}.")
open(f"{out}/table.md", "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
PY
