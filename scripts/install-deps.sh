#!/bin/sh
# Installs every Debian 12 package aalab needs to build, run and test (passwd and procps: the
# multi-user tests create users with useradd and end their processes with pkill;
# python3-jsonschema: the e2e tests validate every answer against proto/schemas; slurm-wlm and
# munge: tests/slurm starts a real one-node Slurm cluster; python3-venv ... python3-tqdm: the
# Python package's venv, offline build and pytest stage, tests/python; python3-scipy: the
# point-set analysis is checked against scipy.stats.qmc.discrepancy; python3-pandas: Job.to_frame()
# is tested with it; debhelper ... bash-completion: the man pages (help2man) and the Debian
# packages of scripts/build-deb.sh, linted and installed by the package stage, ccache so that its
# second package build reuses the first one's objects), then the dashboard test dependencies (npm
# ci in tests/web). Idempotent and quiet: when everything is present it only checks and returns.
# Needs root (or sudo) only when something is missing.
set -eu

cd "$(dirname "$0")/.."

PACKAGES="build-essential cmake pkg-config git ca-certificates
  libmicrohttpd-dev libjansson-dev libsqlite3-dev libpng-dev libcurl4-openssl-dev libsystemd-dev libssl-dev
  liblbfgs-dev libcmocka-dev clang libclang-rt-14-dev clang-format
  curl jq python3 python3-jsonschema sqlite3 wrk chromium systemd
  passwd procps slurm-wlm munge
  python3-venv python3-setuptools python3-wheel python3-pytest python3-numpy python3-matplotlib
  python3-pil python3-tqdm python3-scipy python3-pandas
  debhelper dh-python python3-all help2man lintian ccache bash-completion"

missing=""
for p in $PACKAGES; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing="$missing $p"
  fi
done
# Node for the dashboard tests: any node >= 18 will do (Debian's, or an existing one).
if ! command -v node >/dev/null 2>&1; then
  missing="$missing nodejs npm"
elif ! command -v npm >/dev/null 2>&1; then
  missing="$missing npm"
fi

if [ -n "$missing" ]; then
  if [ "$(id -u)" -ne 0 ]; then
    if command -v sudo >/dev/null 2>&1; then SUDO=sudo; else
      echo "install-deps: missing packages:$missing (run as root)" >&2
      exit 1
    fi
  else
    SUDO=
  fi
  echo "install-deps: installing$missing"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  # shellcheck disable=SC2086
  $SUDO apt-get install -y -qq --no-install-recommends $missing >/dev/null
fi

# Dashboard tests: playwright-core drives the Debian chromium, no browser download.
if [ -f tests/web/package.json ]; then
  stamp=tests/web/node_modules/.aalab-npm-ci
  lock=tests/web/package-lock.json
  if [ ! -f "$stamp" ] || { [ -f "$lock" ] && [ "$lock" -nt "$stamp" ]; } ||
     [ tests/web/package.json -nt "$stamp" ]; then
    if [ -f "$lock" ]; then
      (cd tests/web && PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1 npm ci --no-audit --no-fund --loglevel=error >/dev/null)
    else
      (cd tests/web && PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1 npm install --no-audit --no-fund --loglevel=error >/dev/null)
    fi
    touch "$stamp"
  fi
fi
