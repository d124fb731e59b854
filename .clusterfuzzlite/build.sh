#!/bin/bash -eu
# .clusterfuzzlite/build.sh — builds rayproof's fuzz targets for ClusterFuzzLite / OSS-Fuzz
# (also runnable locally, see docs/fuzzing.md). The engine sets $CXX, $CXXFLAGS (sanitizer
# and coverage flags, -stdlib=libc++ on OSS-Fuzz), $LIB_FUZZING_ENGINE, $SANITIZER, $SRC
# and $OUT. Everything is compiled here from source with those flags: the oracle (CGAL is
# header-only; its exact rationals, CGAL::Gmpq, need only the C libraries GMP and MPFR,
# linked statically) and, for scene_fuzz, the tracer (nlohmann-json is header-only,
# libpng and zlib are C, linked statically). No C++ library from the distribution is
# linked, so libc++ builds work. Outputs per target: the binary, <target>_seed_corpus.zip,
# <target>.dict and <target>.options.
#
# Sanitizers: address and undefined. memory is not supported: GMP, MPFR and libpng come
# uninstrumented from the distribution (MSan would report false positives in them).

PROJECT="${RAYPROOF_SRC:-}"
if [ -z "$PROJECT" ]; then
  if [ -f "$PWD/fuzz/fuzz_decode.hpp" ]; then PROJECT="$PWD"; else PROJECT="$SRC/rayproof"; fi
fi
cd "$PROJECT"

# Header-only dependencies: the versions the Dockerfile unpacks under $SRC, else the system's.
EIGEN_INC=/usr/include/eigen3
[ -d "$SRC/eigen/Eigen" ] && EIGEN_INC="$SRC/eigen"
CGAL_INC=""
[ -d "$SRC/cgal/include/CGAL" ] && CGAL_INC="-isystem $SRC/cgal/include"

# The kernel divides by ±0 on purpose (IEEE 754: ±inf, the slab method's parallel axes),
# which is defined behaviour under Annex F but trapped by OSS-Fuzz's float-divide-by-zero
# check; unsigned wrap-around is defined behaviour (bit manipulation of floats).
if [ "${SANITIZER:-}" = undefined ]; then
  CXXFLAGS="$CXXFLAGS -fno-sanitize=float-divide-by-zero,unsigned-integer-overflow"
fi
if [ "${SANITIZER:-}" = memory ]; then
  echo "build.sh: the memory sanitizer is not supported (uninstrumented GMP, MPFR, libpng)" >&2
  exit 1
fi

# A static C library from the usual places, else the linker flag.
static_lib() {
  local d
  for d in /usr/lib/x86_64-linux-gnu /usr/lib64 /usr/lib /usr/local/lib; do
    [ -f "$d/lib$1.a" ] && { echo "$d/lib$1.a"; return; }
  done
  echo "-l$1"
}
GMP_LIBS="$(static_lib mpfr) $(static_lib gmp)"
PNG_LIBS="$(static_lib png) $(static_lib z)"

FLAGS="$CXXFLAGS -std=c++20 -I$PROJECT/kernel/include -I$PROJECT/oracle/include -I$PROJECT/render/include \
  -I$PROJECT/tests/generators/include \
  -I$PROJECT/fuzz -isystem $EIGEN_INC $CGAL_INC"
WORK="${WORK:-/tmp}/rayproof-fuzz-objects"
rm -rf "$WORK"
mkdir -p "$WORK" "$OUT"

# The oracle library.
ORACLE_OBJS=()
for f in oracle/src/*.cpp; do
  o="$WORK/oracle_$(basename "${f%.cpp}").o"
  $CXX $FLAGS -c "$f" -o "$o"
  ORACLE_OBJS+=("$o")
done

# The render targets' objects: the parser and the tracer (the command-line front end is
# left out).
RENDER_OBJS=()
if [ -f render/src/parse.cpp ]; then
  for f in render/src/*.cpp; do
    [ "$(basename "$f")" = cli.cpp ] && continue
    o="$WORK/render_$(basename "${f%.cpp}").o"
    $CXX $FLAGS -c "$f" -o "$o"
    RENDER_OBJS+=("$o")
  done
fi

# The targets of fuzz/targets.txt: "name links dictionary max_len".
TARGETS=()
while read -r t links dict max_len; do
  if [ "$links" = oracle ]; then
    $CXX $FLAGS "fuzz/$t.cpp" "${ORACLE_OBJS[@]}" $LIB_FUZZING_ENGINE $GMP_LIBS -o "$OUT/$t"
  elif [ ${#RENDER_OBJS[@]} -gt 0 ]; then
    $CXX $FLAGS "fuzz/$t.cpp" "${RENDER_OBJS[@]}" $LIB_FUZZING_ENGINE $PNG_LIBS -lpthread -o "$OUT/$t"
  else
    continue
  fi
  cp "fuzz/dict/$dict" "$OUT/$t.dict"
  printf '[libfuzzer]\nmax_len = %s\n' "$max_len" >"$OUT/$t.options"
  TARGETS+=("$t")
done < <(grep -E '^[a-z]' fuzz/targets.txt)

# Seed corpora: the committed corpora plus the regressions.
for t in "${TARGETS[@]}"; do
  [ -x "$OUT/$t" ] || continue
  rm -f "$OUT/${t}_seed_corpus.zip"
  files=$(find "fuzz/corpus/$t" "tests/regressions/$t" -type f ! -name '.*' 2>/dev/null || true)
  [ -n "$files" ] && echo "$files" | zip -q -j "$OUT/${t}_seed_corpus.zip" -@
done
echo "build.sh: built $(ls "$OUT" | grep -c -E '_fuzz$') fuzz targets in $OUT"
