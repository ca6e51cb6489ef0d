#!/bin/sh
# Builds the Debian packages aalab and python3-aalab of this checkout (its committed and
# uncommitted files, as `git status` sees them) with `dpkg-buildpackage -b -us -uc`, in a copy
# under build/deb-src/ so that nothing is written outside build/, and puts the .debs in OUTDIR
# (default build/deb). The version is CMakeLists.txt's project(VERSION): when debian/changelog's
# top entry says another, the copy gets an entry for it. --version of the programs adds the git
# revision of the checkout.
#   scripts/build-deb.sh [OUTDIR]
# Environment: AALAB_DEB_VERSION=V builds the copy as version V (project(VERSION) rewritten in
# the copy: the upgrade test of scripts/test.sh); DEB_BUILD_OPTIONS (default "nocheck noddebs
# parallel=<nproc>": the suite is scripts/test.sh's). ccache, when installed, is used
# ($CCACHE_DIR, else build/deb-ccache): the copy's path is fixed so a rebuild reuses objects.
set -eu
cd "$(dirname "$0")/.."
repo=$(pwd)
out=${1:-build/deb}
case $out in /*) ;; *) out=$repo/$out ;; esac
top=$repo/build/deb-src
src=$top/aalab

rm -rf "$top"
mkdir -p "$src" "$out"
if git -c safe.directory='*' rev-parse --git-dir >/dev/null 2>&1; then
  AALAB_GIT_REV=$(git -c safe.directory='*' describe --always --dirty --abbrev=10 --match=NONE)
  export AALAB_GIT_REV
  git -c safe.directory='*' ls-files -z --cached --others --exclude-standard |
    xargs -0 sh -c 'for f; do [ -e "$f" ] && printf "%s\0" "$f"; done' files |
    tar --null -T - -cf - | tar -xf - -C "$src"
else
  tar --exclude=./build -cf - . | tar -xf - -C "$src"
fi

cd "$src"
if [ -n "${AALAB_DEB_VERSION:-}" ]; then
  sed -i "s/^project(aalab VERSION [0-9.]*/project(aalab VERSION $AALAB_DEB_VERSION/" CMakeLists.txt
fi
version=$(sed -n 's/^project(aalab VERSION \([0-9.]*\).*/\1/p' CMakeLists.txt)
[ -n "$version" ] || { echo "build-deb: no project(aalab VERSION ...) in CMakeLists.txt" >&2; exit 1; }
if [ "$(dpkg-parsechangelog -SVersion)" != "$version" ]; then
  maintainer=$(dpkg-parsechangelog -SMaintainer)
  { printf 'aalab (%s) unstable; urgency=medium\n\n' "$version"
    printf '  * Version %s of CMakeLists.txt project(VERSION)%s.\n\n' "$version" \
      "${AALAB_GIT_REV:+, git $AALAB_GIT_REV}"
    printf ' -- %s  %s\n\n' "$maintainer" "$(date -R)"
    cat debian/changelog; } >debian/changelog.new
  mv debian/changelog.new debian/changelog
fi

if command -v ccache >/dev/null 2>&1 && [ -d /usr/lib/ccache ]; then
  PATH=/usr/lib/ccache:$PATH
  CCACHE_DIR=${CCACHE_DIR:-$repo/build/deb-ccache}
  export PATH CCACHE_DIR
fi
export DEB_BUILD_OPTIONS="${DEB_BUILD_OPTIONS:-nocheck noddebs parallel=$(nproc)}"
dpkg-buildpackage -b -us -uc >"$top/build.log" 2>&1 ||
  { tail -40 "$top/build.log"; echo "build-deb: dpkg-buildpackage failed, log: $top/build.log" >&2; exit 1; }
rm -f "$out"/*.deb
mv "$top"/*.deb "$out"/
ls "$out"/*.deb
