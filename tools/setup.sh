#!/usr/bin/env bash
# Installs what om_dthex needs on Debian 12 (as root), then configures and builds into build/.
# Idempotent: packages already present are not reinstalled; the build is incremental.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  build-essential cmake pkg-config
  libopenmesh-dev libtet1.5-dev tetgen libeigen3-dev libgtest-dev
  libcli11-dev nlohmann-json3-dev libexodusii-dev libjemalloc-dev calculix-ccx
  python3 python3-vtk9 python3-numpy python3-scipy python3-meshio python3-netcdf4 python3-gmsh
  clang libclang-rt-14-dev
  chromium
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$jobs"
echo "setup: built build/om_dthex"
