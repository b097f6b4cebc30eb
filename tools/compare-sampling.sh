#!/usr/bin/env bash
# Photon importance sampling against BRDF sampling on a scene (default: the box, both lights), as issue 5 asks:
# relative RMSE of luminance against a converged BRDF reference, at equal samples per pixel and at equal time.
# Usage: tools/compare-sampling.sh [SCENE.obj] [OUT_DIR]   (after tools/build.sh)
# Environment: SIZE (64x64), REFERENCE_SPP (8192), SWEEP (1,2,4,8,16,32,64,128), PHOTONS (1000000).
# Writes OUT_DIR/table.md (spp, seconds and RMSE for each sampler) and the images and strips it measured.
set -euo pipefail
cd "$(dirname "$0")/.."
scene=${1:-data/box/box.obj}
out=${2:-out/compare}
size=${SIZE:-64x64}
reference_spp=${REFERENCE_SPP:-8192}
sweep=${SWEEP:-1,2,4,8,16,32,64,128}
photons=${PHOTONS:-1000000}
mkdir -p "$out"

build/render "$scene" -o "$out/reference.exr" --size "$size" --spp "$reference_spp" --seed 7 -q
for sampling in brdf photons; do
  build/render "$scene" -o "$out/$sampling.exr" --size "$size" --spp-sweep "$sweep" --sampling "$sampling" \
    --photons "$photons" --report "$out/$sampling.json" -q
done

python3 - "$out" "$sweep" <<'PY'
import json, subprocess, sys
out, sweep = sys.argv[1], [int(s) for s in sys.argv[2].split(",")]
rows = {}
for sampling in ("brdf", "photons"):
    report = json.load(open(f"{out}/{sampling}.json"))
    setup = sum(v for k, v in report["seconds"].items() if k in ("trace photons", "photon map"))
    images = [f"{out}/{sampling}_spp{s}.exr" for s in sweep]
    errors = subprocess.run(["build/image_error", f"{out}/reference.exr"] + images, check=True,
                            capture_output=True, text=True).stdout.split("\n")
    for spp, image, line in zip(sweep, report["images"], errors):
        rows.setdefault(spp, {})[sampling] = (image["seconds"] + setup, float(line.split()[1]))
lines = ["| spp | brdf s | brdf RMSE | photons s (incl. photon map) | photons RMSE |", "|---|---|---|---|---|"]
for spp in sweep:
    b, p = rows[spp]["brdf"], rows[spp]["photons"]
    lines.append(f"| {spp} | {b[0]:.3f} | {b[1]:.4f} | {p[0]:.3f} | {p[1]:.4f} |")
open(f"{out}/table.md", "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
PY
