#!/bin/sh
# Installs what is missing, builds a Release aalabd and aalab, and runs the daemon in the
# foreground with its embedded defaults plus a loopback TCP listener for the dashboard.
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

echo "aalab: socket     $socket"
echo "aalab: dashboard  http://$tcp/"
echo "aalab: client     $build/client/aalab health"
echo "aalab: curl       curl --unix-socket $socket http://localhost/v1/health"
exec "$build/server/aalabd" --socket "$socket" --tcp "$tcp" --web-dir "$repo/web" "$@"
