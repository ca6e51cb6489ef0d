#!/bin/sh
# Starts aalabd on a temporary socket and state dir, runs aalab_load against it (evaluate of
# the 4-sample RGSS pattern beside a GET /v1/health baseline, 2 connections), stops it.
#   bench/load/run_load.sh BUILD_DIR [aalab_load options...]
set -eu
build=${1:?usage: run_load.sh BUILD_DIR [options]}
shift
tmp=$(mktemp -d /tmp/aalab-load-XXXXXX)
"$build/server/aalabd" --socket "$tmp/s.sock" --state-dir "$tmp/state" >"$tmp/log" 2>&1 &
pid=$!
trap 'kill $pid 2>/dev/null; wait $pid 2>/dev/null; rm -rf "$tmp"' EXIT
i=0
while [ ! -S "$tmp/s.sock" ] && [ $i -lt 100 ]; do sleep 0.05; i=$((i + 1)); done
"$build/bench/load/aalab_load" --socket "$tmp/s.sock" "$@"
