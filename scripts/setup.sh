#!/usr/bin/env bash
# Installs every build and test dependency of fine2coarse from Debian 12's packages.
# Idempotent: packages already present are skipped, so a second run costs a few seconds.
# --peers also installs what bench/run_benchmarks.sh needs to run Open3D's reconstruction
# system beside us (python3-open3d, python3-joblib); the build and the tests do not need it.
# clang, libclang-rt-14-dev: the sanitizer build and the libFuzzer targets (scripts/test_sanitized.sh).
# clang-format: the test that the sources follow .clang-format (scripts/check_format.sh).
# pybind11-dev, python3-dev, python3-numpy, python3-pytest: the Python module and its tests
# (docs/python.md); python3-matplotlib: its example.
# liblz4-dev, libbz2-dev: ROS bags' compressed chunks. python3-rosbag and the message modules,
# python3-pil: the tests write bags with ROS's own implementation (tests/tools/write_rosbag.py).
# libopenblas0-pthread: CHOLMOD (Ceres) then uses OpenBLAS instead of the reference BLAS
# or ATLAS; the refinement solves faster (BENCHMARKS.md). libsuitesparse-dev: CHOLMOD, which
# also factors our own one-step normal equations (src/f2c/optim/gauss_newton.h).
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libceres-dev libsuitesparse-dev libopencv-dev libnanoflann-dev libopenblas0-pthread
  libdeflate-dev libpng-dev libturbojpeg0-dev libxxhash-dev liblz4-dev libbz2-dev libzstd-dev libsqlite3-dev libcli11-dev libspdlog-dev libfmt-dev nlohmann-json3-dev libtbb-dev
  libgtest-dev libgmock-dev libbenchmark-dev libtinyxml2-dev
  libjs-three chromium
  clang libclang-rt-14-dev clang-format
  pybind11-dev python3-dev python3-numpy python3-pytest python3-matplotlib
  python3-rosbag python3-sensor-msgs python3-geometry-msgs python3-tf2-msgs python3-pil
)
[ "${1:-}" = "--peers" ] && packages+=(python3-open3d python3-joblib)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages present"
  exit 0
fi

echo "setup: installing ${missing[*]}"
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
