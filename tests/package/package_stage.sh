#!/bin/bash
# scripts/test.sh's stage "package": the Debian packages as an admin gets them. Root on a
# throwaway Debian 12 machine; systemd need not be PID 1 (the daemon is started the way the
# units would start it). In order:
#   1. scripts/build-deb.sh (dpkg-buildpackage -b -us -uc in build/deb-src/), lintian: no error;
#   2. apt-get install ./aalab_*.deb ./python3-aalab_*.deb: the user and group from sysusers.d,
#      /var/lib/aalab from tmpfiles.d, aalabd.socket enabled, no daemon started without systemd;
#      systemd-analyze verify of the installed units (with the example drop-ins too);
#   3. the installed aalabd started as user aalab with ExecStart= of the installed unit plus what
#      the socket unit would hand it (ListenStream, SocketGroup; the TCP listener of the dashboard
#      drop-in): aalab health and eval, the dashboard's / equal to /usr/share/aalab/web, a job and
#      a token, the Python client, the installed man pages against --help, bash completion;
#   4. upgrade to the same tree rebuilt as version X.Y.Z.1: the job and the token survive;
#   5. remove: the state stays; purge: the state is gone and nothing of `dpkg -L` is left.
# Exit 0 pass, 1 fail, 77 skip (not root). Refuses to run where aalab is installed already.
set -u
cd "$(dirname "$0")/../.."
repo=$(pwd)
out=$repo/build/ci-deb
port=${AALAB_PACKAGE_PORT:-18765}
unitdir=/lib/systemd/system
sock=/run/aalab/aalabd.sock
log=$out/aalabd.log
daemon_pid=""
tmp=""
t_start=$SECONDS

say() { echo "package: $* ($((SECONDS - t_start)) s)"; }
stop_daemon() {
  if [ -n "$daemon_pid" ]; then
    kill -TERM "$daemon_pid" 2>/dev/null
    wait "$daemon_pid" 2>/dev/null
    daemon_pid=""
  fi
}
installed() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "ok installed"; }
cleanup() {
  stop_daemon
  [ -n "$tmp" ] && rm -rf "$tmp"
  if installed aalab || installed python3-aalab; then
    DEBIAN_FRONTEND=noninteractive apt-get -o DPkg::Lock::Timeout=300 purge -y -qq aalab python3-aalab >/dev/null 2>&1
  fi
}
fail() {
  echo "package: FAIL: $*"
  [ -f "$log" ] && tail -20 "$log"
  cleanup
  exit 1
}
apt_install() { DEBIAN_FRONTEND=noninteractive apt-get -o DPkg::Lock::Timeout=300 install -y -qq "$@" >"$out/apt.log" 2>&1 ||
  { cat "$out/apt.log"; fail "apt-get install $*"; }; }

[ "$(id -u)" -eq 0 ] || { echo "package: SKIP: installs packages, needs root"; exit 77; }
if installed aalab || installed python3-aalab || [ -e /var/lib/aalab ]; then
  echo "package: FAIL: aalab is installed here (or /var/lib/aalab exists): this stage installs,"
  echo "  upgrades and purges the package; run it on a throwaway machine"
  exit 1
fi
rm -rf "$out"
mkdir -p "$out"
tmp=$(mktemp -d)

# 1. Build and lint.
scripts/build-deb.sh "$out/v1" >/dev/null || fail "scripts/build-deb.sh"
version=$(dpkg-deb -f "$out"/v1/aalab_*.deb Version)
say "built $(cd "$out/v1" && echo *.deb)"
lintian --fail-on error "$out"/v1/*.deb >"$out/lintian.log" 2>&1
rc=$?
grep -v "root privileges" "$out/lintian.log"
[ $rc -eq 0 ] || fail "lintian reports errors"
say "lintian: $(grep -c '^E:' "$out/lintian.log") errors, $(grep -c '^W:' "$out/lintian.log") warnings"

# 2. Install: what the maintainer scripts did.
apt_install "$out"/v1/aalab_*.deb "$out"/v1/python3-aalab_*.deb
say "installed $version"
getent passwd aalab >/dev/null && getent group aalab >/dev/null || fail "no user/group aalab"
[ "$(stat -c '%U:%G %a' /var/lib/aalab)" = "aalab:aalab 750" ] ||
  fail "/var/lib/aalab is $(stat -c '%U:%G %a' /var/lib/aalab 2>&1)"
[ -L /etc/systemd/system/sockets.target.wants/aalabd.socket ] || fail "aalabd.socket not enabled"
if [ ! -d /run/systemd/system ] && pgrep -x -u aalab aalabd >/dev/null; then
  fail "a daemon runs after install although systemd does not"
fi
out_verify=$(systemd-analyze verify $unitdir/aalabd.socket $unitdir/aalabd.service 2>&1) &&
  [ -z "$out_verify" ] || fail "systemd-analyze verify: $out_verify"
cp $unitdir/aalabd.socket $unitdir/aalabd.service "$tmp/"
cp -r /usr/share/doc/aalab/examples/dashboard/*.d "$tmp/"
out_verify=$(systemd-analyze verify "$tmp/aalabd.socket" "$tmp/aalabd.service" 2>&1) &&
  [ -z "$out_verify" ] || fail "systemd-analyze verify with the drop-ins: $out_verify"
say "user, state dir, socket enabled, units verified"

# 3. The daemon as the units run it: ExecStart= as user aalab with UMask=0027, the socket of
# aalabd.socket in group aalab, and the dashboard drop-in's TCP listener (here on $port).
start_daemon() {
  local exec listen
  exec=$(sed -n 's/^ExecStart=//p' $unitdir/aalabd.service)
  listen=$(sed -n 's/^ListenStream=//p' $unitdir/aalabd.socket)
  [ "${exec%% *}" = /usr/bin/aalabd ] && [ "$listen" = "$sock" ] || fail "unit: $exec, $listen"
  # shellcheck disable=SC2086
  (umask 027 && exec setpriv --reuid=aalab --regid=aalab --init-groups -- $exec \
     --socket "$listen" --socket-group aalab --tcp 127.0.0.1:$port) >>"$log" 2>&1 &
  daemon_pid=$!
  for _ in $(seq 100); do
    aalab health >/dev/null 2>&1 && return 0
    sleep 0.1
  done
  fail "the installed aalabd did not answer within 10 s"
}
client() { env -u AALAB_SOCKET -u XDG_RUNTIME_DIR aalab "$@"; }
start_daemon
health=$(client health) || fail "aalab health"
echo "$health" | grep -q "$version" || fail "health does not say $version: $health"
aalabd --version | grep -q "^aalabd $version" || fail "aalabd --version: $(aalabd --version)"
aalab --version | grep -q "^aalab $version" || fail "aalab --version: $(aalab --version)"
client eval rgss | grep -q "^E2  *0\.4389" || fail "aalab eval rgss: $(client eval rgss 2>&1)"
curl -fsS "http://127.0.0.1:$port/" | cmp -s - /usr/share/aalab/web/index.html ||
  fail "the dashboard's / is not /usr/share/aalab/web/index.html"
job=$(client optimize --family 'P(4,1+,2)' --seeds 1 --max-iterations 20 --wait -q) ||
  fail "optimize job"
token=$(client token --label package-stage | grep -o 'aalab_1_[A-Za-z0-9_-]*' | head -1)
[ -n "$token" ] || fail "no token issued"
api() { curl -s -o /dev/null -w '%{http_code}' -H "Authorization: Bearer $token" \
          "http://127.0.0.1:$port/v1/jobs/$job"; }
[ "$(api)" = 200 ] || fail "the token does not open job $job: $(api)"
/usr/bin/python3 -c "import aalab, sys; h = aalab.Client('$sock').health(); v = aalab.__version__
sys.exit(0 if h['version'] == v == '$version' else 'python3-aalab %s, daemon %s' % (v, h['version']))" ||
  fail "python3-aalab"
/usr/bin/python3 tests/dist/man_pages_match_help.py /usr/share/man/man8/aalabd.8.gz /usr/bin/aalabd \
  /usr/share/man/man1/aalab.1.gz /usr/bin/aalab \
  /usr/share/man/man8/aalab-worker.8.gz /usr/bin/aalab-worker >/dev/null || fail "man pages"
completion=$(bash -c '. /usr/share/bash-completion/bash_completion
  . /usr/share/bash-completion/completions/aalab
  COMP_WORDS=(aalab hea); COMP_CWORD=1; COMP_LINE="aalab hea"; COMP_POINT=9; _aalab
  echo "${COMPREPLY[*]}"')
[ "$completion" = health ] || fail "bash completion of 'aalab hea': '$completion'"
say "health, eval, dashboard /, job $job, token, python3-aalab, man pages, completion"

# 4. Upgrade to a rebuilt package with a bumped version; the state must survive.
stop_daemon
AALAB_DEB_VERSION=$version.1 scripts/build-deb.sh "$out/v2" >/dev/null || fail "rebuild as $version.1"
say "rebuilt as $version.1"
apt_install "$out"/v2/aalab_*.deb "$out"/v2/python3-aalab_*.deb
[ "$(dpkg-query -W -f='${Version}' aalab)" = "$version.1" ] || fail "not upgraded"
version=$version.1
start_daemon
client health | grep -q "$version" || fail "health after the upgrade: $(client health)"
client job "$job" | grep -q "done" || fail "job $job after the upgrade: $(client job "$job" 2>&1)"
[ "$(api)" = 200 ] || fail "the token does not open job $job after the upgrade: $(api)"
say "upgraded to $version: job $job and the token survive"

# 5. Remove keeps the state, purge removes it and leaves nothing of the packages' files.
stop_daemon
dpkg -L aalab python3-aalab >"$out/files.txt"
DEBIAN_FRONTEND=noninteractive apt-get -o DPkg::Lock::Timeout=300 remove -y -qq aalab python3-aalab >/dev/null 2>&1 ||
  fail "apt-get remove"
[ ! -e /usr/bin/aalabd ] && [ -f /var/lib/aalab/jobs.db ] && [ -f /var/lib/aalab/tokens.db ] ||
  fail "after remove: binaries must be gone, /var/lib/aalab kept"
DEBIAN_FRONTEND=noninteractive apt-get -o DPkg::Lock::Timeout=300 purge -y -qq aalab python3-aalab >/dev/null 2>&1 ||
  fail "apt-get purge"
[ ! -e /var/lib/aalab ] && [ ! -e /run/aalab ] || fail "/var/lib/aalab or /run/aalab left after purge"
[ ! -e /etc/systemd/system/sockets.target.wants/aalabd.socket ] || fail "enable link left"
left=$(while read -r f; do
         if [ -d "$f" ]; then case $f in *aalab*) echo "$f" ;; esac
         elif [ -e "$f" ] || [ -L "$f" ]; then echo "$f"; fi
       done <"$out/files.txt")
[ -z "$left" ] || fail "left after purge: $left"
say "removed (state kept), purged ($(wc -l <"$out/files.txt") paths of dpkg -L gone, state gone)"
cleanup
{ times; } >"$out/times.txt"
echo "package: CPU time of the stage's commands (user, system): $(tail -1 "$out/times.txt")"
