#!/usr/bin/env bash
# Installs what is missing, then builds and runs the suites in four configurations and a
# bounded fuzzing stage. Exits non-zero on any failure.
#   1. g++ -O2 (build/gcc): everything (kernel, oracle, tracer, bindings, tools,
#      benchmarks) and the whole CTest suite.
#   2. clang -O2 (build/clang): the kernel-level suites (labels unit, property, oracle,
#      fpenv, consumer), built by name. g++ 12 has a float-rounding miscompilation the
#      suites must not hide, so the kernel's suites run under both compilers. The tracer,
#      bindings and tools only consume the kernel: they are built and run under g++; the
#      regression and corpus replays run under clang in the fuzzing stage (clang -O2,
#      with sanitizers).
#   3. The contraction stage (below).
#   4. The bounded fuzzing stage (fuzz/ci.sh).
# The stages are chosen so the script stays within about an hour on two cores: each
# compiler configuration builds the optimized kernel-level programs anew, which is most
# of the time.
#   RAYPROOF_JOBS=N   parallel build and test jobs (default: all cores)
#   RC_PARAMS=...     passed to the RapidCheck properties (see README)
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
install_missing
mkdir -p "$ROOT/build"
status=0

# show_failures NAME: the failing tests of build/NAME.ctest.log, with their output.
show_failures() {
  echo "== $1: failures (full log: build/$1.ctest.log)"
  grep -B2 -A40 -E "\*\*\*Failed|\*\*\*Timeout|\*\*\*Exception" "$ROOT/build/$1.ctest.log" | head -200
}

# kernel_stage NAME CXX FLAGS PROGRAMS LABELS [EXCLUDE]: configures build/NAME without the
# tracer, tools, benchmarks, bindings and fuzzing engine, builds the test programs whose
# "<dir>/<program>" matches the extended regular expression PROGRAMS (dir: unit, oracle,
# props, exact_stage, regressions, fp_env) and runs the tests of LABELS among them, but
# those whose names match EXCLUDE. The measurement tool kernel_measure is never built.
kernel_stage() {
  local name="$1" cc="$2" flags="$3" programs="$4" labels="$5" exclude="${6:-}" start built targets
  local dir="$ROOT/build/$name"
  echo "== $name: configure and build ($flags)"
  start=$(date +%s)
  configure_dir "$name" "$cc" -DCMAKE_CXX_FLAGS_RELEASE="$flags -DNDEBUG" -DRAYPROOF_RENDER=OFF \
    -DRAYPROOF_TOOLS=OFF -DRAYPROOF_BENCH=OFF -DRAYPROOF_PYTHON=OFF -DRAYPROOF_FUZZ=OFF || return 1
  targets=$(ninja -C "$dir" -t targets all |
    sed -n 's#^tests/\(unit\|oracle\|props\|exact_stage\|regressions\|fp_env\)/\([A-Za-z0-9_]*\): CXX_EXECUTABLE_LINKER.*#\1/\2#p' |
    grep -E "^($programs)\$" | grep -v '/kernel_measure' | sed 's#.*/##' | sort -u)
  [ -n "$targets" ] || { echo "== $name: no test programs match '$programs'"; return 1; }
  build_dir "$name" $targets || return 1
  built=$(date +%s)
  local rc=0
  ctest --test-dir "$dir" -j "$JOBS" -L "$labels" -LE cli ${exclude:+-E "$exclude"} --output-on-failure \
    --timeout 1500 >"$dir.ctest.log" 2>&1 || rc=1
  grep -E "tests passed|tests failed" "$dir.ctest.log" || true
  [ $rc -eq 0 ] || show_failures "$name"
  echo "== $name: built in $(( built - start )) s, suites ran in $(( $(date +%s) - built )) s"
  return $rc
}

# 1. g++ -O2, everything.
echo "== gcc: configure and build (-O2)"
start=$(date +%s)
if configure_and_build gcc g++ -DCMAKE_CXX_FLAGS_RELEASE="-O2 -DNDEBUG"; then
  echo "== gcc: built in $(( $(date +%s) - start )) s; running the suite"
  rc=0
  ctest --test-dir "$ROOT/build/gcc" -j "$JOBS" --output-on-failure --timeout 1500 \
    >"$ROOT/build/gcc.ctest.log" 2>&1 || rc=1
  grep -E "tests passed|tests failed|Label Time|^[a-z-]+ +=|\(Failed\)|\(Timeout\)|\(SEGFAULT\)|Exception" \
    "$ROOT/build/gcc.ctest.log" || true
  [ $rc -eq 0 ] || { status=1; show_failures gcc; }
  echo "== gcc: suite ran in $(( $(date +%s) - start )) s since the build began"
else
  status=1
fi

# 2. clang -O2, the kernel-level suites (every unit, oracle, property, exact-stage and
#    environment program).
kernel_stage clang clang++ "-O2" "(unit|oracle|props|exact_stage|fp_env)/[A-Za-z0-9_]*" \
  'unit|property|oracle|fpenv|consumer' || status=1

# 3. The contraction stage: the kernel-level suites built with g++ and clang at -O3
# -march=native -ffp-contract=fast, where the compiler fuses a*b + c into one fma
# wherever it may (rayproof/detail/eft.hpp says why the kernel's answers hold anyway).
# Built: the property suites, the exact stage's test, the hand-computed tests of each
# shape, the bounds' witnesses, the error-free transformations and exact arithmetic
# (split products forced on in one of them), the programs that hold two forms of a
# query to the same bits (batch, packets, prepared rays) and, under g++ (which fuses by
# default in GNU mode wherever the target has FMA), the regression and corpus replays.
# Not built: the AVX2 copies of the packet and batch tests (-march=native targets AVX2
# already) and the suites of the queries built on the above (the BVH, closest hit,
# surface points, run-time mode), which the plain stages run.
# RAYPROOF_CONTRACT_STAGE=0 skips it; RAYPROOF_CONTRACT_COMPILERS="g++" (or "clang++")
# runs it with one compiler (default: both).
if [ "${RAYPROOF_CONTRACT_STAGE:-1}" != 0 ]; then
  contract_unit="unit/(ray_(aabb|obb|plane|sphere|polyhedron)_test|bound_witness_test|batch_test|ray_aabb_packet_test"
  contract_unit+="|prepared_ray_test|compensated_test|compensated_test_split_products|exact_test|faithful_test"
  contract_unit+="|limbs_test|float_rounding_guard|rounding_test)"
  # Tests of the build and the checkout rather than of the kernel's arithmetic.
  contract_exclude='^(fp_model_refused|kernel_headers_stand_alone|fuzz_mutations_apply)$'
  for cc in ${RAYPROOF_CONTRACT_COMPILERS:-g++ clang++}; do
    programs="$contract_unit|props/[A-Za-z0-9_]*|exact_stage/[A-Za-z0-9_]*" labels='unit|property|oracle'
    if [ "$cc" = g++ ]; then
      programs+="|regressions/[A-Za-z0-9_]*" labels+='|fuzz-replay'
    fi
    kernel_stage "$([ "$cc" = g++ ] && echo gcc || echo clang)-contract" "$cc" "-O3 -march=native -ffp-contract=fast" \
      "$programs" "$labels" "$contract_exclude" || status=1
  done
fi
# The bounded fuzzing stage: sanitizer build, regression replay, RAYPROOF_FUZZ_SECONDS
# (default 20) of fuzzing per target from the committed corpora.
if [ -x "$ROOT/fuzz/ci.sh" ]; then
  "$ROOT/fuzz/ci.sh" || status=1
fi
[ $status -eq 0 ] && echo "== all suites passed" || echo "== FAILED"
exit $status
