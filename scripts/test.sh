#!/usr/bin/env bash
# Builds and runs every test: the whole suite in the optimised build (benchmarks are built
# too, so they keep compiling), then the library test programs again under AddressSanitizer +
# UndefinedBehaviorSanitizer, without the tests named *_Slow and without the fit, synth, eval and
# pipeline test programs: Ceres fits and the generator's level sets take minutes to build and run
# under ASan (valgrind and an earlier ASan run covered them; CMakePresets.json, preset asan).
# Usage: scripts/test.sh [--no-sanitize]
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup.sh
cmake --preset release >/dev/null
cmake --build --preset release
ctest --preset release

if [ "${1:-}" != "--no-sanitize" ]; then
  cmake --preset asan >/dev/null
  cmake --build --preset asan
  ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 ctest --preset asan
fi
