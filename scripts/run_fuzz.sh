#!/usr/bin/env bash
# Builds the libFuzzer targets of tests/fuzz in build-fuzz/ (clang, ASan + UBSan, DLO_FUZZ=ON);
# replays the inputs that once failed (tests/fuzz/regressions/<target>/), then runs each target
# for a bounded number of executions, starting from seeds cut from ../shared/data
# (dlo_fuzz_seeds) and the project's config/*.ini. Fails, naming the target and the input, on any
# crash, hang, leak, out-of-memory or broken error contract. Part of scripts/run_tests.sh
# (DLO_SKIP_FUZZ=1 skips it there).
#
#   DLO_FUZZ_RUNS     executions per target (default 10000)
#   DLO_FUZZ_SEED     libFuzzer's random seed (default 1, so that CI runs are reproducible;
#                     0 picks a new one each run)
#   DLO_FUZZ_TARGETS  targets to run (default: all), e.g. "ply config"
#   DLO_JOBS          build jobs (default 2)
set -euo pipefail
cd "$(dirname "$0")/.."
start=$SECONDS

runs=${DLO_FUZZ_RUNS:-10000}
seed=${DLO_FUZZ_SEED:-1}
targets=${DLO_FUZZ_TARGETS:-rawlog kitti_bin ply config pcap}
shared=$(cd ../shared/data && pwd)
command -v clang++ >/dev/null || {
  echo "run_fuzz: clang++ not found; install it with: bash scripts/install_deps.sh" >&2
  exit 1
}

# One source at a time (no unity build, unlike scripts/build.sh and the sanitizer pass): the
# suite's one build where every library source is compiled on its own, so that a source or
# header that misses an include fails here and not only for whoever builds without unity.
cmake -S . -B build-fuzz -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=Debug -DDLO_FUZZ=ON \
  -DDLO_BUILD_TESTS=OFF -DDLO_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build build-fuzz --target dlo_fuzz_targets -j "${DLO_JOBS:-2}"
build_time=$((SECONDS - start))

# Fresh corpora every run, so that the time and the inputs tried depend only on the sources.
corpus=build-fuzz/corpus
artifacts=build-fuzz/artifacts
logs=build-fuzz/fuzz-logs
rm -rf "$corpus" "$artifacts" "$logs"
mkdir -p "$corpus/config" "$logs"
build-fuzz/tests/fuzz/dlo_fuzz_seeds "$shared" "$corpus"
cp config/*.ini "$corpus/config/"

supp="$PWD/tests/sanitizers"
# detect_leaks: libFuzzer checks for leaks after every input that allocated more than it freed.
# alloc_dealloc_mismatch=0: tests/fuzz/allocation_limit.cpp serves operator new from malloc (so
# that a request beyond its heap limit throws std::bad_alloc instead of aborting), and ASan's
# operator delete then sees malloc'd blocks. A smaller quarantine, and freed memory handed back
# every second, keep the inputs that reach that limit from adding up in the resident size.
# allocator_may_return_null + max_allocation_size_mb: libraries that call malloc themselves get
# the same 64 MB block limit, and a refused malloc returns null as on a machine without the memory
# instead of aborting: OpenCV's cv::fastMalloc, behind every MRPT image, sizes the pixel buffer
# from the width and height in the file and throws when malloc fails (a corrupt entry).
export ASAN_OPTIONS="detect_leaks=1:alloc_dealloc_mismatch=0:quarantine_size_mb=64:allocator_release_to_os_interval_ms=1000:allocator_may_return_null=1:max_allocation_size_mb=64"
export LSAN_OPTIONS="suppressions=$supp/lsan.supp"
export UBSAN_OPTIONS="suppressions=$supp/ubsan.supp:print_stacktrace=1:halt_on_error=1"
# An input running 10 s is a hang; more than 2 GB resident, or one block beyond it, is out of
# memory.
limits=(-timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=2048)

# What went wrong, from a libFuzzer log (MRPT's decoders print much else, without newlines).
what_failed() {
  tr '\r' '\n' <"$1" | grep -a -oE '(==[0-9]+== ?ERROR: .*|SUMMARY: .*|[^ ]+: runtime error: .*|terminate called .*|what\(\): .*|input error that .*|Running: .*|Test unit written to .*)' |
    tail -n 12 || true
}

failed=()
for target in $targets; do
  binary=build-fuzz/tests/fuzz/dlo_fuzz_$target
  log=$logs/$target.log
  mkdir -p "$artifacts/$target" "$corpus/$target"
  t0=$SECONDS
  # First the committed inputs that once failed, each once and as they are: replayed, not used
  # as seeds (some make MRPT allocate up to the fuzzer's heap limit, slow to mutate).
  mapfile -t regressions < <(find "tests/fuzz/regressions/$target" -maxdepth 1 -type f 2>/dev/null |
    sort)
  if [ ${#regressions[@]} -gt 0 ] &&
    ! "$binary" "${limits[@]}" -artifact_prefix="$artifacts/$target/" "${regressions[@]}" \
      >"$logs/$target-regressions.log" 2>&1; then
    failed+=("$target")
    echo "run_fuzz: $target FAILED on a committed regression input ($logs/$target-regressions.log):"
    what_failed "$logs/$target-regressions.log"
    continue
  fi
  if "$binary" -runs="$runs" -seed="$seed" "${limits[@]}" -artifact_prefix="$artifacts/$target/" \
    -print_final_stats=1 "$corpus/$target" >"$log" 2>&1; then
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
    rss=$(sed -n 's/^stat::peak_rss_mb: *//p' "$log")
    cov=$(tr '\r' '\n' <"$log" | grep -a -oE 'cov: [0-9]+' | tail -1 | grep -oE '[0-9]+')
    echo "run_fuzz: $target passed (${#regressions[@]} regression inputs, $execs executions," \
      "$cov edges, peak RSS $rss MB, $((SECONDS - t0)) s)"
  else
    failed+=("$target")
    echo "run_fuzz: $target FAILED after $((SECONDS - t0)) s ($log):"
    what_failed "$log"
    inputs=$(find "$artifacts/$target" -type f 2>/dev/null)
    if [ -n "$inputs" ]; then
      echo "run_fuzz: $target: the failing input (reproduce with $binary FILE):"
      echo "$inputs" | sed 's/^/    /'
    fi
  fi
done

echo "run_fuzz: build ${build_time} s, total $((SECONDS - start)) s, $runs executions per target"
if [ ${#failed[@]} -gt 0 ]; then
  echo "run_fuzz: FAILED: ${failed[*]} (logs in $logs/)" >&2
  exit 1
fi
