#!/bin/sh
# Builds aalab with ThreadSanitizer (-DAALAB_TSAN=ON) in its own build directory and runs the
# worker-pool and job-store unit tests (and any other test matching $AALAB_TSAN_TESTS) under it.
# Any data race, lock-order inversion or signal-unsafe call fails the run.
#   tests/tsan.sh [BUILD_DIR]     (default: build-tsan next to the sources)
set -eu
src=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$src/build-tsan}
tests=${AALAB_TSAN_TESTS:-test_job_manager_stress|test_job_manager_share|test_fair_share|test_job_store|test_api|test_metric_threads|test_split_kinds}
cmake -S "$src" -B "$build" -G "Unix Makefiles" -DAALAB_TSAN=ON -DAALAB_SANITIZE=OFF \
  -DAALAB_FUZZ=OFF -DAALAB_WEB_TESTS=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
# Only what runs: the selected tests' programs (a unit test's target is its name) and the
# programs (scripts/test.sh's tsan stage runs the end-to-end tests in this build next), not
# every test and benchmark.
targets=$(ctest --test-dir "$build" -N -R "$tests" | sed -n 's/^ *Test *#[0-9]*: //p')
cmake --build "$build" -j2 --target aalabd aalab aalab-worker $targets
# halt_on_error: the first report fails the test; exitcode makes a report a non-zero exit even
# when a test catches nothing itself.
TSAN_OPTIONS="halt_on_error=1 exitcode=66 second_deadlock_stack=1 history_size=4 ${TSAN_OPTIONS:-}" \
  ctest --test-dir "$build" -R "$tests" --no-tests=error --output-on-failure --timeout 300
echo "tsan.sh: tests matching '$tests' passed under ThreadSanitizer"
