#!/usr/bin/env bash
# Installs the Khronos glTF Validator (npm gltf-validator) into .cache/gltf-validator for the test of the glTF
# output (tests/baker/gltf_output_test.cpp, through tools/gltf-validate.js). Installs Node.js and npm from Debian
# first where the machine has none. Idempotent: a second run only checks that the module is there.
set -euo pipefail
cd "$(dirname "$0")/.."
version=2.0.0-dev.3.10
dir=.cache/gltf-validator
if [ -f "$dir/node_modules/gltf-validator/package.json" ] && command -v node >/dev/null; then
  echo "install-gltf-validator: gltf-validator present"
  exit 0
fi
if ! command -v npm >/dev/null; then
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends nodejs npm >/dev/null
fi
mkdir -p "$dir"
npm install --prefix "$dir" --no-audit --no-fund --silent "gltf-validator@$version"
echo "install-gltf-validator: gltf-validator $version installed in $dir"
