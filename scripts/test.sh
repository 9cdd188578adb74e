#!/usr/bin/env bash
# Builds and runs every test: the whole suite in the optimised build, then the library test
# programs again under AddressSanitizer +
# UndefinedBehaviorSanitizer, without the tests named *_Slow and without the fit, synth, eval and
# pipeline test programs: Ceres fits and the generator's level sets take minutes to build and run
# under ASan (valgrind and an earlier ASan run covered them; CMakePresets.json, preset asan).
# Usage: scripts/test.sh [--no-sanitize] [--bench]
#   --no-sanitize  skip the sanitizer stage
#   --bench        also build the benchmark programs (left out by default, and so by CI, to keep
#                  CI well under 30 minutes; bench/RESULTS.md says how each is run)
set -euo pipefail
cd "$(dirname "$0")/.."

sanitize=1
bench=OFF
for arg in "$@"; do
  case "$arg" in
    --no-sanitize) sanitize=0 ;;
    --bench) bench=ON ;;
    *) echo "usage: scripts/test.sh [--no-sanitize] [--bench]" >&2; exit 2 ;;
  esac
done

bash scripts/setup.sh
cmake --preset release -DS2P_BUILD_BENCH="$bench" >/dev/null
cmake --build --preset release
ctest --preset release

if [ "$sanitize" = 1 ]; then
  cmake --preset asan >/dev/null
  cmake --build --preset asan
  ASAN_OPTIONS=detect_leaks=1 LSAN_OPTIONS=suppressions="$PWD/scripts/lsan.supp" \
    UBSAN_OPTIONS=print_stacktrace=1 ctest --preset asan
fi
