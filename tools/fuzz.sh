#!/usr/bin/env bash
# Fuzzes every file reader with libFuzzer (clang, from Debian), AddressSanitizer and UndefinedBehaviorSanitizer,
# each for a bounded time, as many at once as there are cores:
#   obj_loader   OBJ/MTL scenes (mesh/obj_loader.h, mesh/mtl_loader.h), with the textures they name
#   gltf_loader  glTF 2.0 scenes, .gltf with data URIs or .glb (mesh/gltf_loader.h), with their images
#   texture      PNG, JPEG, TGA and BMP textures (mesh/texture.h)
#   camera       camera JSON files (mesh/camera.h)
#   light_file   lights JSON files (mesh/light_file.h)
#   ies_file     IES LM-63 photometric files (mesh/ies_file.h)
#   sky_image    sky images, OpenEXR and Radiance HDR (mesh/sky_image.h)
#   photon_file  photon files for --resume (baker/files/photon_file.h), their CRC recomputed so mutations get past it
# Usage: tools/fuzz.sh [SECONDS per target, default 60] [TARGET ...; default all]. The targets are built in the
# sanitized tree (tools/build-sanitized.sh, which installs clang if it is missing). Seeds come from
# tests/fuzz/corpus/TARGET (the photon files are written by photon_file_seeds); new interesting inputs land in
# build-asan/fuzz/corpus/TARGET, and a crash, leak, sanitizer finding or 10 s hang fails the run with the input that
# caused it in build-asan/fuzz/findings/.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(obj_loader gltf_loader texture camera light_file ies_file sky_image photon_file)
bash tools/build-sanitized.sh photon_file_seeds "${targets[@]/#/fuzz_}"
bin=build-asan out=build-asan/fuzz
rm -rf "$out/seeds" && mkdir -p "$out/seeds" "$out/findings"
"$bin/photon_file_seeds" "$out/seeds/photon_file"
# One target: its result lines, or the log's tail and the finding, with libFuzzer's exit status.
fuzz_one() {
  local target=$1 seeds=tests/fuzz/corpus/$1 log=$out/$1.log status=0
  [ "$target" != photon_file ] || seeds=$out/seeds/photon_file
  mkdir -p "$out/corpus/$target"
  "$bin/fuzz_$target" "$out/corpus/$target" "$seeds" -max_total_time="$seconds" -max_len=4096 \
    -timeout=10 -artifact_prefix="$out/findings/$target-" -print_final_stats=1 >"$log" 2>&1 || status=$?
  echo "== fuzz_$target for $seconds s, seeds in $seeds"
  grep -E "^(Done [0-9]+ runs|stat::number_of_executed_units|stat::new_units_added)" "$log" || true
  if [ "$status" -ne 0 ]; then
    tail -n 60 "$log"
    echo "fuzz_$target found a bug (exit $status); the input is in $out/findings/, the log in $log"
  fi
  return "$status"
}
# As many targets at once as there are cores (each libFuzzer process runs on one).
failed=0
for target in "${targets[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "$(nproc)" ]; do wait -n || failed=1; done
  fuzz_one "$target" &
done
while [ "$(jobs -rp | wc -l)" -gt 0 ]; do wait -n || failed=1; done
exit "$failed"
