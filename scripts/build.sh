#!/usr/bin/env bash
# Configures and builds DLO in build/ (Release, warnings on). Two jobs: MRPT headers are heavy
# and the reference machine has 2 cores. A unity build (CMake compiles the sources of each target
# in batches of eight, so each batch parses the Eigen, MRPT and GoogleTest headers once) halves
# the time of a build from scratch; the binaries work out the same numbers bit for bit.
# DLO_UNITY_BUILD=OFF builds one source at a time (quicker rebuilds after editing one file).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DCMAKE_UNITY_BUILD="${DLO_UNITY_BUILD:-ON}" \
  >/dev/null
cmake --build build -j "${DLO_JOBS:-2}"
