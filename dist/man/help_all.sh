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
  # A heading per command ("aalab eval:" becomes a subsection), then its help with the usage
  # lines joined into one indented paragraph, a blank line, the rest (help2man would otherwise
  # run them together).
  echo
  echo "aalab $c:"
  "$AALAB" help "$c" | awk 'NR == 1 { sub(/^usage: *aalab */, ""); u = $0; next }
    !body && /^ +[^ ]/ {
      sub(/^ +/, "")
      if ($0 ~ /^aalab /) { print "  aalab " u; u = substr($0, 7) } else u = u " " $0
      next }
    !body { print "  aalab " u; print ""; body = 1 } { print }
    END { if (!body) print "  aalab " u }'
done
