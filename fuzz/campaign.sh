#!/usr/bin/env bash
# fuzz/campaign.sh — a local fuzzing campaign: builds the fuzz targets (build/fuzz), runs
# each with libFuzzer's -fork=J for a time limit, starting from its committed corpus,
# merges the inputs that add coverage into fuzz/corpus/<target>/, minimizes every finding
# (keeping the same kind of failure) and prints executions, coverage and findings per
# target. Findings stay in build/fuzz/campaign/<target>/artifacts/: after triage, copy the
# minimized ones (min-*) to tests/regressions/<target>/ (see docs/fuzzing.md).
#
#   fuzz/campaign.sh [--minutes M] [--jobs J] [--targets "t1 t2"] [--no-merge]
#     --minutes M   time per target (default 10; fractions allowed, e.g. 0.5)
#     --jobs J      libFuzzer -fork=J worker processes (default 1)
#     --targets     a subset of the targets of fuzz/targets.txt (default: all that were built)
#     --no-merge    leave fuzz/corpus/ untouched
#   RAYPROOF_FUZZ_IGNORE / RAYPROOF_FUZZ_ONLY: triage filters (fuzz/fuzz_common.hpp)
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
minutes=10 jobs=1 merge=1 targets=""
while [ $# -gt 0 ]; do
  case "$1" in
    --minutes) minutes="$2"; shift 2 ;;
    --jobs) jobs="$2"; shift 2 ;;
    --targets) targets="$2"; shift 2 ;;
    --no-merge) merge=0; shift ;;
    -h|--help) sed -n '2,16p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "unknown argument: $1 (see --help)" >&2; exit 2 ;;
  esac
done
seconds=$(awk -v m="$minutes" 'BEGIN { s = int(m * 60 + 0.5); print (s < 1 ? 1 : s) }')

echo "== campaign: building the targets (build/fuzz)"
fuzz_build || { echo "== campaign: build FAILED"; exit 1; }
[ -n "$targets" ] || targets="$(fuzz_targets | tr '\n' ' ')"
[ -n "${RAYPROOF_FUZZ_IGNORE:-}" ] && echo "== campaign: ignoring violations matching: $RAYPROOF_FUZZ_IGNORE"

summary=()
total_findings=0
for t in $targets; do
  bin=$(fuzz_bin "$t")
  [ -x "$bin" ] || { echo "no such target: $t" >&2; exit 2; }
  dir="$FUZZ_BUILD/campaign/$t"
  rm -rf "$dir"
  mkdir -p "$dir/corpus" "$dir/artifacts" "$ROOT/fuzz/corpus/$t"
  before=$(find "$ROOT/fuzz/corpus/$t" -type f ! -name '.*' | wc -l)
  echo "== $t: ${seconds} s, -fork=$jobs (log: build/fuzz/campaign/$t/fuzz.log)"
  (cd "$dir" && "$bin" -fork="$jobs" -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 \
     -max_total_time="$seconds" -timeout=10 -rss_limit_mb=4096 -max_len="$(fuzz_max_len "$t")" \
     -dict="$(fuzz_dict "$t")" -print_final_stats=1 -artifact_prefix="$dir/artifacts/" \
     "$dir/corpus" "$ROOT/fuzz/corpus/$t" >"$dir/fuzz.log" 2>&1) || true
  read -r execs rate cov ft < <(fuzz_stats "$dir/fuzz.log")

  if [ $merge -eq 1 ]; then
    # Unfiltered: an input that fails a check (even an ignored one) is not merged.
    env -u RAYPROOF_FUZZ_IGNORE -u RAYPROOF_FUZZ_ONLY "$bin" -merge=1 -timeout=10 -rss_limit_mb=4096 -max_len="$(fuzz_max_len "$t")" \
      "$ROOT/fuzz/corpus/$t" "$dir/corpus" >"$dir/merge.log" 2>&1 || echo "   merge failed: see $dir/merge.log"
  fi
  after=$(find "$ROOT/fuzz/corpus/$t" -type f ! -name '.*' | wc -l)

  # Findings: replay each to name it, then minimize the first of each kind keeping that
  # kind of failure.
  kinds=()
  declare -A minimized=()
  for a in "$dir"/artifacts/crash-* "$dir"/artifacts/leak-* "$dir"/artifacts/timeout-* "$dir"/artifacts/oom-*; do
    [ -e "$a" ] || continue
    name=$(basename "$a")
    "$bin" -timeout=10 -rss_limit_mb=4096 "$a" >"$dir/artifacts/$name.log" 2>&1 || true
    kind=$(fuzz_finding "$dir/artifacts/$name.log")
    [ -n "$kind" ] || kind="$name"
    what=$(echo "$kind" | sed -n 's/^rayproof[^:]*: contract violation: //p; s/^rayproof scene fuzz: //p')
    if [[ "$name" == crash-* && -z "${minimized[$kind]:-}" ]]; then
      minimized[$kind]=1
      RAYPROOF_FUZZ_ONLY="${what}" "$bin" -minimize_crash=1 -max_total_time=30 -timeout=10 \
        -exact_artifact_path="$dir/artifacts/min-$name" "$a" >"$dir/artifacts/min-$name.log" 2>&1 || true
    fi
    kinds+=("$kind")
  done
  findings=${#kinds[@]}
  total_findings=$((total_findings + findings))
  line=$(printf '%-16s %10s execs  %6s exec/s  cov %5s  ft %6s  corpus %5d -> %5d  findings %d' \
    "$t" "$execs" "$rate" "$cov" "$ft" "$before" "$after" "$findings")
  summary+=("$line")
  if [ "$findings" -gt 0 ]; then
    printf '%s\n' "${kinds[@]}" | sort | uniq -c | sed 's/^/     /' >"$dir/findings.txt"
    summary+=("$(cat "$dir/findings.txt")")
  fi
done

echo "== campaign summary (${seconds} s per target, -fork=$jobs)"
printf '%s\n' "${summary[@]}"
if [ $total_findings -gt 0 ]; then
  echo "== $total_findings finding(s): minimized inputs are build/fuzz/campaign/<target>/artifacts/min-*;"
  echo "   replay one with build/fuzz/fuzz/<target> FILE, then keep it in tests/regressions/<target>/"
  exit 1
fi
echo "== campaign: no findings"
