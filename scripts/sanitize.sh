#!/usr/bin/env bash
# The sanitizer run (docs/fuzzing.md): one clang build with AddressSanitizer, UBSan (fatal) and
# libFuzzer instrumentation (DEEPSEA_FUZZ=ON) in build-san/, then
#   1. every unit test binary, each in one process (the per-test processes CTest would start
#      cost three times as long under ASan, mostly in repeated fixtures), less three accuracy
#      tests that integrate exactly for minutes under ASan on code paths lighter tests here run
#      (SLOW_UNDER_ASAN below);
#   2. the CLI integration tests that drive the deepsea binary, and the fuzz regression
#      inputs; not the Blender/Cycles tests (they only drive Blender), the clang-format check,
#      nor five that spend minutes rendering under ASan on code paths the others cover
#      (real_data_test: the authors' sequence; reference_independent_test and
#      reference_validate_test: physics checked against a Python integrator and the path
#      tracer; render_kill_test and bake_kill_test: kills and resumes; 160, 120, 140, 130 and
#      about 100 s);
#   3. each libFuzzer target for FUZZ_SECONDS (default 20) from the seed corpus that
#      scripts/fuzz-corpus.sh makes.
# Any sanitizer report, in any process, fails the run: reports go to files under
# build-san/sanitizer-logs as well (some tests expect a command to fail, and check its stderr
# for one line only), and the run fails if any file is there.
# No Python module: an ASan-instrumented extension cannot be imported by Debian's python3.
# No ROS node (DEEPSEA_ROS=OFF): Debian's roscpp is not instrumented and keeps its own threads
# and singletons alive at exit; the node's ROS-free core (live_tests) runs here.
#   scripts/sanitize.sh [--no-fuzz | --fuzz-only]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh --tests  # clang-14 and its sanitizer runtimes
root=$(pwd)
fuzz=1 tests=1
case "${1:-}" in
  --no-fuzz) fuzz=0 ;;
  --fuzz-only) tests=0 ;;
esac
seconds=${FUZZ_SECONDS:-20}
b=build-san
t0=$SECONDS
stamp() { echo "== $1 ($((SECONDS - t0)) s)"; }

stamp "configure and build $b (clang, ASan + UBSan + libFuzzer)"
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
export CCACHE_BASEDIR=$PWD  # a checkout elsewhere hits the same cache
export CCACHE_NOHASHDIR=true  # (-g would hash the folder in; reports name the file either way)
CC=${SAN_CC:-clang-14} CXX=${SAN_CXX:-clang++-14} cmake -S . -B $b -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  "${launcher[@]}" -DDEEPSEA_BUILD_TESTS=ON -DDEEPSEA_FUZZ=ON -DDEEPSEA_BUILD_PYTHON=OFF -DDEEPSEA_ROS=OFF --no-warn-unused-cli >/dev/null
cmake --build $b -j "$(nproc)"

logs=$root/$b/sanitizer-logs
rm -rf "$logs"
mkdir -p "$logs"
export ASAN_OPTIONS="detect_leaks=1:halt_on_error=1:abort_on_error=0:log_path=$logs/asan"
export LSAN_OPTIONS="suppressions=$root/tests/sanitizers/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:log_path=$logs/ubsan"
fail=0
reports() {
  if compgen -G "$logs/*" >/dev/null; then
    echo "sanitizer reports:"
    for f in "$logs"/*; do echo "--- $f"; head -60 "$f"; done
    return 1
  fi
}

if ((tests)); then
  stamp "unit tests"
  # Exact integration along every ray for the accuracy bars: release-build tests (ctest) hold
  # them; the same code runs here in PortBake.Dispersions*, PortLayers.*, the dome reference and
  # the LampShadows tests left.
  SLOW_UNDER_ASAN='PortBake.RenderedBackscatterAgainstExactIntegrationAlongTheRefractedRays'
  SLOW_UNDER_ASAN+=':PortReference.AgainstTheRuntimeThroughFlatAndDomePorts'
  SLOW_UNDER_ASAN+=':LampShadows.SeafloorShadowsOnEveryOtherPixelAgreeAtTwiceTheResolution'
  run_unit() {
    local out
    if out=$("$1" --gtest_brief=1 --gtest_filter="-$SLOW_UNDER_ASAN" 2>&1); then
      echo "ok $(basename "$1")"
    else
      echo "$out" | tail -40
      echo "FAIL $1"
      return 1
    fi
  }
  run_unit $b/tests/runtime_tests &  # the longest: beside all the others
  slow=$!
  for t in $b/tests/*_tests; do
    [[ $t == */runtime_tests ]] || run_unit "$t" || fail=1
  done
  wait $slow || fail=1
  reports || fail=1

  stamp "integration tests and fuzz regressions"
  ctest --test-dir $b --output-on-failure -j "$(nproc)" -L 'integration|fuzz' \
    -E 'blender|cycles|format_test|real_data_test|reference_independent_test|reference_validate_test|render_kill_test|bake_kill_test' ||
    fail=1
  reports || fail=1
fi

if ((fuzz)); then
  stamp "fuzzing, ${seconds} s per target"
  # libFuzzer prints the report and keeps the input itself (and the triage below reads it).
  export ASAN_OPTIONS="detect_leaks=1:halt_on_error=1"
  export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
  corpus=$b/fuzz-corpus
  bash scripts/fuzz-corpus.sh $b/tools/deepsea/deepsea "$corpus" >/dev/null
  # fuzz_asset without comparison feedback: with it, libFuzzer copies the expected SHA-256 out
  # of the integrity check and forges the record, which is fuzz_asset_sealed's job.
  # fuzz_asset_sealed reaches OpenVDB's decoders, which trust lengths in the file; it runs in
  # fork mode past their crashes, and each crash is replayed and sorted below.
  # Its allocations over 1 GB stop it where they are made, so that the report (and the triage's
  # replay, which uses the same limit) has the allocating stack.
  declare -A extra=([asset]="-use_cmp=0"
    [asset_sealed]="-fork=1 -ignore_crashes=1 -ignore_ooms=1 -ignore_timeouts=1 -malloc_limit_mb=1024")
  for target in config asset asset_sealed depth image paths; do
    seeds=$corpus/${target%_sealed}
    work=$b/fuzz-work/$target
    rm -rf "$work"
    mkdir -p "$work/corpus"
    # -rss_limit_mb: the readers may allocate the largest image they accept (kMaxImagePixels
    # RGB floats, 1.2 GB) before a truncated raster is noticed.
    # shellcheck disable=SC2086
    if ! (cd "$work" && "$root/$b/tests/fuzz/fuzz_$target" -max_total_time="$seconds" \
          -rss_limit_mb=3072 -timeout=30 -print_final_stats=1 ${extra[$target]:-} \
          corpus "$root/$seeds" >log.txt 2>&1) && [[ $target != asset_sealed ]]; then
      tail -60 "$work/log.txt"
      echo "FAIL fuzz_$target (the crashing input is in $work)"
      fail=1
    fi
    execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$work/log.txt" | grep -o '[0-9]*$' ||
      grep -o '^#[0-9]*' "$work/log.txt" | tail -1 | tr -d '#')
    echo "fuzz_$target: ${execs:-?} executions"
    if [[ $target == asset_sealed ]]; then
      bash scripts/triage-crashes.sh "$b/tests/fuzz/fuzz_$target" "$work" || fail=1
    fi
  done
fi

stamp "done"
if ((fail)); then echo "sanitizer run FAILED"; exit 1; fi
echo "sanitizer run clean"
