#!/usr/bin/env bash
# Installs every Debian package scan2pattern needs to build, test and benchmark.
# Idempotent: when everything is already installed it checks with dpkg and returns at once.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config git
  clang libclang-rt-14-dev            # libFuzzer target for the readers
  libeigen3-dev                       # linear algebra
  libsuitesparse-dev                  # CHOLMOD supernodal Cholesky
  libopenblas0-pthread libopenblas-dev  # optimised BLAS for CHOLMOD, linked first (see CMakeLists.txt)
  libceres-dev                        # Levenberg-Marquardt body fit
  libembree-dev                       # closest point / ray casting
  libnanoflann-dev                    # kd-tree
  libassimp-dev libstb-dev            # scan import, images
  libcgal-dev                         # 2D constrained Delaunay meshing (GPL)
  libboost-dev                        # Boost.Geometry buffer: seam allowances (also a CGAL dependency)
  libopenvdb-dev libboost-iostreams-dev  # level sets (OpenVDB's CMake module needs boost_iostreams)
  libmeshoptimizer-dev                # decimation
  libmaxflow-dev                      # graph-cut baseline
  libcairo2-dev                       # SVG/PDF/PNG drawing
  libdxflib-dev                       # DXF
  libcli11-dev nlohmann-json3-dev libspdlog-dev libfmt-dev
  libtbb-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  zlib1g-dev libpng-dev
  # GarmentCode's loader (../shared/validators/gc_check.py), run on pattern.json by the tests
  python3 python3-numpy python3-scipy python3-svgwrite python3-cairosvg python3-matplotlib
  python3-yaml python3-psutil
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#PACKAGES[@]} packages present"
  exit 0
fi

echo "setup: installing ${#missing[@]} packages: ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
echo "setup: done"
