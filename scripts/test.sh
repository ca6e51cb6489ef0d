#!/bin/bash
# Installs what is missing, builds, and runs everything CI checks:
#   1. the whole ctest suite in a Release build, scripts/run.sh's build type (-O3 finds warnings
#      -O2 does not; one build instead of two keeps the run under 20 minutes)  build/ci
#   1b. "slurm": the tests labelled slurm (a real one-node Slurm cluster, tests/slurm), build/ci;
#      SKIP with the reason printed where the cluster cannot start (not root, no slurmd)
#   1c. "python": the Python package (python/) installed in a venv over Debian's python3-*
#      packages, its pytest suite (tests/python) against build/ci's aalabd, docs/examples
#   2. the whole ctest suite with AddressSanitizer + UBSan            build/ci-sanitize
#   3. ThreadSanitizer: tests/tsan.sh's selection, then the end-to-end tests that drive
#      concurrency (tsan() names the others)                            build/ci-tsan
#   4. tests labelled "fuzz" (AALAB_FUZZ_SECONDS per target, default 20) in a clang libFuzzer
#      build                                                          build/ci-fuzz
#   5. systemd-analyze verify of systemd/*.socket|service (any output fails) and sysusers.d
#   6. systemd-analyze security --offline=yes aalabd.service, exposure <= 2.0
#   7. "package": the Debian packages built (scripts/build-deb.sh), linted, installed with
#      apt-get, the installed daemon run as the units run it, upgraded, removed and purged
#      (tests/package/package_stage.sh; root only, else SKIP)
# and prints a summary with the time of each stage. Exit status 0 only if every stage passed.
# Environment: AALAB_TEST_JOBS (default: nproc), AALAB_SKIP="tsan fuzz ..." to skip stages,
# AALAB_FUZZ_SECONDS (default 20).
set -u

cd "$(dirname "$0")/.."
repo=$(pwd)
jobs=${AALAB_TEST_JOBS:-$(nproc)}
skip=" ${AALAB_SKIP:-} "
summary=""
failed=0
t_all=$(date +%s)

stage() { # stage NAME COMMAND...: runs, records pass/fail and seconds
  name=$1; shift
  case "$skip" in *" $name "*) summary="$summary
  SKIP  $name"; return 0 ;; esac
  echo "==> $name"
  t0=$(date +%s)
  "$@"
  case $? in
    0) result=PASS ;;
    77) result=SKIP ;; # nothing to run in this stage (the slurm stage: the cluster cannot start)
    *) result=FAIL; failed=1 ;;
  esac
  t=$(( $(date +%s) - t0 ))
  summary="$summary
  $result  $name (${t}s)"
}

build() { # build DIR CMAKE-ARGS... (targets="A B" before it: only those)
  dir=$1; shift
  mkdir -p "$dir"
  cmake -S "$repo" -B "$dir" -G "Unix Makefiles" "$@" >"$dir.configure.log" 2>&1 ||
    { cat "$dir.configure.log"; return 1; }
  cmake --build "$dir" -j"$jobs" ${targets:+--target $targets} >"$dir.build.log" 2>&1 ||
    { grep -E "error|Error" "$dir.build.log" | head -50; return 1; }
}

suite() { # suite DIR [CTEST-ARGS...]
  dir=$1; shift
  (cd "$dir" && ctest -j"$jobs" --output-on-failure --timeout 600 "$@")
}

# Tests that mostly wait (sleeping jobs, a client trickling 1 byte/s, timeouts between users)
# and use little CPU: e2e_users_share waits out the 60 s slice with 8 s of CPU, load_slowloris
# 12 s with 0.2 s, e2e_users_net 33 s with 8 s. They run one after the other from
# DIR/tests's own ctest (its own Testing/ directory) beside the suite, instead of holding one of
# its $jobs slots while CPU-bound tests wait for it.
waiting='e2e_users_share|load_slowloris|e2e_users_net'
suite_beside() { # suite_beside DIR WAITING EXCLUDE [CTEST-ARGS...]: like suite, WAITING beside
  local dir=$1 names=$2 wait_re="^($2)\$" exclude=${3:-'^$'} rc pid
  shift 3
  (cd "$dir/tests" && ctest --no-tests=error --output-on-failure --timeout 600 "$@" \
     -R "$wait_re" -E "$exclude" >"$repo/$dir/beside.log" 2>&1) &
  pid=$!
  suite "$dir" "$@" -E "$exclude|$wait_re"
  rc=$?
  wait $pid || rc=1
  echo "--- beside the suite, one at a time: $names"
  cat "$repo/$dir/beside.log"
  return $rc
}

normal() {
  build build/ci -DCMAKE_BUILD_TYPE=Release && suite_beside build/ci "$waiting" '' -LE slurm
}

slurm() {
  # The one-node Slurm cluster tests (tests/slurm), serially and verbosely (they print what they
  # measured, or why they skip). The stage is SKIP when they skipped, FAIL when one failed.
  build build/ci -DCMAKE_BUILD_TYPE=Release || return 1
  log=$(mktemp)
  (cd build/ci && ctest -L slurm --no-tests=error -V --timeout 600) 2>&1 | tee "$log"
  rc=${PIPESTATUS[0]}
  skipped=$(grep -c '\*\*\*Skipped' "$log")
  rm -f "$log"
  [ "$rc" -eq 0 ] || return 1
  [ "$skipped" -eq 0 ] || return 77
}

python_stage() {
  # pip install offline (--no-index, Debian's setuptools: --no-build-isolation) into a venv that
  # sees Debian's numpy, matplotlib, tqdm, pytest, jsonschema; /usr/bin/python3, never a pyenv
  # python3 on PATH. The tests start build/ci's aalabd themselves and run docs/examples.
  build build/ci -DCMAKE_BUILD_TYPE=Release || return 1
  local venv=$repo/build/ci-python
  rm -rf "$venv" python/build python/aalab.egg-info
  /usr/bin/python3 -m venv --system-site-packages "$venv" &&
    "$venv/bin/pip" install -q --no-index --no-build-isolation --disable-pip-version-check \
      ./python || return 1
  rm -rf python/build python/aalab.egg-info
  (cd tests/python && AALAB_DAEMON="$repo/build/ci/server/aalabd" AALAB_TEST_INSTALLED=1 \
     "$venv/bin/python" -m pytest -q -p no:cacheprovider .)
}

sanitize() {
  # Leak checking is part of ASan; UBSan reports abort (-fno-sanitize-recover=all as well).
  build build/ci-sanitize -DCMAKE_BUILD_TYPE=Debug -DAALAB_SANITIZE=ON &&
    (export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
     export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
     # The fair-share figure (60 s slice) is measured in the normal stage; here the same check
     # runs with a 5 s slice.
     export AALAB_SHARE_SLICE=${AALAB_SHARE_SLICE:-5}
     # Slow tests run smaller under ASan, same code and checks (each test says what it shrinks);
     # the normal stage runs them at full size.
     export AALAB_TEST_SMALL=${AALAB_TEST_SMALL:-1}
     # Of the dashboard suites, web_jobs runs here: the daemon under ASan serving web/ over TCP,
     # issuing and revoking tokens, listing jobs and their patterns. The other suites add browser
     # checks of pages over endpoints the e2e tests already drive under ASan (3 minutes of CPU);
     # web_unit needs no daemon.
     # e2e_users_net is CPU-bound under ASan (55 s): it keeps its slot here.
     suite_beside build/ci-sanitize 'e2e_users_share|load_slowloris' \
       '^web_(unit|evaluate|families|optimize|tiles|kinds|recovery|layout|temporal|analysis|plots)$' \
       -LE slurm)
}

tsan() {
  # tests/tsan.sh's selection (worker pool, job store, ...), then, in the same ThreadSanitizer
  # build, the end-to-end tests, which drive the daemon's HTTP and worker threads for real.
  local dir=build/ci-tsan
  export TSAN_OPTIONS=${TSAN_OPTIONS:-halt_on_error=1:second_deadlock_stack=1}
  export AALAB_SHARE_SLICE=${AALAB_SHARE_SLICE:-5}
  sh tests/tsan.sh "$repo/$dir" || return 1
  # The end-to-end tests that drive concurrency: several users, connections, workers, restarts.
  # Those that check one request's decoding or computation (documentation examples, formats,
  # temporal jobs and renders, analysis, predict, the client) run the same code under ASan in
  # the sanitize stage; under TSan they cost 3 minutes and exercise no other thread interplay.
  suite_beside $dir e2e_users_share \
    '^(client_e2e|e2e_api_doc|e2e_temporal.*|e2e_points|e2e_formats|e2e_analysis|e2e_predict|e2e_schemas|e2e_optimize_scene|e2e_point_metrics|e2e_users_diskfull|e2e_users_fs|e2e_systemd)$' \
    -R e2e -LE slurm
}

fuzz() {
  # libFuzzer needs clang, and the fuzz build needs ASan+UBSan (tests/fuzz/CMakeLists.txt). It
  # builds the fuzz targets and the three programs, so clang's warnings still cover the code that
  # ships, without a fourth build of every test and benchmark.
  targets="fuzz_pattern_decoder fuzz_request_handler fuzz_pointset_parser fuzz_pointset_binary aalabd aalab
           aalab-worker" \
    build build/ci-fuzz -DCMAKE_C_COMPILER=clang -DCMAKE_BUILD_TYPE=Debug -DAALAB_FUZZ=ON \
    -DAALAB_SANITIZE=ON -DAALAB_WEB_TESTS=OFF -DAALAB_FUZZ_SECONDS="${AALAB_FUZZ_SECONDS:-20}" ||
    return 1
  suite build/ci-fuzz -L fuzz
}

units_dir=""
systemd_verify() {
  # verify insists that ExecStart= exists. Rather than install into /usr/local, check a copy of
  # the units whose ExecStart points at the aalabd just built (nothing else differs), and, if an
  # aalabd is installed, the units exactly as shipped too. Any output at all fails the stage.
  aalabd=$(find build/ci -type f -name aalabd -perm -u+x | head -1)
  [ -n "$aalabd" ] || { echo "no built aalabd under build/ci"; return 1; }
  units_dir=$(mktemp -d)
  sed "s|/usr/local/bin/aalabd|$repo/$aalabd|" systemd/aalabd.service >"$units_dir/aalabd.service"
  cp systemd/aalabd.socket "$units_dir/"
  out=$(systemd-analyze verify "$units_dir/aalabd.socket" "$units_dir/aalabd.service" 2>&1)
  rc=$?
  if [ -x /usr/local/bin/aalabd ]; then
    out="$out$(systemd-analyze verify systemd/aalabd.socket systemd/aalabd.service 2>&1)" || rc=1
  fi
  # The same units with the dashboard drop-ins (systemd/dashboard/*.d) beside them.
  cp -r systemd/dashboard/aalabd.socket.d systemd/dashboard/aalabd.service.d "$units_dir/"
  out="$out$(systemd-analyze verify "$units_dir/aalabd.socket" "$units_dir/aalabd.service" 2>&1)" ||
    rc=1
  [ -z "$out" ] && [ $rc -eq 0 ] || { echo "$out"; return 1; }
  # sysusers.d: creating the user and group in an empty root must work and say nothing odd.
  root=$(mktemp -d)
  mkdir -p "$root/etc"
  systemd-sysusers --root="$root" "$repo/systemd/aalab.conf" >/dev/null 2>&1 &&
    grep -q '^aalab:' "$root/etc/passwd" && grep -q '^aalab:' "$root/etc/group"
  rc=$?
  rm -rf "$root"
  [ $rc -eq 0 ] || { echo "systemd-sysusers rejected systemd/aalab.conf"; return 1; }
  echo "units and sysusers.d verified"
}

exposure=""
security_of() { # security_of DIR: exposure of DIR/aalabd.service (with the drop-ins beside it)
  out=$(cd "$1" && systemd-analyze security --offline=yes --threshold=20 aalabd.service 2>&1)
  rc=$?
  exposure=$(echo "$out" | sed -n 's/.*Overall exposure level for aalabd.service: \([0-9.]*\).*/\1/p')
  echo "exposure ($2): ${exposure:-unknown} (threshold 2.0)"
  [ $rc -eq 0 ] && [ -n "$exposure" ] && awk -v e="$exposure" 'BEGIN { exit !(e <= 2.0) }' ||
    { echo "$out" | grep -E "✗|Overall"; return 1; }
}
systemd_security() {
  plain=$(mktemp -d)
  cp systemd/aalabd.service "$plain/"
  security_of "$plain" "as shipped" || { rm -rf "$plain"; return 1; }
  shipped=$exposure
  cp -r systemd/dashboard/aalabd.service.d "$plain/"
  security_of "$plain" "with the dashboard drop-in"
  rc=$?
  rm -rf "$plain"
  exposure="$shipped, dashboard $exposure"
  return $rc
}

scripts/install-deps.sh || { echo "install-deps failed"; exit 1; }
stage normal normal
stage slurm slurm
stage python python_stage
stage sanitize sanitize
stage tsan tsan
stage fuzz fuzz
stage systemd-verify systemd_verify
stage systemd-security systemd_security
stage package tests/package/package_stage.sh
[ -n "$units_dir" ] && rm -rf "$units_dir"

echo
echo "summary (${jobs} jobs, $(( $(date +%s) - t_all ))s total, exposure ${exposure:-n/a}):$summary"
exit $failed
