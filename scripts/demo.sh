#!/usr/bin/env bash
# Builds scan2pattern and runs its main job on the built-in demo scan.
# Usage: scripts/demo.sh [OUT_DIR]   (default: demo_out)
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-demo_out}"

bash scripts/setup.sh
cmake --preset release >/dev/null
cmake --build --preset release --target scan2pattern
build/release/app/scan2pattern demo -o "$out"
