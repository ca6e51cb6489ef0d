"""aa_spearman_of (server/engine/core/spearman.c) against scipy.stats.spearmanr (python3-scipy):
random samples of 3 to 5,000 pairs with many ties (values rounded to a few levels), rho to
1e-12 absolute and the two-sided p-value to 1e-9 relative (where it is above 1e-250).
Usage: spearman_scipy.py path/to/spearman_cli. Exit 77 (skip) without scipy."""
import random
import subprocess
import sys

try:
    from scipy import stats
except ImportError:
    print("scipy missing: skipped")
    sys.exit(77)

cli = sys.argv[1]
rng = random.Random(31)
worst_rho = worst_p = 0.0
cases = 0
for trial in range(300):
    n = rng.choice([3, 4, 5, 7, 10, 30, 100, 1000, 5000])
    levels = rng.choice([2, 3, 5, 20, 1000, 0])  # 0: continuous, no ties
    slope = rng.uniform(-1, 1)
    xs, ys = [], []
    for _ in range(n):
        x = rng.random()
        y = slope * x + rng.gauss(0, 0.3)
        if levels:
            x = round(x * levels) / levels
            y = round(y * levels) / levels
        xs.append(x)
        ys.append(y)
    text = "%d\n" % n + "".join("%.17g %.17g\n" % p for p in zip(xs, ys))
    out = subprocess.run([cli], input=text, capture_output=True, text=True, check=True)
    rho, m, p = out.stdout.split()
    rho, m, p = float(rho), int(m), float(p)
    ref = stats.spearmanr(xs, ys)
    assert m == n, (m, n)
    if ref.correlation != ref.correlation:  # scipy: NaN for a constant side
        assert rho != rho, (n, levels, rho)
        continue
    d = abs(rho - ref.correlation)
    assert d <= 1e-12, ("rho", n, levels, rho, ref.correlation)
    worst_rho = max(worst_rho, d)
    if ref.pvalue > 1e-250:
        rel = abs(p - ref.pvalue) / ref.pvalue
        assert rel <= 1e-9, ("p", n, levels, p, ref.pvalue)
        worst_p = max(worst_p, rel)
    cases += 1
print("%d cases: worst |rho - scipy| %.2e, worst p-value relative %.2e" % (cases, worst_rho, worst_p))
