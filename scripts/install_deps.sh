#!/usr/bin/env bash
# Installs the Debian 12 packages DLO needs to build, test and benchmark, if missing.
# Run as root (or with sudo). Safe to run repeatedly: it only installs what is absent.
# DLO_WITH_PCL=1 also installs libpcl-dev (about 240 packages: VTK, Qt, OpenMPI), which lets
# dlo-bench compare against PCL's NDT and GICP; the build finds it on its own.
set -euo pipefail

PACKAGES=(
  build-essential cmake ccache pkg-config
  libmrpt-dev libeigen3-dev libopencv-dev zlib1g-dev nlohmann-json3-dev
  # the apps' command lines (header-only, needed to build only: not in the .deb's Depends)
  libcli11-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  clang-format
  # run_demo.sh and scripts/eval_matrix.py read report.json and metrics.json with Python's json
  python3
  # fuzzing (scripts/run_fuzz.sh): clang, and libclang_rt.fuzzer with the ASan/UBSan runtimes,
  # which Debian 12's clang-14 only recommends
  clang libclang-rt-14-dev
  # exports: graph-slam checks keyframes.graph; EGL + Mesa render map_render.png headless
  mrpt-apps libegl1 libegl-mesa0 libgl1-mesa-dri
)
if [ "${DLO_WITH_PCL:-0}" = "1" ]; then
  PACKAGES+=(libpcl-dev)
fi

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#PACKAGES[@]} packages present."
  exit 0
fi

if [ "$(id -u)" -ne 0 ]; then
  SUDO=sudo
else
  SUDO=
fi
echo "install_deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
# The downloaded packages (about 1.4 GB on a fresh machine) are not needed once installed: a CI
# machine with little disk ran out of space linking the tests with them kept.
$SUDO apt-get clean
