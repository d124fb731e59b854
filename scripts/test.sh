#!/usr/bin/env bash
# Installs what is missing, builds with g++ and with clang at -O2 (two build
# directories: g++ 12 has a float-rounding miscompilation the suites must not hide),
# and runs the whole CTest suite in each, then the kernel-level suites under
# floating-point contraction (below). Exits non-zero on any failure.
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
# The contraction stage: the kernel-level suites (labels unit, property, oracle,
# fuzz-replay) built with g++ and clang at -O3 -march=native -ffp-contract=fast, where
# the compiler fuses a*b + c into one fma wherever it may (rayproof/detail/eft.hpp says
# why the kernel's answers hold anyway). Only the test programs are built (by name: the
# executables under tests/unit, oracle, props, exact_stage and regressions, not the
# measurement tools), in build/gcc-contract and build/clang-contract.
# RAYPROOF_CONTRACT_STAGE=0 skips it; RAYPROOF_CONTRACT_COMPILERS="g++" (or "clang++")
# runs it with one compiler (default: both).
if [ "${RAYPROOF_CONTRACT_STAGE:-1}" != 0 ]; then
  for cc in ${RAYPROOF_CONTRACT_COMPILERS:-g++ clang++}; do
    name=$([ "$cc" = g++ ] && echo gcc || echo clang)-contract
    echo "== $name: configure and build (-O3 -march=native -ffp-contract=fast)"
    start=$(date +%s)
    dir="$ROOT/build/$name"
    cmake -S "$ROOT" -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER="$cc" -DRAYPROOF_WERROR=ON \
      -DCMAKE_CXX_FLAGS_RELEASE="-O3 -march=native -ffp-contract=fast -DNDEBUG" -DRAYPROOF_RENDER=OFF \
      -DRAYPROOF_TOOLS=OFF -DRAYPROOF_BENCH=OFF -DRAYPROOF_PYTHON=OFF -DRAYPROOF_FUZZ=OFF \
      >"$dir.configure.log" 2>&1 || { cat "$dir.configure.log"; status=1; continue; }
    targets=$(ninja -C "$dir" -t targets all | sed -n 's#^tests/\(unit\|oracle\|props\|exact_stage\|regressions\)/\([A-Za-z0-9_]*\): CXX_EXECUTABLE_LINKER.*#\2#p' | grep -v '^kernel_measure' | sort -u)
    cmake --build "$dir" -j "$JOBS" --target $targets >"$dir.build.log" 2>&1 ||
      { grep -E "error|FAILED|warning" "$dir.build.log" | head -50; status=1; continue; }
    built=$(date +%s)
    ctest --test-dir "$dir" -j "$JOBS" -L 'unit|property|oracle|fuzz-replay' -LE cli \
      -E '^(fp_model_refused|kernel_headers_stand_alone)$' --output-on-failure --timeout 1500 \
      >"$dir.ctest.log" 2>&1 || { status=1; grep -B2 -A40 -E "\*\*\*Failed|\*\*\*Timeout|\*\*\*Exception" "$dir.ctest.log" | head -200; }
    grep -E "tests passed|tests failed" "$dir.ctest.log" || true
    echo "== $name: built in $(( built - start )) s, suites ran in $(( $(date +%s) - built )) s"
  done
fi
# The bounded fuzzing stage: sanitizer build, regression replay, RAYPROOF_FUZZ_SECONDS
# (default 20) of fuzzing per target from the committed corpora.
if [ -x "$ROOT/fuzz/ci.sh" ]; then
  "$ROOT/fuzz/ci.sh" || status=1
fi
[ $status -eq 0 ] && echo "== all suites passed" || echo "== FAILED"
exit $status
