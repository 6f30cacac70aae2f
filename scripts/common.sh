#!/usr/bin/env bash
# Shared by scripts/bench, scripts/test, scripts/lint, scripts/sanitize and scripts/fuzz: install
# missing Debian packages, configure, build.
# Idempotent: with everything installed and built it only re-runs the (no-op) incremental build.
set -euo pipefail

CALIBENCH_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${CALIBENCH_BUILD_DIR:-$CALIBENCH_ROOT/build}"
PACKAGES=(cmake ninja-build g++ pkg-config libeigen3-dev libceres-dev libopencv-dev
          libapriltag-dev libyaml-cpp-dev libgtest-dev libgmock-dev libbenchmark-dev libcli11-dev
          python3 python3-matplotlib python3-scipy python3-pandas python3-statsmodels python3-yaml
          python3-tabulate python3-venv python3-setuptools
          python3-mrcal)

install_packages() {
  local missing=()
  for p in "${PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "calibench: installing ${missing[*]}" >&2
  local sudo=""
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { echo "calibench: need root (or sudo) to install: ${missing[*]}" >&2; exit 1; }
    sudo=sudo
  fi
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
}

# CALIBENCH_WERROR=ON (CI) makes the project's warnings errors (CMake option CALIBENCH_WERROR).
configure() {
  local opts=()
  [ -n "${CALIBENCH_WERROR:-}" ] && opts+=(-DCALIBENCH_WERROR="$CALIBENCH_WERROR")
  if [ ! -f "$BUILD_DIR/build.ninja" ]; then
    cmake -S "$CALIBENCH_ROOT" -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release \
      -DCALIBENCH_DATA_DIR="${CALIBENCH_DATA_DIR:-$CALIBENCH_ROOT/../shared/data}" "${opts[@]}" >&2
  elif [ ${#opts[@]} -gt 0 ] &&
       ! grep -qx "CALIBENCH_WERROR:BOOL=$CALIBENCH_WERROR" "$BUILD_DIR/CMakeCache.txt"; then
    cmake -S "$CALIBENCH_ROOT" -B "$BUILD_DIR" "${opts[@]}" >&2
  fi
}

build() {
  configure
  cmake --build "$BUILD_DIR" -j "${CALIBENCH_JOBS:-2}" >&2
}

# build-asan/ (preset asan: clang, ASan + UBSan, the tests and the fuzzers), configured afresh when
# missing or when an older one was configured otherwise (g++, or without the fuzzers).
ASAN_DIR="$CALIBENCH_ROOT/build-asan"
configure_asan() {
  local cache="$ASAN_DIR/CMakeCache.txt" fresh=()
  if [ -f "$ASAN_DIR/build.ninja" ] && grep -q "^CMAKE_CXX_COMPILER:[A-Z]*=.*clang++" "$cache" &&
     grep -qx "CALIBENCH_BUILD_FUZZERS:BOOL=ON" "$cache"; then
    return 0
  fi
  [ -f "$cache" ] && fresh=(--fresh)
  cmake --preset asan "${fresh[@]}" -S "$CALIBENCH_ROOT" \
    -DCALIBENCH_DATA_DIR="${CALIBENCH_DATA_DIR:-$CALIBENCH_ROOT/../shared/data}" >&2
}
