#!/usr/bin/env bash
# fuzz/ci.sh — the bounded fuzzing stage of the test script: builds the fuzz targets in
# build/fuzz (clang, libFuzzer, ASan + UBSan), replays tests/regressions/<target>/ with
# each target, then fuzzes each target for a bounded time starting from its committed
# corpus (fuzz/corpus/<target>/, which is not modified: new inputs go to a scratch
# directory). Prints one line per target and exits non-zero on any finding.
#   RAYPROOF_FUZZ_SECONDS  seconds of fuzzing per target (default 20; 0: replay only)
#   RAYPROOF_FUZZ_CXX, RAYPROOF_FUZZ_RENDER, RAYPROOF_JOBS: see fuzz/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
seconds="${RAYPROOF_FUZZ_SECONDS:-20}"
# CI runs the checks unfiltered.
unset RAYPROOF_FUZZ_IGNORE RAYPROOF_FUZZ_ONLY

start=$(date +%s)
echo "== fuzz: building the targets (build/fuzz)"
fuzz_build || { echo "== fuzz: build FAILED"; exit 1; }
echo "== fuzz: built in $(( $(date +%s) - start )) s; ${seconds} s per target"

status=0
work="$FUZZ_BUILD/ci"
rm -rf "$work"
for t in $(fuzz_targets); do
  bin=$(fuzz_bin "$t")
  mkdir -p "$work/$t/corpus" "$work/$t/artifacts"
  result=ok
  detail=""

  # 1. The regressions, each run once.
  mapfile -t regs < <(regression_files "$t")
  if [ ${#regs[@]} -gt 0 ]; then
    if ! "$bin" -rss_limit_mb=4096 -timeout=30 "${regs[@]}" >"$work/$t/regressions.log" 2>&1; then
      result=FAIL
      detail="regression: $(fuzz_finding "$work/$t/regressions.log")"
    fi
  fi

  # 2. Bounded fuzzing from the committed corpus.
  execs=0 rate=0 cov=0 ft=0
  if [ "$seconds" -gt 0 ]; then
    corpus_dirs=("$work/$t/corpus")
    [ -d "$ROOT/fuzz/corpus/$t" ] && corpus_dirs+=("$ROOT/fuzz/corpus/$t")
    if ! "$bin" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=4096 -max_len="$(fuzz_max_len "$t")" \
        -dict="$(fuzz_dict "$t")" -print_final_stats=1 -artifact_prefix="$work/$t/artifacts/" \
        "${corpus_dirs[@]}" >"$work/$t/fuzz.log" 2>&1; then
      result=FAIL
      detail="${detail:+$detail; }fuzzing: $(fuzz_finding "$work/$t/fuzz.log") (artifacts: build/fuzz/ci/$t/artifacts/)"
    fi
    read -r execs rate cov ft < <(fuzz_stats "$work/$t/fuzz.log")
  fi
  [ "$result" = ok ] || status=1
  printf '%-16s %-4s  regressions %3d  %8s execs  %6s exec/s  cov %5s  ft %6s  %s\n' \
    "$t" "$result" "${#regs[@]}" "$execs" "$rate" "$cov" "$ft" "$detail"
done
echo "== fuzz: $( [ $status -eq 0 ] && echo passed || echo FAILED ) in $(( $(date +%s) - start )) s (logs: build/fuzz/ci/)"
exit $status
