#!/usr/bin/env bash
# Doubles one axis of a scene at a time and prints each stage's time before and after, and their ratio (issue 38:
# every stage's cost at most doubles, x 1.15, when one axis doubles):
#   triangles          make-scene grid-room --triangles N, then 2N
#   area               the same room (N triangles) at --scale 1, then sqrt(2): twice the area, the same triangles
#   lights             make-scene led-room --lamps L, then 2L
#   emitter triangles  make-scene one-light --light-triangles E, then 2E
# Each bake: bake ROOM -q -o out.ply --photons P --report r.json, on all cores; stages under 0.05 s are left out
# (their ratio is noise). Usage: tools/scaling-axes.sh [BUILD_DIR] (N, L, E, P: environment, defaults below).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
N=${N:-200000} L=${L:-20000} E=${E:-20000} P=${P:-1000000}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

scene() {  # kind, option, value -> the OBJ's path
  "$build/make-scene" "$1" "$2" "$3" --out "$out/$1-$3" >/dev/null
  echo "$out/$1-$3/room.obj"
}
bake() {  # report, obj, extra options
  local report=$1 obj=$2
  shift 2
  "$build/bake" "$obj" -q -o "$out/out.ply" --photons "$P" --report "$report" "$@" 2>/dev/null
}
compare() {  # axis, report before, report after
  python3 - "$1" "$2" "$3" <<'PY'
import json, sys
axis, a, b = sys.argv[1], json.load(open(sys.argv[2]))["seconds"], json.load(open(sys.argv[3]))["seconds"]
rows = [(k, a[k], b.get(k, 0.0)) for k in a if k != "total" and max(a[k], b.get(k, 0.0)) >= 0.05]
rows.append(("total", a["total"], b["total"]))
print(f"{axis}:")
for k, x, y in rows:
    print(f"  {k:<12} {x:8.3f} s -> {y:8.3f} s   x{y / x if x > 0 else float('inf'):.2f}")
PY
}

room=$(scene grid-room --triangles "$N")
bake "$out/t1.json" "$room"
bake "$out/t2.json" "$(scene grid-room --triangles $((2 * N)))"
compare "triangles ($N -> $((2 * N)))" "$out/t1.json" "$out/t2.json"
bake "$out/a2.json" "$room" --scale 1.41421356
compare "area (x2 at $N triangles)" "$out/t1.json" "$out/a2.json"
bake "$out/l1.json" "$(scene led-room --lamps "$L")"
bake "$out/l2.json" "$(scene led-room --lamps $((2 * L)))"
compare "lights ($L -> $((2 * L)))" "$out/l1.json" "$out/l2.json"
bake "$out/e1.json" "$(scene one-light --light-triangles "$E")"
bake "$out/e2.json" "$(scene one-light --light-triangles $((2 * E)))"
compare "emitter triangles ($E -> $((2 * E)))" "$out/e1.json" "$out/e2.json"
