#!/usr/bin/env bash
# Installs the Debian 12 packages photonbake builds against, and nothing else.
# Idempotent: packages already present are skipped, so a second run costs one dpkg query.
# Needs root (or sudo) only when something is missing.
set -euo pipefail

packages=(
  # toolchain
  build-essential cmake ninja-build pkg-config
  # core
  libembree-dev libtbb-dev libopenmesh-dev libcgal-dev libosd-dev
  libopenexr-dev libimath-dev
  # useful
  libnanoflann-dev libeigen3-dev libcli11-dev
  nlohmann-json3-dev libfmt-dev libgtest-dev libbenchmark-dev
  libpng-dev zlib1g-dev libstb-dev libtinygltf-dev
  # bake-mpi (tools/bake_mpi.cpp): Open MPI and its mpirun
  openmpi-bin libopenmpi-dev
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install-deps: done"
