#!/usr/bin/env bash
# README command (2): install what is missing, build, and run the whole test suite with ctest;
# check the installation and the Debian package (scripts/check_install.sh); then build again
# with AddressSanitizer + UndefinedBehaviorSanitizer (build-asan/) and run the suite once more
# under them (without the whole-drive accuracy tests, label "drive"); then fuzz every input
# parser for a bounded number of executions (scripts/run_fuzz.sh, build-fuzz/).
# DLO_SKIP_SANITIZERS=1 skips the second pass, DLO_SKIP_FUZZ=1 the third.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
bash scripts/build.sh
(cd build && ctest --output-on-failure -j "${DLO_JOBS:-2}")
# Installs into a temporary prefix, builds and runs a downstream project against it
# (tests/downstream) and makes the Debian package (scripts/check_install.sh).
bash scripts/check_install.sh build

if [ "${DLO_SKIP_SANITIZERS:-0}" != "1" ]; then
  echo "run_tests: the same suite under AddressSanitizer and UndefinedBehaviorSanitizer"
  # -O1, as the sanitizers' documentation advises: -O2 and -O3 cost more compile time under their
  # instrumentation than they save in the run (CMakeLists.txt, DLO_HOT_CODE_OPTIONS).
  # Line tables only (-g1): the sanitizers' reports keep their files and lines, and the build
  # takes about half the disk of full debug information (4.2 GB for build-asan/ with it; the
  # core library 150 -> 59 MB, its test binary 186 -> 97 MB).
  # A unity build, as scripts/build.sh's (DLO_UNITY_BUILD).
  cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDLO_SANITIZE=ON \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
    -DDLO_BUILD_BENCHMARKS=OFF -DDLO_DRIVE_TESTS=OFF \
    -DCMAKE_UNITY_BUILD="${DLO_UNITY_BUILD:-ON}" >/dev/null
  cmake --build build-asan -j "${DLO_JOBS:-2}"
  supp="$PWD/tests/sanitizers"
  # A malloc the system cannot serve returns null, as without the sanitizers (ASan otherwise
  # aborts): OpenCV then throws, and the rawlog reader reports a corrupt entry (FuzzRegression
  # tests).
  export ASAN_OPTIONS="detect_leaks=1:allocator_may_return_null=1"
  export LSAN_OPTIONS="suppressions=$supp/lsan.supp"
  export UBSAN_OPTIONS="suppressions=$supp/ubsan.supp:print_stacktrace=1:halt_on_error=1"
  # Mesa's llvmpipe, which renders map_render.png, otherwise leaves worker threads (and a shader
  # cache thread) ending while LeakSanitizer stops the world at exit: its tracer then crashed
  # now and then ("Tracer caught signal 11", exit 1) in dlo-slam runs of the SLAM tests. With
  # these, rendering stays on the calling thread.
  export LP_NUM_THREADS=0 MESA_SHADER_CACHE_DISABLE=true
  # Without the whole-drive accuracy tests (label "drive", see tests/CMakeLists.txt): they ran
  # for most of the sanitizer pass, judging accuracy that the Release pass already judged.
  (cd build-asan && ctest --output-on-failure -j "${DLO_JOBS:-2}" -LE drive)
fi

if [ "${DLO_SKIP_FUZZ:-0}" != "1" ]; then
  echo "run_tests: libFuzzer targets of every input parser (scripts/run_fuzz.sh)"
  bash scripts/run_fuzz.sh
fi
