#!/usr/bin/env bash
# The speed/accuracy trade, regenerated with one command: installs what is missing,
# builds (build/bench, g++ -O2), runs the benchmarks (the paired ones, the ladder's
# ratios, in three processes: the report takes each ratio's median), the exact-stage
# counts, the accuracy judgement of the very same cases by the exact oracle, the audit, and the
# tracer against POV-Ray; prints the summary table and writes
#   docs/trade.md              the full report (date, compiler, flags, every table)
#   docs/trade.png             time per query against wrong-verdict rate, per workload
#   docs/tracer_vs_povray.png  the default scene, rayproof and POV-Ray side by side
#   render/default.png         the default scene, certified, for render/README.md
# and the tracer-and-BVH tables (issue #18): generated 2,000- and 100,000-object scenes
# rendered by rayproof and by POV-Ray, closest-hit rays on 100,000 balls against Embree,
# and render/README.md's paragraph on speed, between <!-- speed:begin --> and <!-- speed:end -->,
# and, when README.md holds the lines <!-- trade:begin --> and <!-- trade:end -->, the
# summary (date, compiler, flags, the uniform table, the checks, the plot) between them.
# Raw data (benchmark JSON, accuracy CSV, renders) stay in build/bench/trade/.
#
#   RAYPROOF_JOBS=N          parallel build jobs (default: all cores)
#   TRADE_QUICK=1            a fast, low-precision run (smaller samples, fewer repetitions)
#   TRADE_REPETITIONS=R      benchmark repetitions (default 5; the median is reported)
#   TRADE_CASES=N            cases judged per (shape, type, workload) (default 131072)
#   TRADE_ONLY=tracer        run the tracer stages alone (the default scene against POV-Ray,
#                            and the tracer-and-BVH tables) and rebuild the report with the
#                            other stages' raw data of the last full run (build/bench/trade/),
#                            which the report's head then dates
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
start_all=$(date +%s)
install_missing

BUILD="$ROOT/build/bench"
OUT="$BUILD/trade"
DOCS="$ROOT/docs"
mkdir -p "$ROOT/build" "$DOCS"

REPS="${TRADE_REPETITIONS:-5}"
MIN_TIME=0.05
PAIRED_EXTRA=2
CASES="${TRADE_CASES:-131072}"
CGAL_CASES=16384
COUNT=65536
COUNT_UNIFORM=1048576
AUDIT_CASES=10000
BATCH_MAX=1000000
# The BVH stage: the generated scenes' sizes, the rays per set timed and judged, and how
# long a render of each scene may run (the 2,000-object scene's render is kept to see its
# time even far from the target; a larger scene's is stopped at 4× POV-Ray's time, at
# least BVH_FLOOR s, which is beyond its target anyway).
BVH_SCENES="2000 100000"
BVH_RAYS=100000
BVH_JUDGE=2000
BVH_LIMIT_SMALL=180
BVH_FLOOR=30
if [ "${TRADE_QUICK:-0}" = 1 ]; then
  REPS="${TRADE_REPETITIONS:-3}" MIN_TIME=0.01 CASES="${TRADE_CASES:-8192}" CGAL_CASES=1024
  COUNT=4096 COUNT_UNIFORM=65536 AUDIT_CASES=500 BATCH_MAX=100000
  BVH_RAYS=20000 BVH_JUDGE=300
fi
TIMEFORMAT='%R %U %S'  # bash `time`: wall, user and system seconds

ONLY="${TRADE_ONLY:-}"
case "$ONLY" in
  "" | tracer) ;;
  *) echo "trade.sh: TRADE_ONLY must be empty or 'tracer', got '$ONLY'" >&2; exit 2 ;;
esac
if [ "$ONLY" = tracer ] && [ ! -s "$OUT/bench.json" ]; then
  echo "trade.sh: TRADE_ONLY=tracer needs the raw data of a full run in build/bench/trade/" >&2
  exit 2
fi

echo "== build (build/bench, g++ -O2)"
t0=$(date +%s)
configure_and_build bench g++ -DCMAKE_CXX_FLAGS_RELEASE="-O2 -DNDEBUG" -DBUILD_TESTING=OFF \
  -DRAYPROOF_BENCH=ON -DRAYPROOF_ORACLE=ON -DRAYPROOF_RENDER=ON
echo "   built in $(( $(date +%s) - t0 )) s"
if [ "$ONLY" = tracer ]; then
  earlier="$(date -u -r "$OUT/bench.json" '+%Y-%m-%d %H:%M UTC')"
else
  rm -rf "$OUT"
fi
mkdir -p "$OUT"
B="$BUILD/bench"
RP="$BUILD/tools/rayproof"
# True when the AVX2 build of bench program $1 exists (the compiler made one) and this
# CPU runs it.
avx2_runs() { [ -x "$B/$1_avx2" ] && grep -qw avx2 /proc/cpuinfo 2>/dev/null; }

# The flags the timed code was compiled with (the compile command of one benchmark file,
# without include paths and file names).
ninja -C "$BUILD" -t commands bench/rayproof_bench >"$OUT/commands.txt" 2>/dev/null || true
flags=$(grep 'ray_aabb_bench.cpp' "$OUT/commands.txt" | head -1 | tr ' ' '\n' |
  grep -E '^-(O|f|m|D|std=|W)' | grep -v '^-D.*_HAVE_' | tr '\n' ' ' | sed 's/ $//' || true)
compiler=$(g++ --version | head -1)

# Runs Google Benchmark program $1 with the report's repetitions into $OUT/$2.json (log
# $OUT/$2.log), extra flags after. Random interleaving runs the repetitions of all
# benchmarks in a random order, so that a change of load on a shared machine spreads over
# every method instead of hitting one.
timed_run() {
  local program="$1" name="$2"
  shift 2
  "$program" --benchmark_repetitions="$REPS" --benchmark_report_aggregates_only=true \
    --benchmark_enable_random_interleaving=true --benchmark_min_time="$MIN_TIME" "$@" \
    --benchmark_out="$OUT/$name.json" --benchmark_out_format=json >"$OUT/$name.log" 2>&1
}

if [ "$ONLY" != tracer ]; then
echo "== timings ($REPS repetitions, median; log: build/bench/trade/bench.log)"
t0=$(date +%s)
timed_run "$B/rayproof_bench" bench --batch_max="$BATCH_MAX"
echo "   $(( $(date +%s) - t0 )) s"

# The pairs (the ladder's ratios) in two more processes: a process may keep one speed for
# its whole run, so the report takes each ratio's median over the three.
echo "== the pairs in $PAIRED_EXTRA more processes"
t0=$(date +%s)
for k in $(seq 2 $((PAIRED_EXTRA + 1))); do
  timed_run "$B/rayproof_bench" "paired_$k" --benchmark_filter='^paired/'
done
echo "   $(( $(date +%s) - t0 )) s"

# The certified lane batches (Aabb, plane) in the AVX2 build, where the compiler made one
# and the CPU runs it: the batch table's AVX2 rows.
rm -f "$OUT/batch_avx2.json"
if avx2_runs rayproof_batch_bench; then
  echo "== the lane batches in the AVX2 build ($REPS repetitions, median)"
  t0=$(date +%s)
  timed_run "$B/rayproof_batch_bench_avx2" batch_avx2 --batch_max="$BATCH_MAX"
  echo "   $(( $(date +%s) - t0 )) s"
fi

echo "== box packets ($REPS repetitions, median)"
t0=$(date +%s)
# The AVX2 build where the compiler made one and the CPU runs it, else the default (SSE2).
packet_bench="$B/rayproof_packet_bench"
if avx2_runs rayproof_packet_bench; then
  packet_bench="$B/rayproof_packet_bench_avx2"
fi
timed_run "$packet_bench" packets
echo "   $(( $(date +%s) - t0 )) s"

echo "== exact-stage counts"
t0=$(date +%s)
"$B/rayproof_bench_counters" --benchmark_min_time=0.01 --count_cases="$COUNT" \
  --count_cases_uniform="$COUNT_UNIFORM" --watchdog=60 \
  --benchmark_out="$OUT/counters.json" --benchmark_out_format=json >"$OUT/counters.log" 2>&1
echo "   $(( $(date +%s) - t0 )) s"
fi

echo "== tracer: rayproof render against POV-Ray (640x480, depth 5, 2 threads)"
t0=$(date +%s)
scene="$ROOT/render/scenes/default.json"
# The ray tree's distance attenuation is off in every render compared with POV-Ray, which
# lacks it (export-pov says what else it cannot write exactly: export.log).
: >"$OUT/tracer.txt"
: >"$OUT/tracer.cpu"
: >"$OUT/tracer_facts.txt"
for mode in fast conservative certified; do
  t=$( { time "$RP" render "$scene" -o "$OUT/rayproof_$mode.png" --width 640 --height 480 \
           --mode "$mode" --depth 5 --threads 2 --no-tree-attenuation --stats -q >/dev/null 2>"$OUT/render_$mode.log"; } 2>&1 )
  echo "$mode $(echo "$t" | awk '{print $1}')" >>"$OUT/tracer.txt"
  echo "$mode-cpu $(echo "$t" | awk '{print $2 + $3}')" >>"$OUT/tracer.cpu"
  # --stats: "rays: A primary, B shadow, C reflected, D refracted; ..." and "kernel queries: Q (...)"
  awk -v m="$mode" '/^rays:/ { gsub(/[,;]/, ""); print "rays-" m, $2 + $4 + $6 + $8 }
                    /^kernel queries:/ { print "queries-" m, $3 }' "$OUT/render_$mode.log" >>"$OUT/tracer_facts.txt"
done
"$RP" export-pov "$scene" --width 640 --height 480 --no-tree-attenuation >"$OUT/scene.pov" 2>"$OUT/export.log"
echo "parity-inexact $(grep -c 'not exact' "$OUT/export.log" || true)" >>"$OUT/tracer_facts.txt"
t=$( { time (cd "$OUT" && povray +Iscene.pov +Opovray.png +W640 +H480 -D -A +WT2 File_Gamma=1.0 >povray.log 2>&1); } 2>&1 )
echo "povray $(echo "$t" | awk '{print $1}')" >>"$OUT/tracer.txt"
echo "povray-cpu $(echo "$t" | awk '{print $2 + $3}')" >>"$OUT/tracer.cpu"
cat "$OUT/tracer.cpu" >>"$OUT/tracer.txt"
# "mean absolute difference X/255 per channel; largest Y/255; N of M pixels differ; PSNR ..."
"$RP" compare "$OUT/rayproof_certified.png" "$OUT/povray.png" >"$OUT/compare.txt"
sed -E 's|^mean absolute difference ([0-9.]+)/255 per channel; largest ([0-9]+)/255; ([0-9]+) of ([0-9]+) pixels.*|parity-mean \1\nparity-max \2\nparity-differing \3\nparity-pixels \4|' \
  "$OUT/compare.txt" >>"$OUT/tracer_facts.txt"
echo "   POV-Ray against rayproof: $(cat "$OUT/compare.txt")"
# The tracer's own picture in render/README.md: the default scene as it is, certified.
"$RP" render "$scene" -o "$ROOT/render/default.png" --width 640 --height 480 --mode certified --threads 2 -q
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

echo "== tracer and BVH: generated scenes against POV-Ray, closest-hit rays on 100k balls against Embree"
t0=$(date +%s)
BV="$OUT/bvh"
mkdir -p "$BV"
: >"$BV/scenes.txt"
for n in $BVH_SCENES; do
  "$B/rayproof_scene_gen" --kind mixed --objects "$n" --seed 1 -o "$BV/mixed_$n.json"
  "$RP" export-pov "$BV/mixed_$n.json" --width 640 --height 480 --no-tree-attenuation \
    >"$BV/mixed_$n.pov" 2>"$BV/export_$n.log"
  t=$( { time (cd "$BV" && povray +Imixed_$n.pov +Opovray_$n.png +W640 +H480 -D -A +WT2 File_Gamma=1.0 \
                 >povray_$n.log 2>&1); } 2>&1 )
  pw=$(echo "$t" | awk '{print $1}')
  echo "scene-$n-povray $pw" >>"$BV/scenes.txt"
  echo "scene-$n-povray-cpu $(echo "$t" | awk '{print $2 + $3}')" >>"$BV/scenes.txt"
  limit=$(awk -v p="$pw" -v n="$n" -v small="$BVH_LIMIT_SMALL" -v floor="$BVH_FLOOR" \
    'BEGIN { l = n <= 2000 ? small : 4 * p; if (l < floor) l = floor; printf "%d", l + 1 }')
  status=0
  t=$( { time timeout "$limit" "$RP" render "$BV/mixed_$n.json" -o "$BV/rayproof_$n.png" --width 640 --height 480 \
           --mode certified --depth 5 --threads 2 --no-tree-attenuation --stats -q >/dev/null 2>"$BV/render_$n.log"; } 2>&1 ) ||
    status=$?
  if [ "$status" = 0 ]; then
    echo "scene-$n-certified $(echo "$t" | awk '{print $1}')" >>"$BV/scenes.txt"
    echo "scene-$n-certified-cpu $(echo "$t" | awk '{print $2 + $3}')" >>"$BV/scenes.txt"
    # The same picture? "mean absolute difference X/255 per channel; ..."
    "$RP" compare "$BV/rayproof_$n.png" "$BV/povray_$n.png" >"$BV/compare_$n.txt" 2>&1 || true
    sed -nE "s|^mean absolute difference ([0-9.]+)/255.*|scene-$n-parity-mean \1|p" "$BV/compare_$n.txt" >>"$BV/scenes.txt"
  elif [ "$status" = 124 ]; then
    echo "scene-$n-certified-timeout $limit" >>"$BV/scenes.txt"
  else
    echo "   (rayproof render failed on the $n-object scene, status $status: see $BV/render_$n.log)"
  fi
  echo "   $n objects: $(grep "^scene-$n-" "$BV/scenes.txt" | tr '\n' ' ')"
done
"$B/rayproof_bvh_bench" --rays "$BVH_RAYS" --judge "$BVH_JUDGE" --repetitions "$REPS" --seed 1 \
  -o "$BV/rays.txt" 2>"$BV/rays.log" ||
  echo "   (rayproof_bvh_bench: the certified BVH differed from brute force or failed: see $BV/rays.log)"
# The same tree in the AVX2 build, where the compiler made one and the CPU runs it.
rm -f "$BV/rays_avx2.txt"
if avx2_runs rayproof_bvh_bench; then
  "$B/rayproof_bvh_bench_avx2" --rays "$BVH_RAYS" --judge "$BVH_JUDGE" --repetitions "$REPS" --seed 1 \
    -o "$BV/rays_avx2.txt" 2>"$BV/rays_avx2.log" ||
    echo "   (rayproof_bvh_bench_avx2: the certified BVH differed from brute force or failed: see $BV/rays_avx2.log)"
fi
echo "   $(( $(date +%s) - t0 )) s"

if [ "$ONLY" != tracer ]; then
echo "== accuracy: the oracle's judgement of the same cases ($CASES per workload) and the audit"
t0=$(date +%s)
"$B/rayproof_trade_accuracy" --cases "$CASES" --cgal-cases "$CGAL_CASES" --timeout 60 \
  --shape aabb,obb,plane >"$OUT/accuracy_boxes.csv" 2>"$OUT/accuracy_boxes.log" &
acc1=$!
# (accuracy_sphere.csv holds the sphere's and the convex polyhedron's rows)
"$B/rayproof_trade_accuracy" --cases "$CASES" --cgal-cases "$CGAL_CASES" --timeout 60 \
  --shape sphere,polyhedron >"$OUT/accuracy_sphere.csv" 2>"$OUT/accuracy_sphere.log" &
acc2=$!
wait $acc1 $acc2
audit="$BUILD/tools/audit/rayproof-audit"
if [ -x "$audit" ]; then
  timeout 300 "$audit" --cases "$AUDIT_CASES" --format md --jobs 2 >"$OUT/audit.md" 2>"$OUT/audit.log" ||
    echo "   (the audit did not finish: see $OUT/audit.log)"
fi
echo "   $(( $(date +%s) - t0 )) s"
fi

echo "== report"
stages_meta=()
if [ "$ONLY" = tracer ]; then
  stages_meta=(--meta "stages=the tracer's sections (POV-Ray, tracer and BVH) from this run; every other table from the full run of $earlier")
fi
"$B/rayproof_trade_report" --bench "$OUT/bench.json" --counters "$OUT/counters.json" --packets "$OUT/packets.json" \
  --accuracy "$OUT/accuracy_boxes.csv" --accuracy "$OUT/accuracy_sphere.csv" --tracer "$OUT/tracer.txt" \
  $(for k in $(seq 2 $((PAIRED_EXTRA + 1))); do [ -s "$OUT/paired_$k.json" ] && echo --paired "$OUT/paired_$k.json"; done) \
  $( [ -s "$OUT/audit.md" ] && echo --audit "$OUT/audit.md" ) \
  $( [ -s "$OUT/batch_avx2.json" ] && echo --batch-avx2 "$OUT/batch_avx2.json" ) \
  --tracer-facts "$OUT/tracer_facts.txt" --render-md "$OUT/render_speed.md" \
  --bvh "$OUT/bvh/scenes.txt" $( [ -s "$OUT/bvh/rays.txt" ] && echo --bvh "$OUT/bvh/rays.txt" ) \
  $( [ -s "$OUT/bvh/rays_avx2.txt" ] && echo --bvh "$OUT/bvh/rays_avx2.txt" ) \
  --meta "date=$(date -u +%Y-%m-%d)" --meta "compiler=$compiler" --meta "flags=$flags" \
  "${stages_meta[@]}" \
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
# render/README.md's paragraph on speed, between its markers.
rreadme="$ROOT/render/README.md"
if [ -s "$OUT/render_speed.md" ] && grep -q '^<!-- speed:begin -->' "$rreadme" && grep -q '^<!-- speed:end -->' "$rreadme"; then
  awk -v f="$OUT/render_speed.md" '
    /^<!-- speed:begin -->/ { print; while ((getline line < f) > 0) print line; skip = 1; next }
    /^<!-- speed:end -->/ { skip = 0 }
    !skip' "$rreadme" >"$OUT/render_README.md" && cp "$OUT/render_README.md" "$rreadme"
  echo "updated the speed paragraph and the picture in render/README.md"
fi
echo
echo "wrote docs/trade.md, docs/trade.png, docs/tracer_vs_povray.png, render/default.png (raw data: build/bench/trade/)"
echo "trade.sh took $(( $(date +%s) - start_all )) s"
