#!/usr/bin/env bash
# Configures and builds DLO in build/ (Release, warnings on). Two jobs: MRPT headers are heavy
# and the reference machine has 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "${DLO_JOBS:-2}"
