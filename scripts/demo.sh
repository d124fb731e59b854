#!/usr/bin/env bash
# Installs what is missing, builds, and shows the kernel at work: the showcase table
# of every shape and mode on the rays that break textbook code.
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
install_missing
mkdir -p "$ROOT/build"
echo "== building (build/gcc)"
configure_and_build gcc g++ -DCMAKE_CXX_FLAGS_RELEASE="-O2 -DNDEBUG"
"$ROOT/build/gcc/tools/rayproof" showcase
