#!/usr/bin/env bash
# Installs every build and test dependency of rayaccel from Debian packages (only what is missing). Clang and
# libclang-rt-dev (libFuzzer and Clang's sanitizer runtimes) are for the fuzz tier, scripts/ci_fuzz.sh; chromium opens
# the bench's HTML report in a test (tests/cli/bench_report_test.cpp).
set -euo pipefail
packages=(
  build-essential cmake ninja-build pkg-config
  libtbb-dev libassimp-dev libstb-dev libcli11-dev nlohmann-json3-dev libfmt-dev
  libgtest-dev libbenchmark-dev libembree-dev libgmp-dev
  clang libclang-rt-dev
  python3 python3-numpy
  python3-dev pybind11-dev python3-pytest python3-matplotlib python3-pip python3-setuptools python3-wheel
  python3-dask python3-distributed
  chromium
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  sudo_cmd=""
  [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "setup: all packages present"
fi
