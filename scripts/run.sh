#!/bin/sh
# Installs what is missing, builds a Release aalabd and aalab, and runs the daemon in the
# foreground with its embedded defaults plus a loopback TCP listener for the dashboard; once it
# is up, issues a bearer token to the calling user over the socket and prints the dashboard URL
# carrying it (every API request over TCP needs a token).
#   scripts/run.sh                 # Ctrl-C (SIGINT/SIGTERM) stops it gracefully
#   AALAB_TCP=127.0.0.1:9000 scripts/run.sh -- --workers 4   # extra aalabd flags after --
set -eu

cd "$(dirname "$0")/.."
repo=$(pwd)
build="$repo/build/release"
tcp=${AALAB_TCP:-127.0.0.1:8765}

scripts/install-deps.sh
cmake -S . -B "$build" -G "Unix Makefiles" -DCMAKE_BUILD_TYPE="${AALAB_BUILD_TYPE:-Release}" \
  -DAALAB_WEB_TESTS=OFF >/dev/null
cmake --build "$build" -j"$(nproc)" --target aalabd aalab >"$build.log" 2>&1 ||
  { grep -E "error|Error" "$build.log" | head -30; exit 1; }

# The same default as aalabd (and the aalab client): /run/aalab as root, else
# $XDG_RUNTIME_DIR/aalab, else /tmp/aalab-UID. Passed explicitly so what is printed is what is used.
if [ -n "${AALAB_SOCKET:-}" ]; then
  socket=$AALAB_SOCKET
elif [ "$(id -u)" -eq 0 ]; then
  socket=/run/aalab/aalabd.sock
elif [ -n "${XDG_RUNTIME_DIR:-}" ]; then
  socket=$XDG_RUNTIME_DIR/aalab/aalabd.sock
else
  socket=/tmp/aalab-$(id -u)/aalabd.sock
fi
[ "$#" -gt 0 ] && [ "$1" = "--" ] && shift

client="$build/client/aalab"
echo "aalab: socket     $socket"
echo "aalab: client     $client health"
echo "aalab: curl       curl --unix-socket $socket http://localhost/v1/health"
"$build/server/aalabd" --socket "$socket" --tcp "$tcp" --web-dir "$repo/web" "$@" &
daemon=$!
# A non-interactive shell's background job ignores SIGINT: pass Ctrl-C on as SIGTERM (the
# daemon's graceful stop) and keep waiting until it has exited.
trap 'kill -TERM "$daemon" 2>/dev/null' INT TERM
tries=0
until "$client" --socket "$socket" --timeout 2 health >/dev/null 2>&1; do
  kill -0 "$daemon" 2>/dev/null || { wait "$daemon" || exit $?; exit 1; }
  tries=$((tries + 1))
  [ "$tries" -lt 300 ] || { echo "aalab: the daemon did not answer on $socket" >&2; kill -TERM "$daemon"; wait "$daemon"; exit 1; }
  sleep 0.1
done
# The URL's fragment hands the token to the page (it is stored in the browser, then removed
# from the address bar); revoke it with: aalab token list / aalab token revoke ID.
"$client" --socket "$socket" token --label "dashboard (scripts/run.sh)" | sed 's/^/aalab: /'
status=0
while kill -0 "$daemon" 2>/dev/null; do
  wait "$daemon" && status=0 || status=$?
done
exit "$status"
