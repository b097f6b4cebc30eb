#!/usr/bin/env bash
# Keeps tests/ctest-costs/ up to date: each test's time in the last run of build/ (plain.txt) and build-asan/
# (sanitized.txt), as ctest recorded it. tools/run-tests.sh gives a tree without timings these, so that ctest
# starts the longest tests first on a clean clone too (in declaration order, the sanitizer pass took 292 s on
# 2 cores where it takes 233 s longest first). Run after a full tools/run-tests.sh when tests were added or grew.
# Names with spaces (ctest's ' # GetParam() = ...' suffix) are left out: ctest cannot read them back, and they
# are the short parametrised tests, which it runs last.
set -euo pipefail
cd "$(dirname "$0")/.."
copy() {
  local data="$1/Testing/Temporary/CTestCostData.txt"
  [ -f "$data" ] || { echo "update-test-costs: no $data; run tools/run-tests.sh first" >&2; exit 1; }
  sed '/^---$/,$d' "$data" | awk 'NF == 3 && $3 > 0 { printf "%s %s %.2f\n", $1, $2, $3 }' | sort > "tests/ctest-costs/$2.txt"
  echo "update-test-costs: tests/ctest-costs/$2.txt, $(wc -l < "tests/ctest-costs/$2.txt") tests"
}
copy build plain
copy build-asan sanitized
