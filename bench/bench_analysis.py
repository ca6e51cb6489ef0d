#!/usr/bin/env python3
"""aalab's point-set metrics beside scipy.stats.qmc.discrepancy on the same random sets of 64,
1,024 and 4,096 points, in one run: bench_analysis --points FILE times aalab (thread CPU time,
best of 3, all four L2 discrepancies in one pass); scipy is timed here per method (best of 3,
wall time, one worker). Prints both and the ratio scipy / aalab for the discrepancies.
    python3 bench/bench_analysis.py BUILD/bench/bench_analysis"""

import os
import subprocess
import sys
import tempfile
import time

import numpy as np
from scipy.stats import qmc


def best_of(f, reps=3):
    best = float("inf")
    for _ in range(reps):
        t0 = time.perf_counter()
        f()
        best = min(best, time.perf_counter() - t0)
    return best * 1e3


def main():
    binary = sys.argv[1]
    rng = np.random.default_rng(2026)
    print("%6s %12s %12s %10s | %10s %10s %10s %10s" % (
        "points", "aalab 4xL2", "scipy 4xL2", "ratio", "star_linf", "spacing", "spectrum",
        "pcf"))
    for n in (64, 1024, 4096):
        x = rng.random((n, 2))
        with tempfile.NamedTemporaryFile("w", suffix=".txt", delete=False) as f:
            f.write("\n".join("%r %r" % (a, b) for a, b in x))
            path = f.name
        try:
            out = subprocess.run([binary, "--points", path], check=True, capture_output=True,
                                 text=True).stdout.split("\n")
        finally:
            os.unlink(path)
        ours = [float(line.split()[1]) for line in out if line.strip()]
        scipy_ms = sum(best_of(lambda m=m: qmc.discrepancy(x, method=m))
                       for m in ("CD", "WD", "MD", "L2-star"))
        print("%6d %10.2f ms %10.2f ms %9.1fx | %7.2f ms %7.2f ms %7.2f ms %7.2f ms" % (
            n, ours[0], scipy_ms, scipy_ms / ours[0], ours[1], ours[2], ours[3], ours[4]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
