#!/usr/bin/env bash
# fuzz/mutants.sh — does the fuzzing catch a broken kernel? Each mutation below is a
# plausible one-line bug (an error bound too small, a closed boundary made open, a
# dropped correction, a wrong exact sign); for each one this script copies the source
# tree to build/fuzz/mutants/src, applies the mutation there (never to the checkout),
# rebuilds the one target that should notice it (same sanitizer build as fuzz/ci.sh),
# and fuzzes it for at most --seconds. A mutant the fuzzer does not report within that
# time survived: the script prints one line per mutation (found or not, the seconds
# and executions it took, what was reported) and exits 1 if any survived.
#
#   fuzz/mutants.sh [--seconds S] [--empty] [--only NAME] [--check]
#     --seconds S   time limit per mutant (default 60)
#     --empty       start from an empty corpus instead of the committed fuzz/corpus/<target>/
#     --only NAME   run one mutation (see the table below)
#     --check       build and fuzz nothing: check that every mutation's pattern matches
#                   exactly one line of its file in the checkout and changes it, and that
#                   its target is a fuzz target; exit 1 when one does not (a CTest test
#                   runs this, so a kernel edit that moves a mutated line fails it)
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
seconds=60 empty=0 only="" check=0
while [ $# -gt 0 ]; do
  case "$1" in
    --check) check=1; shift ;;
    --seconds) seconds="$2"; shift 2 ;;
    --empty) empty=1; shift ;;
    --only) only="$2"; shift 2 ;;
    -h|--help) sed -n '2,19p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "unknown argument: $1 (see --help)" >&2; exit 2 ;;
  esac
done

# name | target | file | perl substitution (must match exactly once) | what it breaks
MUTATIONS=(
  "aabb-no-correction|ray_aabb_fuzz|kernel/include/rayproof/ray_aabb.hpp|s/tc = tt \+ rounded\(/tc = m + splat(0.0) * rounded(/|certified Aabb t not faithfully rounded for double (the straight-line path's correction dropped)"
  "aabb-filter-no-bound|ray_aabb_fuzz|kernel/include/rayproof/ray_aabb.hpp|s/const D2 bm = abs\(L.m\) \* splat\(K\) \+ splat\(eta\);/const D2 bm = splat(0.0);/|certified Aabb filter without its error bound: every close comparison decided by floating point"
  "aabb-conservative-bound|ray_aabb_fuzz|kernel/include/rayproof/ray_aabb.hpp|s/constexpr double K = 2 \* gamma<double>\(3\);/constexpr double K = 0;/|conservative Aabb enclosure without its error bound"
  "aabb-verdict-no-bound|ray_aabb_fuzz|kernel/include/rayproof/ray_aabb.hpp|s/const D2 h = max\(L.m_hi, L.limit\), g = max\(L.m_lo, L.limit\);/const D2 h = max(L.m, L.limit), g = max(L.m, L.limit);/|certified Aabb straight-line verdict (the verdict query's and the full query's) decided on the computed values, without their bounds"
  "aabb-common-no-probe|ray_aabb_fuzz|kernel/include/rayproof/ray_aabb.hpp|s/L.usable = \(probe == splat\(0.0\)\) & /L.usable = /|certified Aabb straight-line paths answer for infinite or NaN input (their finiteness probe dropped)"
  "aabb-float-no-direction-probe|ray_aabb_fuzz|kernel/include/rayproof/ray_aabb.hpp|s/dterms = from_float \? L.d01 \+ L.d22 :/dterms = from_float ? splat(0.0) :/|certified Aabb straight-line paths answer for a float ray with an infinite direction component (the directions left out of the finiteness probe)"
  "aabb-double-no-direction-probe|ray_aabb_fuzz|kernel/include/rayproof/ray_aabb.hpp|s/: rounded\(L.d01 \* splat\(4.0\)\) \+ rounded\(L.d22 \* splat\(4.0\)\);/: splat(0.0);/|certified Aabb straight-line paths answer for a double ray with a direction component of magnitude 2^1022 or more, whose subnormal reciprocal the bound does not cover"
  "aabb-correction-any-direction|ray_aabb_fuzz|kernel/include/rayproof/ray_aabb.hpp|s/ & \(ad >= splat\(0x1p-500\)\) & \(ad <= splat\(0x1p500\)\);/;/|certified Aabb double straight-line path corrects a winner whose direction is outside [2^-500, 2^500], where its products can underflow"
  "range-check-finite-only|ray_aabb_fuzz|kernel/include/rayproof/detail/lanes.hpp|s/return ordered \+ swap\(ordered\) <= splat\(0.0\);/return ordered - ordered <= splat(0.0);/|the straight-line paths' range check accepts any finite range, t_min > t_max included"
  "aabb-flat-box-invalid|ray_aabb_fuzz|kernel/include/rayproof/detail/validate.hpp|s/\(lo\[0\] <= hi\[0\]\)/(lo[0] < hi[0])/|a flat Aabb (lo_0 == hi_0) reported invalid"
  "obb-open-parallel-slab|ray_obb_fuzz|kernel/include/rayproof/ray_obb.hpp|s/return above\.sign\(\) >= 0 && below\.sign\(\) >= 0;/return above.sign() > 0 && below.sign() > 0;/|Obb: a ray parallel to a slab and exactly on its face plane taken as outside (exact stage)"
  "obb-common-no-bound|ray_obb_fuzz|kernel/include/rayproof/ray_obb.hpp|s/const D2 bound = \(e \+ e\) \+ splat\(eta\);/const D2 bound = (e + e) * splat(0.0);/|certified Obb: the straight-line path's slab values without their error bounds"
  "plane-in-plane-miss|ray_plane_fuzz|kernel/include/rayproof/ray_plane.hpp|s/if \(x\.in_plane\(\)\) \{/if (false \&\& x.in_plane()) {/|Plane: a ray lying in the plane reported as a miss"
  "sphere-distance-no-bound|ray_sphere_fuzz|kernel/include/rayproof/detail/ray_sphere_straight_line.hpp|s/if \(n - rad > L.threshold\) return h;/if (n - rad > 0) return h;/|certified Sphere straight-line path: a miss taken from the estimated distance of the line, without its error bound"
  "sphere-root-no-proof|ray_sphere_fuzz|kernel/include/rayproof/detail/ray_sphere_straight_line.hpp|s/const double thr = 2 \* \(qx\.err \+/const double thr = 0 * (qx.err +/|certified Sphere straight-line path: the signs of q next to a root taken from floating point, without their bound"
  "plane-pin-no-bound|ray_plane_fuzz|kernel/include/rayproof/detail/compensated.hpp|s/\(2 \* e \+ 0x1p-1020\)/(0 * e + 0x1p-1020)/|certified Plane: the straight-line path's proof that t lies next to its candidate without the residual's error bound"
  "sphere-verdict-no-margin|ray_sphere_fuzz|kernel/include/rayproof/detail/ray_sphere_verdict.hpp|s/line_in = -D > E;/line_in = -D > 0;/|certified Sphere verdict filter taking the line inside the ball without the certificate's margin"
  "sphere-verdict-ends-no-bound|ray_sphere_fuzz|kernel/include/rayproof/detail/ray_sphere_verdict.hpp|s/const M2 inside = v < -tq,/const M2 inside = v < splat(0.0) * tq,/|certified Sphere verdict filter taking an end of the range as inside the ball from the sign of q there, without its bound"
  "plane-verdict-no-bound|ray_plane_fuzz|kernel/include/rayproof/ray_plane.hpp|s/E = Q \+ Q;/E = Q * splat(0.0);/|certified Plane verdict filter deciding t against t_min and t_max without its error bound"
  "plane-verdict-overflow-holds|ray_plane_fuzz|kernel/include/rayproof/ray_plane.hpp|s/\(\(X >= E\) & finite\)/(X >= E)/|certified Plane verdict filter taking an overflowed limit·D~ (X~ = +inf for a finite limit) as proof that t lies inside the range"
  "sphere-tangent-miss|ray_sphere_fuzz|kernel/include/rayproof/detail/ray_sphere_general.hpp|s/hit = sd >= 0;/hit = sd > 0;/|Sphere: an exactly tangent ray (zero discriminant) reported as a miss"
  "exact-two-sum-sign|ray_obb_fuzz|kernel/include/rayproof/detail/eft.hpp|s/return \{s, \(a - av\) \+ \(b - bv\)\};/return {s, (a - av) - (b - bv)};/|exact arithmetic: two_sum's error term with a wrong sign"
)

# --check: every pattern against the checkout, nothing built.
if [ $check -eq 1 ]; then
  bad=0
  for m in "${MUTATIONS[@]}"; do
    IFS='|' read -r name target file subst what <<<"$m"
    [ -z "$only" ] || [ "$only" = "$name" ] || continue
    if [ ! -f "$ROOT/$file" ]; then
      echo "mutation $name: no file $file" >&2; bad=1; continue
    fi
    case " ${FUZZ_TARGETS_ALL[*]} " in
      *" $target "*) ;;
      *) echo "mutation $name: $target is not a fuzz target" >&2; bad=1 ;;
    esac
    n=$(perl -ne "\$n++ if $subst; END { print \$n+0 }" "$ROOT/$file")
    if [ "$n" != 1 ]; then
      echo "mutation $name: the pattern matches $n lines of $file (expected 1)" >&2; bad=1; continue
    fi
    if perl -pe "$subst" "$ROOT/$file" | cmp -s - "$ROOT/$file"; then
      echo "mutation $name: the substitution leaves $file unchanged" >&2; bad=1; continue
    fi
    echo "mutation $name: applies once to $file"
  done
  exit $bad
fi

work="$FUZZ_BUILD/mutants"
src="$work/src"
bld="$work/build"
rm -rf "$src"
mkdir -p "$src" "$bld"
# The tracked files of the checkout as they are now (uncommitted edits included).
(cd "$ROOT" && git ls-files -z | tar --null -T - -cf -) | tar -xf - -C "$src"

echo "== mutants: configuring build/fuzz/mutants/build"
cmake -S "$src" -B "$bld" -G Ninja -DCMAKE_CXX_COMPILER="${RAYPROOF_FUZZ_CXX:-clang++}" \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g" \
  -DCMAKE_CXX_FLAGS="$SANITIZE" -DCMAKE_EXE_LINKER_FLAGS="$SANITIZE" \
  -DRAYPROOF_FUZZ=ON -DRAYPROOF_ORACLE=ON -DRAYPROOF_RENDER=OFF -DRAYPROOF_BENCH=OFF \
  -DBUILD_TESTING=OFF -DRAYPROOF_WERROR=OFF >"$work/configure.log" 2>&1 || { cat "$work/configure.log"; exit 1; }

# Every mutated file as in the checkout (undoes any mutation in the copy).
restore_all() {
  local m f
  for m in "${MUTATIONS[@]}"; do
    f=$(echo "$m" | cut -d'|' -f3)
    cp "$ROOT/$f" "$src/$f"
  done
}

results=()
survived=0 ran=0
for m in "${MUTATIONS[@]}"; do
  IFS='|' read -r name target file subst what <<<"$m"
  [ -z "$only" ] || [ "$only" = "$name" ] || continue
  ran=$((ran + 1))
  # Every other mutation undone, then this one applied.
  restore_all
  n=$(perl -ne "\$n++ if $subst; END { print \$n+0 }" "$src/$file")
  if [ "$n" != 1 ]; then
    echo "mutation $name: the pattern matches $n lines of $file (expected 1); update the table" >&2
    exit 2
  fi
  perl -pi -e "$subst" "$src/$file"
  echo "== $name: $what"
  if ! cmake --build "$bld" --target "$target" -j "${RAYPROOF_JOBS:-2}" >"$work/$name.build.log" 2>&1; then
    grep -E "error|FAILED" "$work/$name.build.log" | head -20
    echo "   build FAILED (log: build/fuzz/mutants/$name.build.log)"
    exit 1
  fi
  dir="$work/$name"
  rm -rf "$dir"
  mkdir -p "$dir/corpus" "$dir/artifacts"
  corpora=("$dir/corpus")
  [ $empty -eq 1 ] || corpora+=("$ROOT/fuzz/corpus/$target")
  t0=$(date +%s.%N)
  set +e
  (cd "$dir" && env -u RAYPROOF_FUZZ_IGNORE -u RAYPROOF_FUZZ_ONLY "$bld/fuzz/$target" \
     -max_total_time="$seconds" -timeout=10 -rss_limit_mb=4096 -max_len="$(fuzz_max_len "$target")" \
     -dict="$(fuzz_dict "$target")" -print_final_stats=1 -artifact_prefix="$dir/artifacts/" \
     "${corpora[@]}" >"$dir/fuzz.log" 2>&1)
  rc=$?
  set -e
  took=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
  read -r execs rate cov ft < <(fuzz_stats "$dir/fuzz.log")
  if [ $rc -ne 0 ]; then
    found="FOUND"
    detail=$(fuzz_finding "$dir/fuzz.log")
  else
    found="SURVIVED"
    detail="no report in ${seconds} s"
    survived=$((survived + 1))
  fi
  results+=("$(printf '%-26s %-16s %-8s %6s s %9s execs  %s' "$name" "$target" "$found" "$took" "$execs" "$detail")")
  echo "   ${results[-1]}"
done
# Leave the copy as in the checkout.
restore_all

echo "== mutants summary (limit ${seconds} s each, $( [ $empty -eq 1 ] && echo 'empty corpus' || echo 'committed corpus'))"
printf '%s\n' "${results[@]}"
[ $ran -gt 0 ] || { echo "no mutation named $only" >&2; exit 2; }
if [ $survived -gt 0 ]; then
  echo "== $survived mutant(s) survived"
  exit 1
fi
echo "== every mutant was found"
