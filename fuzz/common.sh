# fuzz/common.sh — sourced by fuzz/ci.sh and fuzz/campaign.sh: the sanitizer build of the
# fuzz targets in build/fuzz (clang, libFuzzer, ASan + UBSan, assertions on), the target
# list, each target's dictionary and input-length limit (all three from fuzz/targets.txt,
# the sanitizer flags from fuzz/sanitizers.txt), and the parsing of libFuzzer's
# statistics.
#   RAYPROOF_FUZZ_CXX     the compiler (default clang++)
#   RAYPROOF_FUZZ_RENDER  ON/OFF: build scene_fuzz (needs the tracer; default ON)
#   RAYPROOF_JOBS         build jobs (default 2)
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
FUZZ_BUILD="$ROOT/build/fuzz"
# The target lines of fuzz/targets.txt: "name links dictionary max_len".
fuzz_target_lines() { grep -E '^[a-z]' "$ROOT/fuzz/targets.txt"; }
mapfile -t FUZZ_TARGETS_ALL < <(fuzz_target_lines | awk '{ print $1 }')
SANITIZE="$(grep -v '^#' "$ROOT/fuzz/sanitizers.txt" | tr '\n' ' ' | sed -e 's/  */ /g' -e 's/^ //' -e 's/ $//')"

# Configures and builds the fuzz targets; prints the build log's errors on failure.
fuzz_build() {
  local jobs="${RAYPROOF_JOBS:-2}" render="${RAYPROOF_FUZZ_RENDER:-ON}"
  mkdir -p "$FUZZ_BUILD"
  # -O2 -g without -DNDEBUG: the assertions of the kernel, the oracle and CGAL stay on.
  cmake -S "$ROOT" -B "$FUZZ_BUILD" -G Ninja -DCMAKE_CXX_COMPILER="${RAYPROOF_FUZZ_CXX:-clang++}" \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g" \
    -DCMAKE_CXX_FLAGS="$SANITIZE" -DCMAKE_EXE_LINKER_FLAGS="$SANITIZE" \
    -DRAYPROOF_FUZZ=ON -DRAYPROOF_ORACLE=ON -DRAYPROOF_RENDER="$render" -DRAYPROOF_BENCH=OFF \
    -DBUILD_TESTING=OFF -DRAYPROOF_WERROR=OFF >"$FUZZ_BUILD/configure.log" 2>&1 ||
    { cat "$FUZZ_BUILD/configure.log"; return 1; }
  cmake --build "$FUZZ_BUILD" --target rayproof_fuzz_all -j "$jobs" >"$FUZZ_BUILD/build.log" 2>&1 ||
    { grep -E "error|FAILED|warning" "$FUZZ_BUILD/build.log" | head -50; return 1; }
}

# The targets that were built.
fuzz_targets() {
  local t
  for t in "${FUZZ_TARGETS_ALL[@]}"; do
    [ -x "$FUZZ_BUILD/fuzz/$t" ] && echo "$t"
  done
  return 0
}

fuzz_bin() { echo "$FUZZ_BUILD/fuzz/$1"; }
fuzz_target_field() { fuzz_target_lines | awk -v t="$1" -v f="$2" '$1 == t { print $f }'; }
fuzz_dict() { echo "$ROOT/fuzz/dict/$(fuzz_target_field "$1" 3)"; }
fuzz_max_len() { fuzz_target_field "$1" 4; }

# The regression inputs of a target (files not starting with '.').
regression_files() {
  local dir="$ROOT/tests/regressions/$1"
  [ -d "$dir" ] || return 0
  find "$dir" -type f ! -name '.*' | sort
}

# Statistics from a libFuzzer log (plain or -fork mode): "execs exec_per_s cov ft".
fuzz_stats() {
  local log="$1" execs rate cov ft line
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  line=$(grep -E '^#[0-9]+.*cov: [0-9]+ ft: [0-9]+' "$log" | tail -1 || true)
  cov=$(echo "$line" | sed -n 's/.*cov: \([0-9]*\).*/\1/p')
  ft=$(echo "$line" | sed -n 's/.* ft: \([0-9]*\).*/\1/p')
  if [ -z "$execs" ] && [ -n "$line" ]; then  # -fork mode: "#N: cov: ... exec/s R ..."
    execs=$(echo "$line" | sed -n 's/^#\([0-9]*\).*/\1/p')
    rate=$(echo "$line" | sed -n 's/.*exec\/s \([0-9]*\).*/\1/p')
  fi
  echo "${execs:-0} ${rate:-0} ${cov:-0} ${ft:-0}"
}

# The contract violation or sanitizer report a log ends with (one line), if any.
fuzz_finding() {
  grep -m1 -E "==== rayproof|ERROR: (AddressSanitizer|LeakSanitizer|libFuzzer)|runtime error:|SUMMARY: UndefinedBehaviorSanitizer" "$1" |
    sed -e 's/^==== //' -e 's/^==[0-9]*==//' -e 's/ on address .*//' -e 's/ at pc .*//' || true
}
