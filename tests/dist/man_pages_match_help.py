#!/usr/bin/env python3
"""The man pages say what --help says: every option named in a program's help (and, for aalab,
in each `aalab help COMMAND`) appears in its man page, and every option the page names is one the
program's help names. The pages are generated from --help by help2man (dist/CMakeLists.txt), with
hand-written sections (dist/man/*.h2m) beside it; this catches a command left out of the page, a
flag added by hand to a page, or a page built from a stale program.

usage: man_pages_match_help.py PAGE PROGRAM [PAGE PROGRAM ...]
PAGE may be gzip-compressed (the installed /usr/share/man/...gz)."""

import gzip
import re
import subprocess
import sys

# A long option, or a short one standing alone (-s, -q, -o), not a negative number or a dash in
# a word.
OPTION = re.compile(r"(?<![\w-])(--[a-z][a-z0-9-]*|-[a-zA-Z])(?![\w-])")


def options(text):
    return set(OPTION.findall(text))


def help_text(program):
    """--help, and each command's own help when the program has commands (aalab)."""
    text = subprocess.run([program, "--help"], capture_output=True, text=True, check=True).stdout
    m = re.search(r"^commands:\n(.*?)\n\n", text, re.S | re.M)
    if m:
        for name in re.findall(r"^  ([a-z][a-z0-9-]*) ", m.group(1), re.M):
            if name != "help":
                text += subprocess.run([program, "help", name], capture_output=True, text=True,
                                       check=True).stdout
    return text


def page_text(path):
    raw = open(path, "rb").read()
    if raw[:2] == b"\x1f\x8b":
        raw = gzip.decompress(raw)
    text = raw.decode("utf-8")
    # roff comments, then the escapes help2man writes around options: \- for -, \fB..\fR fonts.
    text = re.sub(r'^\.\\".*$', "", text, flags=re.M)
    text = text.replace("\\-", "-")
    return re.sub(r"\\f[BIRP]", "", text)


def main(argv):
    if len(argv) < 2 or len(argv) % 2:
        print(__doc__, file=sys.stderr)
        return 2
    failed = False
    for page, program in zip(argv[0::2], argv[1::2]):
        in_help, in_page = options(help_text(program)), options(page_text(page))
        if not in_help:
            print(f"{program} --help names no option at all", file=sys.stderr)
            failed = True
        for o in sorted(in_help - in_page):
            print(f"{page}: missing {o} (in {program}'s help)", file=sys.stderr)
            failed = True
        for o in sorted(in_page - in_help):
            print(f"{page}: names {o}, which {program}'s help does not", file=sys.stderr)
            failed = True
        print(f"{page}: {len(in_help)} options, as in {program}'s help"
              if not in_help ^ in_page else f"{page}: differs from {program}'s help")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
