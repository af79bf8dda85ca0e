#!/usr/bin/env bash
# Checks that DLO installs and is usable downstream, from a Release build in build/ (run by
# scripts/run_tests.sh after the test suite):
#   1. `cmake --install` into a temporary prefix;
#   2. tests/downstream, a project of its own, configured with find_package(dlo) against that
#      prefix, built and run (it registers a scene through mrpt::slam::CDirectHeightAligner);
#   3. `cpack -G DEB` makes the Debian package (build/dlo_<version>_amd64.deb), whose contents
#      must hold the apps, the headers and the CMake package.
# Install the package on Debian 12 with: apt install ./build/dlo_<version>_amd64.deb
set -euo pipefail
cd "$(dirname "$0")/.."
build="${1:-build}"
work="$(mktemp -d /tmp/dlo-install-check.XXXXXX)"
trap 'rm -rf "$work"' EXIT

cmake --install "$build" --prefix "$work/prefix" >/dev/null
cmake -S tests/downstream -B "$work/downstream" -DCMAKE_PREFIX_PATH="$work/prefix" \
  -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$work/downstream" -j "${DLO_JOBS:-2}" >/dev/null
"$work/downstream/dlo_downstream"
"$work/prefix/bin/dlo-slam" --help >/dev/null

(cd "$build" && cpack -G DEB >/dev/null)
deb="$(ls -t "$build"/dlo_*.deb | head -n 1)"
contents="$(dpkg-deb -c "$deb")"
for f in ./usr/bin/dlo-slam ./usr/include/dlo/mrpt/CDirectHeightAligner.h \
  ./usr/lib/cmake/dlo/dloConfig.cmake ./usr/share/dlo/config/dlo-slam.ini; do
  if ! grep -qF "$f" <<<"$contents"; then
    echo "check_install: $deb lacks $f" >&2
    exit 1
  fi
done
echo "check_install: installed, built and ran tests/downstream against it; $deb holds the apps, headers and CMake package"
