#!/usr/bin/env bash
# The speed/accuracy trade, regenerated with one command: installs what is missing,
# builds (build/bench, g++ -O2), runs the benchmarks, the exact-stage counts, the
# accuracy judgement of the very same cases by the exact oracle, the audit, and the
# tracer against POV-Ray; prints the summary table and writes
#   docs/trade.md              the full report (date, compiler, flags, every table)
#   docs/trade.png             time per query against wrong-verdict rate, per workload
#   docs/tracer_vs_povray.png  the default scene, rayproof and POV-Ray side by side
# and, when README.md holds the lines <!-- trade:begin --> and <!-- trade:end -->, the
# summary (date, compiler, flags, the uniform table, the checks, the plot) between them.
# Raw data (benchmark JSON, accuracy CSV, renders) stay in build/bench/trade/.
#
#   RAYPROOF_JOBS=N          parallel build jobs (default: all cores)
#   TRADE_QUICK=1            a fast, low-precision run (smaller samples, fewer repetitions)
#   TRADE_REPETITIONS=R      benchmark repetitions (default 5; the median is reported)
#   TRADE_CASES=N            cases judged per (shape, type, workload) (default 131072)
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
start_all=$(date +%s)
install_missing

BUILD="$ROOT/build/bench"
OUT="$BUILD/trade"
DOCS="$ROOT/docs"
mkdir -p "$ROOT/build" "$DOCS"

REPS="${TRADE_REPETITIONS:-5}"
MIN_TIME=0.05
CASES="${TRADE_CASES:-131072}"
CGAL_CASES=16384
COUNT=65536
COUNT_UNIFORM=1048576
AUDIT_CASES=10000
BATCH_MAX=1000000
if [ "${TRADE_QUICK:-0}" = 1 ]; then
  REPS="${TRADE_REPETITIONS:-3}" MIN_TIME=0.01 CASES="${TRADE_CASES:-8192}" CGAL_CASES=1024
  COUNT=4096 COUNT_UNIFORM=65536 AUDIT_CASES=500 BATCH_MAX=100000
fi
TIMEFORMAT='%R %U %S'  # bash `time`: wall, user and system seconds

echo "== build (build/bench, g++ -O2)"
t0=$(date +%s)
configure_and_build bench g++ -DCMAKE_CXX_FLAGS_RELEASE="-O2 -DNDEBUG" -DBUILD_TESTING=OFF \
  -DRAYPROOF_BENCH=ON -DRAYPROOF_ORACLE=ON -DRAYPROOF_RENDER=ON
echo "   built in $(( $(date +%s) - t0 )) s"
rm -rf "$OUT"
mkdir -p "$OUT"
B="$BUILD/bench"

# The flags the timed code was compiled with (the compile command of one benchmark file,
# without include paths and file names).
ninja -C "$BUILD" -t commands bench/rayproof_bench >"$OUT/commands.txt" 2>/dev/null || true
flags=$(grep 'ray_aabb_bench.cpp' "$OUT/commands.txt" | head -1 | tr ' ' '\n' |
  grep -E '^-(O|f|m|D|std=|W)' | grep -v '^-D.*_HAVE_' | tr '\n' ' ' | sed 's/ $//' || true)
compiler=$(g++ --version | head -1)

echo "== timings ($REPS repetitions, median; log: build/bench/trade/bench.log)"
t0=$(date +%s)
# Random interleaving runs the repetitions of all benchmarks in a random order, so that a
# change of load on a shared machine spreads over every method instead of hitting one.
"$B/rayproof_bench" --benchmark_repetitions="$REPS" --benchmark_report_aggregates_only=true \
  --benchmark_enable_random_interleaving=true \
  --benchmark_min_time="$MIN_TIME" --batch_max="$BATCH_MAX" \
  --benchmark_out="$OUT/bench.json" --benchmark_out_format=json >"$OUT/bench.log" 2>&1
echo "   $(( $(date +%s) - t0 )) s"

echo "== exact-stage counts"
t0=$(date +%s)
"$B/rayproof_bench_counters" --benchmark_min_time=0.01 --count_cases="$COUNT" \
  --count_cases_uniform="$COUNT_UNIFORM" --watchdog=60 \
  --benchmark_out="$OUT/counters.json" --benchmark_out_format=json >"$OUT/counters.log" 2>&1
echo "   $(( $(date +%s) - t0 )) s"

echo "== tracer: rayproof render against POV-Ray (640x480, depth 5, 2 threads)"
t0=$(date +%s)
scene="$ROOT/render/scenes/default.json"
: >"$OUT/tracer.txt"
for mode in fast conservative certified; do
  t=$( { time "$BUILD/tools/rayproof" render "$scene" -o "$OUT/rayproof_$mode.png" --width 640 --height 480 \
           --mode "$mode" --depth 5 --threads 2 -q >/dev/null 2>"$OUT/render_$mode.log"; } 2>&1 )
  echo "$mode $(echo "$t" | awk '{print $1}')" >>"$OUT/tracer.txt"
  echo "$mode-cpu $(echo "$t" | awk '{print $2 + $3}')" >>"$OUT/tracer.cpu"
done
"$BUILD/tools/rayproof" export-pov "$scene" --width 640 --height 480 >"$OUT/scene.pov"
t=$( { time (cd "$OUT" && povray +Iscene.pov +Opovray.png +W640 +H480 -D -A +WT2 >povray.log 2>&1); } 2>&1 )
echo "povray $(echo "$t" | awk '{print $1}')" >>"$OUT/tracer.txt"
echo "povray-cpu $(echo "$t" | awk '{print $2 + $3}')" >>"$OUT/tracer.cpu"
cat "$OUT/tracer.cpu" >>"$OUT/tracer.txt"
rayproof_s=$(awk '$1 == "certified" {print $2}' "$OUT/tracer.txt")
povray_s=$(awk '$1 == "povray" {print $2}' "$OUT/tracer.txt")
gnuplot <<EOF
set terminal pngcairo size 960,400 font 'DejaVu Sans,11'
set output '$DOCS/tracer_vs_povray.png'
set multiplot layout 1,2
unset border; unset tics; unset key; unset colorbox
set size ratio -1
set lmargin 0; set rmargin 0; set bmargin 0; set tmargin 2
set xrange [0:639]; set yrange [0:479]
set title 'rayproof render, certified: ${rayproof_s} s'
plot '$OUT/rayproof_certified.png' binary filetype=png with rgbimage
set title 'POV-Ray 3.7, exported scene: ${povray_s} s'
plot '$OUT/povray.png' binary filetype=png with rgbimage
unset multiplot
EOF
echo "   $(( $(date +%s) - t0 )) s"

echo "== accuracy: the oracle's judgement of the same cases ($CASES per workload) and the audit"
t0=$(date +%s)
"$B/rayproof_trade_accuracy" --cases "$CASES" --cgal-cases "$CGAL_CASES" --timeout 60 \
  --shape aabb,obb,plane >"$OUT/accuracy_boxes.csv" 2>"$OUT/accuracy_boxes.log" &
acc1=$!
"$B/rayproof_trade_accuracy" --cases "$CASES" --cgal-cases "$CGAL_CASES" --timeout 60 \
  --shape sphere >"$OUT/accuracy_sphere.csv" 2>"$OUT/accuracy_sphere.log" &
acc2=$!
wait $acc1 $acc2
audit="$BUILD/tools/audit/rayproof-audit"
if [ -x "$audit" ]; then
  timeout 300 "$audit" --cases "$AUDIT_CASES" --format md --jobs 2 >"$OUT/audit.md" 2>"$OUT/audit.log" ||
    echo "   (the audit did not finish: see $OUT/audit.log)"
fi
echo "   $(( $(date +%s) - t0 )) s"

echo "== report"
"$B/rayproof_trade_report" --bench "$OUT/bench.json" --counters "$OUT/counters.json" \
  --accuracy "$OUT/accuracy_boxes.csv" --accuracy "$OUT/accuracy_sphere.csv" --tracer "$OUT/tracer.txt" \
  $( [ -s "$OUT/audit.md" ] && echo --audit "$OUT/audit.md" ) \
  --meta "date=$(date -u +%Y-%m-%d)" --meta "compiler=$compiler" --meta "flags=$flags" \
  --meta "samples=$CASES cases judged per (shape, type, workload), the first $(grep -o '"cases": "[0-9]*"' "$OUT/bench.json" | grep -o '[0-9]*') of them timed; CGAL: the first $CGAL_CASES judged; $REPS repetitions of each timing" \
  --md "$DOCS/trade.md" --plot-dir "$OUT" --plot-png "$DOCS/trade.png" --plot-ref trade.png \
  --tracer-png tracer_vs_povray.png --summary-md "$OUT/summary.md"
(cd "$OUT" && gnuplot trade.gp)
# The README shows the summary between these two markers, when it has them.
readme="$ROOT/README.md"
if grep -q '^<!-- trade:begin -->' "$readme" && grep -q '^<!-- trade:end -->' "$readme"; then
  awk -v f="$OUT/summary.md" '
    /^<!-- trade:begin -->/ { print; while ((getline line < f) > 0) print line; skip = 1; next }
    /^<!-- trade:end -->/ { skip = 0 }
    !skip' "$readme" >"$OUT/README.md" && cp "$OUT/README.md" "$readme"
  echo "updated the trade summary in README.md"
fi
echo
echo "wrote docs/trade.md, docs/trade.png, docs/tracer_vs_povray.png (raw data: build/bench/trade/)"
echo "trade.sh took $(( $(date +%s) - start_all )) s"
