# Sourced by the scripts: installs what is missing (Debian 12, as root), configures and
# builds. Quiet when everything is already there.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
JOBS="${RAYPROOF_JOBS:-$(nproc)}"

# Everything the build, the suites, the fuzz replay, the tracer and the benchmarks use.
RAYPROOF_PACKAGES=(
  cmake ninja-build g++ clang libclang-rt-14-dev
  libeigen3-dev libcgal-dev libgmp-dev libmpfr-dev libboost-dev
  libgtest-dev librapidcheck-dev libbenchmark-dev
  nlohmann-json3-dev libpng-dev libembree-dev
  povray gnuplot-nox pkg-config
  pybind11-dev python3-dev python3-numpy python3-hypothesis python3-pytest
  libcli11-dev libfmt-dev
)

install_missing() {
  local missing=()
  for p in "${RAYPROOF_PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "installing: ${missing[*]}"
  local sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}

# configure_dir NAME CXX [extra cmake args...]: configures build/NAME (Ninja, Release,
# warnings as errors); prints the configure log on failure.
configure_dir() {
  local name="$1" cxx="$2"
  shift 2
  local dir="$ROOT/build/$name"
  cmake -S "$ROOT" -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER="$cxx" \
    -DRAYPROOF_WERROR=ON "$@" >"$dir.configure.log" 2>&1 || { mkdir -p "$dir"; cat "$dir.configure.log"; return 1; }
}

# build_dir NAME [targets...]: builds build/NAME (everything, or the targets named); prints
# the build log's errors and warnings on failure.
build_dir() {
  local dir="$ROOT/build/$1"
  shift
  cmake --build "$dir" -j "$JOBS" ${1:+--target "$@"} >"$dir.build.log" 2>&1 ||
    { grep -E "error|FAILED|warning" "$dir.build.log" | head -50; return 1; }
}

# configure_and_build NAME CXX [extra cmake args...]: build/NAME, warnings as errors.
configure_and_build() {
  configure_dir "$@" && build_dir "$1"
}
