#!/usr/bin/env python3
"""Checks that the folders of server/ form layers: every #include "..." of a server header goes
to the same layer or a lower one in LAYERS, so no two folders include each other (issue 33).
Exits 1 naming each upward edge and any cycle between folders. Usage: check_layers.py [server]"""
import os
import re
import sys

# Lowest first. A folder, or a file of server/ itself (by name without extension).
LAYERS = [
    "engine",       # the library: no I/O, nothing above it
    "lock_held",    # ASSERT_LOCK_HELD, the _locked functions' precondition (header only)
    "owned_path",   # small helpers of server/ with no server includes
    "fallback_dir",
    "install_paths",  # where the installed web directory is (config.c's default)
    "kinds",        # the job kind and split contracts, shared by jobs/, cluster/ and worker/
    "tiles",
    "cluster",      # the Slurm executor: runs a kind's split, knows nothing of the job manager
    "jobs",         # the job manager, store and kinds
    "config",       # the daemon's configuration (includes cluster_config.h)
    "http",
    "worker",       # aalab-worker: one shard on a cluster node
    "main",         # aalabd
]


def unit_of(server, path):
    rel = os.path.relpath(path, server)
    parts = rel.split(os.sep)
    return parts[0] if len(parts) > 1 else os.path.splitext(parts[0])[0]


def main():
    server = sys.argv[1] if len(sys.argv) > 1 else os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "..", "server")
    files = []
    for root, _, names in os.walk(server):
        files += [os.path.join(root, n) for n in names if n.endswith((".c", ".h"))]
    by_name = {}
    for f in files:
        by_name.setdefault(os.path.basename(f), set()).add(unit_of(server, f))
    rank = {u: i for i, u in enumerate(LAYERS)}
    edges, bad = {}, []
    for f in files:
        src = unit_of(server, f)
        if src not in rank:
            bad.append(f"{src} ({f}) is in no layer: add it to LAYERS")
            continue
        for line in open(f, encoding="utf-8"):
            m = re.match(r'\s*#\s*include\s+"([^"]+)"', line)
            if not m:
                continue
            targets = by_name.get(os.path.basename(m.group(1)), set())
            if src in targets:  # a header of its own folder
                continue
            for dst in targets:
                edges.setdefault(src, set()).add(dst)
                if dst not in rank:
                    bad.append(f"{dst} is in no layer: add it to LAYERS")
                elif rank[dst] > rank[src]:
                    bad.append(f"{os.path.relpath(f, server)} includes {m.group(1)}: "
                               f"{src} is below {dst}")
    # A cycle between folders (implied by an upward edge, but named for the reader).
    for a in edges:
        for b in edges[a]:
            if a in edges.get(b, ()):
                bad.append(f"cycle: {a} and {b} include each other")
    for b in sorted(set(bad)):
        print(b)
    n = sum(len(v) for v in edges.values())
    print(f"{len(files)} files, {n} folder edges, layers {' < '.join(LAYERS)}: "
          + ("FAIL" if bad else "ok"))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
