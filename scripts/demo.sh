#!/usr/bin/env bash
# Installs what is missing, builds, and shows the kernel at work: the showcase table of
# every shape and mode on the rays that break textbook code, then the default scene
# rendered in certified mode.
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
install_missing
mkdir -p "$ROOT/build"
echo "== building (build/gcc)"
configure_and_build gcc g++ -DCMAKE_CXX_FLAGS_RELEASE="-O2 -DNDEBUG"
"$ROOT/build/gcc/tools/rayproof" showcase
echo
echo "== rendering render/scenes/default.json (640x480, depth 5, certified)"
start=$(date +%s%N)
"$ROOT/build/gcc/tools/rayproof" render "$ROOT/render/scenes/default.json" -o "$ROOT/build/default.png" \
  --width 640 --height 480 --depth 5 --mode certified
ms=$(( ($(date +%s%N) - start) / 1000000 ))
printf "rendered in %d.%03d s\npicture: %s\n" $((ms / 1000)) $((ms % 1000)) "$ROOT/build/default.png"
