#!/usr/bin/env bash
# Builds KISS-ICP as a peer of dlo-bench and scripts/eval_matrix.py (optional; CI does not):
#   bash scripts/build_kiss_icp_peer.sh KISS_ICP_SOURCE [SOPHUS_SOURCE] [BUILD_DIR]
# KISS_ICP_SOURCE: a checkout of github.com/PRBonn/kiss-icp (its C++ pipeline is built, nothing
# of it is copied into this project). SOPHUS_SOURCE: a checkout of github.com/strasdat/Sophus
# (1.24), which Debian 12 does not package; without it KISS-ICP's build downloads Sophus.
# Installs TBB and tsl-robin-map with apt, configures BUILD_DIR (default build/) with
# -DDLO_KISS_ICP_SOURCE and builds dlo-kiss-icp and dlo-bench. Then:
#   build/apps/dlo-kiss-icp/dlo-kiss-icp ../shared/data/kitti_city_seq poses.txt
#   build/apps/dlo-bench/dlo-bench --input drive.rawlog --out bench --kiss-icp
#   python3 scripts/eval_matrix.py --out /tmp/mx --kiss-icp
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 1 ] || [ ! -f "$1/cpp/kiss_icp/CMakeLists.txt" ]; then
  echo "build_kiss_icp_peer: the first argument must be a KISS-ICP source tree (with cpp/kiss_icp)." >&2
  exit 2
fi
kiss="$(cd "$1" && pwd)"
sophus=""
if [ $# -ge 2 ] && [ -n "$2" ]; then
  if [ ! -f "$2/sophus/se3.hpp" ]; then
    echo "build_kiss_icp_peer: '$2' is not a Sophus source tree (no sophus/se3.hpp)." >&2
    exit 2
  fi
  sophus="$(cd "$2" && pwd)"
fi
build="${3:-build}"
SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO=sudo
missing=()
for p in libtbb-dev robin-map-dev; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
bash scripts/install_deps.sh
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DDLO_KISS_ICP_SOURCE="$kiss" \
  -DDLO_SOPHUS_SOURCE="$sophus" >/dev/null
cmake --build "$build" -j "${DLO_JOBS:-2}" --target dlo-kiss-icp dlo-bench
echo "build_kiss_icp_peer: $build/apps/dlo-kiss-icp/dlo-kiss-icp built; dlo-bench --kiss-icp and eval_matrix.py --kiss-icp use it."
