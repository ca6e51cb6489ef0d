#!/bin/sh
# help2man's "program" for aalab(1): aalab --help, then each command's own help, so that the man
# page documents every option. $AALAB is the aalab binary (set by dist/CMakeLists.txt).
set -eu
case "${1:-}" in
--version) exec "$AALAB" --version ;;
esac
"$AALAB" --help
echo
echo "Options of each command:"
"$AALAB" --help | sed -n '/^commands:/,/^$/s/^  \([a-z][a-z0-9-]*\) .*/\1/p' | while read -r c; do
  [ "$c" = help ] && continue
  echo
  "$AALAB" help "$c"
done
