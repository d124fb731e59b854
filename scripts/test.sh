#!/usr/bin/env bash
# Installs what is missing, builds with g++ and with clang at -O2 (two build
# directories: g++ 12 has a float-rounding miscompilation the suites must not hide),
# and runs the whole CTest suite in each. Exits non-zero on any failure.
#   RAYPROOF_JOBS=N   parallel build and test jobs (default: all cores)
#   RC_PARAMS=...     passed to the RapidCheck properties (see README)
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
install_missing
mkdir -p "$ROOT/build"
status=0
for cc in g++ clang++; do
  name=$([ "$cc" = g++ ] && echo gcc || echo clang)
  echo "== $name: configure and build (-O2)"
  start=$(date +%s)
  configure_and_build "$name" "$cc" -DCMAKE_CXX_FLAGS_RELEASE="-O2 -DNDEBUG" || { status=1; continue; }
  echo "== $name: built in $(( $(date +%s) - start )) s; running the suite"
  ctest --test-dir "$ROOT/build/$name" -j "$JOBS" --output-on-failure --timeout 1500 \
    >"$ROOT/build/$name.ctest.log" 2>&1 || status=1
  grep -E "tests passed|tests failed|Label Time|^[a-z-]+ +=|\(Failed\)|\(Timeout\)|\(SEGFAULT\)|Exception" \
    "$ROOT/build/$name.ctest.log" || true
  if [ $status -ne 0 ]; then
    echo "== $name: failures (full log: build/$name.ctest.log)"
    grep -B2 -A40 -E "\*\*\*Failed|\*\*\*Timeout|\*\*\*Exception" "$ROOT/build/$name.ctest.log" | head -200
  fi
done
# The bounded fuzzing stage: sanitizer build, regression replay, RAYPROOF_FUZZ_SECONDS
# (default 20) of fuzzing per target from the committed corpora.
if [ -x "$ROOT/fuzz/ci.sh" ]; then
  "$ROOT/fuzz/ci.sh" || status=1
fi
[ $status -eq 0 ] && echo "== all suites passed" || echo "== FAILED"
exit $status
