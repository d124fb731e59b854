#!/usr/bin/env bash
# fuzz/mutants.sh — do the tests and the fuzzing catch a broken kernel? Each mutant is a
# patch, fuzz/mutants/<name>.patch: a plausible bug (an error bound dropped or shrunk, a
# closed boundary made open, a dropped correction, a wrong exact sign) whose header says
# what it breaks, which fuzz target judges it and which shapes' code it is in:
#
#   mutant: <name>
#   target: <fuzz target of fuzz/targets.txt>
#   shapes: <aabb|obb|plane|sphere|polyhedron|bvh ...>   (bvh: the BVH and its closest hit)
#   breaks: <one line>
#   (blank line, then the diff, as `git diff` writes it)
#
# The script copies the tracked files of the checkout to build/mutants/src (once; later
# runs copy only the files that changed, so the builds there stay incremental), applies
# each patch there with `git apply` (never to the checkout; a patch that no longer
# applies ends the script with status 2) and judges the mutant two ways:
#   suites  the CTest unit, oracle and property suites of its shapes, at their default
#           size (the RAYPROOF_RC_DEFAULT of tests/props/CMakeLists.txt, for bvh_props its
#           RAYPROOF_RC_BVH_DEFAULT), built with g++
#           -O2 in build/mutants/src/build/suites: bound_witness_test (the bounds'
#           witnesses, every shape's), then for each shape, ray_<shape>_test,
#           ray_<shape>_oracle_test, certified_exact_stage_test (that shape's tests) and
#           ray_<shape>_props, in that order (for aabb then ray_aabb_packet_test and
#           ray_aabb_packet_props), up to the first failing test;
#   fuzz    the fuzz target from an EMPTY corpus (same sanitizer build as fuzz/ci.sh, in
#           build/mutants/src/build/fuzz) for at most --seconds, run beside the suites.
# Only the shapes' targets are rebuilt. One line per mutant (which test failed or
# "survived"; fuzz found after how many seconds and executions, or survived), then the
# kill matrix as a Markdown table; exit 1 when a mutant survived both judgements.
#
#   fuzz/mutants.sh [--seconds S] [--only NAME[,NAME...]] [--no-suites] [--no-fuzz] [--check]
#     --seconds S   fuzzing limit per mutant (default 300)
#     --only NAMES  judge these mutants only
#     --no-suites, --no-fuzz   skip one judgement
#     --check       build nothing: check that every patch has its header (a fuzz target,
#                   known shapes) and applies to the checkout (`git apply --check`);
#                   exit 1 when one does not (the CTest test fuzz_mutations_apply)
#   RAYPROOF_MUTANTS_WORK  the work directory (default build/mutants; two runs at once,
#                          say one per judgement, need one each)
#   RAYPROOF_JOBS          build jobs (default 2)
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
seconds=300 only="" check=0 suites=1 fuzz=1
while [ $# -gt 0 ]; do
  case "$1" in
    --check) check=1; shift ;;
    --seconds) seconds="$2"; shift 2 ;;
    --only) only=",$2,"; shift 2 ;;
    --no-suites) suites=0; shift ;;
    --no-fuzz) fuzz=0; shift ;;
    -h|--help) sed -n '2,40p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "unknown argument: $1 (see --help)" >&2; exit 2 ;;
  esac
done

MUTANTS_DIR="$ROOT/fuzz/mutants"
mapfile -t PATCHES < <(find "$MUTANTS_DIR" -maxdepth 1 -name '*.patch' | sort)
if [ -n "$only" ]; then  # in the order given
  PATCHES=()
  for n in ${only//,/ }; do
    [ -f "$MUTANTS_DIR/$n.patch" ] || { echo "no mutant named $n" >&2; exit 2; }
    PATCHES+=("$MUTANTS_DIR/$n.patch")
  done
fi
[ ${#PATCHES[@]} -gt 0 ] || { echo "no patches in fuzz/mutants/" >&2; exit 2; }
# header FIELD PATCH: the value of a header line ("field: value") before the diff.
header() { sed -n "/^diff --git/q; s/^$1: *//p" "$2" | head -1; }
selected() { [ -z "$only" ] || [[ "$only" == *",$1,"* ]]; }

# --check: every patch's header, and `git apply --check` against the checkout.
if [ $check -eq 1 ]; then
  bad=0
  for p in "${PATCHES[@]}"; do
    name=$(basename "$p" .patch)
    selected "$name" || continue
    target=$(header target "$p") shapes=$(header shapes "$p")
    [ "$(header mutant "$p")" = "$name" ] || { echo "mutant $name: its header does not name it" >&2; bad=1; }
    [ -n "$(header breaks "$p")" ] || { echo "mutant $name: no 'breaks:' line" >&2; bad=1; }
    case " ${FUZZ_TARGETS_ALL[*]} " in
      *" $target "*) ;;
      *) echo "mutant $name: '$target' is not a fuzz target" >&2; bad=1 ;;
    esac
    [ -n "$shapes" ] || { echo "mutant $name: no shapes" >&2; bad=1; }
    for s in $shapes; do
      case "$s" in aabb|obb|plane|sphere|polyhedron|bvh) ;; *) echo "mutant $name: unknown shape '$s'" >&2; bad=1 ;; esac
    done
    if ! (cd "$ROOT" && git apply --check "$p") 2>"${TMPDIR:-/tmp}/mutants-check.$$"; then
      echo "mutant $name: the patch does not apply: $(head -3 "${TMPDIR:-/tmp}/mutants-check.$$")" >&2; bad=1
    else
      echo "mutant $name: applies"
    fi
    rm -f "${TMPDIR:-/tmp}/mutants-check.$$"
  done
  exit $bad
fi

# Every patch must apply before anything is built.
for p in "${PATCHES[@]}"; do
  if ! (cd "$ROOT" && git apply --check "$p" 2>/dev/null); then
    echo "mutant $(basename "$p" .patch): the patch no longer applies to the checkout; regenerate it" >&2
    exit 2
  fi
done

work="${RAYPROOF_MUTANTS_WORK:-$ROOT/build/mutants}"
src="$work/src"
suites_bld="$src/build/suites"
fuzz_bld="$src/build/fuzz"
mkdir -p "$src" "$work/logs"
# The copy is a repository of its own, so that `git apply` there patches its files.
[ -d "$src/.git" ] || git -C "$src" init -q
# The tracked files of the checkout as they are now (uncommitted edits included); a file
# is copied only when its content differs, so that unchanged files keep their time
# stamps and the builds stay incremental.
(cd "$ROOT" && git ls-files -z) | python3 -c '
import filecmp, os, shutil, sys
root, dst = sys.argv[1], sys.argv[2]
copied = 0
for rel in sys.stdin.buffer.read().decode().split("\0"):
    if not rel or not os.path.isfile(os.path.join(root, rel)):
        continue
    a, b = os.path.join(root, rel), os.path.join(dst, rel)
    if os.path.isfile(b) and filecmp.cmp(a, b, shallow=False):
        continue
    os.makedirs(os.path.dirname(b), exist_ok=True)
    shutil.copyfile(a, b)
    shutil.copymode(a, b)
    copied += 1
print(f"== mutants: {copied} file(s) copied to {dst}")
' "$ROOT" "$src"

if [ $suites -eq 1 ] && [ ! -f "$suites_bld/build.ninja" ]; then
  echo "== mutants: configuring $suites_bld (g++)"
  cmake -S "$src" -B "$suites_bld" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=g++ \
    -DCMAKE_CXX_FLAGS_RELEASE="-O2 -DNDEBUG" -DRAYPROOF_WERROR=OFF -DRAYPROOF_ORACLE=ON \
    -DRAYPROOF_RENDER=OFF -DRAYPROOF_BENCH=OFF -DRAYPROOF_PYTHON=OFF -DRAYPROOF_FUZZ=OFF \
    >"$work/logs/suites.configure.log" 2>&1 || { cat "$work/logs/suites.configure.log"; exit 1; }
fi
if [ $fuzz -eq 1 ] && [ ! -f "$fuzz_bld/build.ninja" ]; then
  echo "== mutants: configuring $fuzz_bld (clang, libFuzzer, sanitizers)"
  cmake -S "$src" -B "$fuzz_bld" -G Ninja -DCMAKE_CXX_COMPILER="${RAYPROOF_FUZZ_CXX:-clang++}" \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g" \
    -DCMAKE_CXX_FLAGS="$SANITIZE" -DCMAKE_EXE_LINKER_FLAGS="$SANITIZE" \
    -DRAYPROOF_FUZZ=ON -DRAYPROOF_ORACLE=ON -DRAYPROOF_RENDER=OFF -DRAYPROOF_BENCH=OFF \
    -DRAYPROOF_PYTHON=OFF -DBUILD_TESTING=OFF -DRAYPROOF_WERROR=OFF \
    >"$work/logs/fuzz.configure.log" 2>&1 || { cat "$work/logs/fuzz.configure.log"; exit 1; }
fi
rc_default="" rc_bvh_default=""
if [ $suites -eq 1 ]; then
  rc_default=$(sed -n 's/^RAYPROOF_RC_DEFAULT:STRING=//p' "$suites_bld/CMakeCache.txt")
  rc_bvh_default=$(sed -n 's/^RAYPROOF_RC_BVH_DEFAULT:STRING=//p' "$suites_bld/CMakeCache.txt")
fi

# The suites of a shape: "binary gtest-filter" per line, run in this order. The BVH
# ("shape" bvh): bvh_test, then bvh_props.
suite_lines() {
  local s="$1" S
  if [ "$s" = bvh ]; then
    echo "tests/unit/bvh_test *"
    echo "tests/props/bvh_props *"
    return 0
  fi
  S="$(tr '[:lower:]' '[:upper:]' <<<"${s:0:1}")${s:1}"
  [ "$s" = aabb ] && S=Aabb
  [ "$s" = obb ] && S=Obb
  echo "tests/unit/bound_witness_test *"
  echo "tests/unit/ray_${s}_test *"
  echo "tests/oracle/ray_${s}_oracle_test *"
  echo "tests/exact_stage/certified_exact_stage_test *.${S}*"
  echo "tests/props/ray_${s}_props *"
  if [ "$s" = aabb ]; then  # the box packets (ray_aabb_packet.hpp)
    echo "tests/unit/ray_aabb_packet_test *"
    echo "tests/props/ray_aabb_packet_props *"
  fi
}

applied=""
undo() {
  if [ -n "$applied" ]; then
    git -C "$src" apply -R "$applied" || true
    applied=""
  fi
}
judge_pid=""
cleanup() {
  [ -z "$judge_pid" ] || kill -- "$judge_pid" 2>/dev/null || true
  undo
}
trap cleanup EXIT

# judge NAME TARGET: runs the snapshot of the mutant's binaries in $work/run/NAME (the
# fuzz target from an empty corpus in the background, the suites meanwhile) and writes
# the mutant's matrix row to $work/run/NAME/row and its report to $work/run/NAME/report.
judge() {
  local name="$1" target="$2" run="$work/run/$1" fuzz_pid="" suite_result="not run" suite_cell="not run"
  local fuzz_result="not run" fuzz_cell="not run" t0 fuzz_t0 rc rc_params took execs rate cov ft b bin filter out failed
  if [ -x "$run/fuzz/$target" ]; then
    mkdir -p "$run/fuzz/corpus" "$run/fuzz/artifacts"
    fuzz_t0=$(date +%s.%N)
    (cd "$run/fuzz" && exec env -u RAYPROOF_FUZZ_IGNORE -u RAYPROOF_FUZZ_ONLY "./$target" \
       -max_total_time="$seconds" -timeout=10 -rss_limit_mb=4096 -max_len="$(fuzz_max_len "$target")" \
       -dict="$(fuzz_dict "$target")" -print_final_stats=1 -artifact_prefix="$run/fuzz/artifacts/" \
       corpus >"$run/fuzz/fuzz.log" 2>&1) &
    fuzz_pid=$!
  fi
  if [ -f "$run/suites.txt" ]; then
    suite_result="survived"
    t0=$(date +%s)
    while IFS='|' read -r bin filter; do
      out="$run/$bin.$(echo "$filter" | tr -c 'A-Za-z0-9\n' _).log"
      rc_params="$rc_default"
      [ "$bin" != bvh_props ] || rc_params="$rc_bvh_default"
      if ! (cd "$run" && env -u RC_PARAMS RAYPROOF_RC_DEFAULT="$rc_params" "./$bin" \
             --gtest_filter="$filter" --gtest_fail_fast --gtest_brief=1 >"$out" 2>&1); then
        failed=$(sed -n 's/^\[  FAILED  \] \([^ ,]*\).*/\1/p' "$out" | head -1)
        suite_result="killed by $bin ${failed:-(crashed: see $out)}"
        break
      fi
    done <"$run/suites.txt"
    suite_result="$suite_result ($(( $(date +%s) - t0 )) s)"
    suite_cell="${suite_result#killed by }"
    [[ "$suite_result" != survived* ]] || suite_cell="**${suite_result}**"
  fi
  if [ -n "$fuzz_pid" ]; then
    set +e; wait "$fuzz_pid"; rc=$?; set -e
    took=$(awk -v a="$fuzz_t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.0f", b - a }')
    read -r execs rate cov ft < <(fuzz_stats "$run/fuzz/fuzz.log")
    if [ $rc -ne 0 ]; then
      fuzz_result="found after $took s, $execs execs: $(fuzz_finding "$run/fuzz/fuzz.log")"
      fuzz_cell="found: $took s, $execs execs"
    else
      fuzz_result="survived $seconds s ($execs execs)"
      fuzz_cell="**survived** $seconds s ($execs execs)"
    fi
  fi
  {
    echo "   $name suites: $suite_result"
    echo "   $name fuzz:   $fuzz_result"
  } >"$run/report"
  echo "| $name | $target | $suite_cell | $fuzz_cell |" >"$run/row"
  # Killed by neither judgement.
  if [[ "$suite_result" != killed* ]] && [[ "$fuzz_result" != found* ]]; then touch "$run/survived"; fi
  # The snapshots are large: keep only the logs.
  rm -f "$run/fuzz/$target"
  if [ -f "$run/suites.txt" ]; then cut -d'|' -f1 "$run/suites.txt" | sort -u | sed "s|^|$run/|" | xargs rm -f; fi
}

# wait_judge: the running judgement, if any, finished and reported.
wait_judge() {
  if [ -n "$judge_pid" ]; then
    wait "$judge_pid" || true
    cat "$work/run/$judge_name/report"
    judge_pid=""
  fi
}

started=$(date -u +%Y-%m-%dT%H:%MZ)
names=()
ran=0
for p in "${PATCHES[@]}"; do
  name=$(basename "$p" .patch)
  selected "$name" || continue
  ran=$((ran + 1))
  names+=("$name")
  target=$(header target "$p") shapes=$(header shapes "$p") what=$(header breaks "$p")
  log="$work/logs/$name"
  if ! git -C "$src" apply "$p" 2>"$log.apply.log"; then
    echo "mutant $name: the patch no longer applies ($(head -1 "$log.apply.log")); update fuzz/mutants/$name.patch" >&2
    exit 2
  fi
  applied="$p"
  echo "== $name ($target; $shapes): $what"

  # Build the shapes' suites and the fuzz target, then snapshot the binaries, so that the
  # judgement runs while the next mutant builds.
  run="$work/run/$name"
  rm -rf "$run"
  mkdir -p "$run/fuzz"
  if [ $suites -eq 1 ]; then
    for s in $shapes; do suite_lines "$s"; done | awk '!seen[$0]++' >"$run/suites.full"
    targets=$(awk '{ n = split($1, a, "/"); print a[n] }' "$run/suites.full" | sort -u | tr '\n' ' ')
    t0=$(date +%s)
    # shellcheck disable=SC2086
    if ! cmake --build "$suites_bld" --target $targets -j "${RAYPROOF_JOBS:-2}" >"$log.suites.build.log" 2>&1; then
      grep -E "error|FAILED" "$log.suites.build.log" | head -20
      echo "   suites build FAILED (log: $log.suites.build.log)"; exit 1
    fi
    echo "   suites built in $(( $(date +%s) - t0 )) s"
    while read -r bin filter; do
      cp "$suites_bld/$bin" "$run/$(basename "$bin")"
      echo "$(basename "$bin")|$filter"
    done <"$run/suites.full" >"$run/suites.txt"
  fi
  if [ $fuzz -eq 1 ]; then
    t0=$(date +%s)
    if ! cmake --build "$fuzz_bld" --target "$target" -j "${RAYPROOF_JOBS:-2}" >"$log.fuzz.build.log" 2>&1; then
      grep -E "error|FAILED" "$log.fuzz.build.log" | head -20
      echo "   fuzz build FAILED (log: $log.fuzz.build.log)"; exit 1
    fi
    echo "   fuzz target built in $(( $(date +%s) - t0 )) s"
    cp "$fuzz_bld/fuzz/$target" "$run/fuzz/$target"
  fi
  undo

  wait_judge
  judge "$name" "$target" &
  judge_pid=$! judge_name="$name"
done
wait_judge
[ $ran -gt 0 ] || { echo "no mutant named ${only//,/ }" >&2; exit 2; }

echo "== kill matrix (started $started, fuzzing limit $seconds s from an empty corpus)"
echo "| mutant | fuzz target | suites: first failing test (run time) | fuzz from empty |"
echo "|---|---|---|---|"
both_survived=0
for name in "${names[@]}"; do
  cat "$work/run/$name/row"
  [ ! -f "$work/run/$name/survived" ] || both_survived=$((both_survived + 1))
done
if [ $both_survived -gt 0 ]; then
  echo "== $both_survived mutant(s) survived both judgements"
  exit 1
fi
echo "== every mutant was killed"
