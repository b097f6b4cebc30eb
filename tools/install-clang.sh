#!/usr/bin/env bash
# Installs Debian's clang (with its sanitizer and libFuzzer runtimes) when clang++ is missing; does nothing else.
# tools/fuzz.sh and the sanitizer pass of tools/run-tests.sh build with it.
set -euo pipefail
command -v clang++ >/dev/null && exit 0
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
$sudo apt-get update -qq && $sudo apt-get install -y -qq --no-install-recommends clang >/dev/null
