#!/usr/bin/env python3
"""The default alpha of the averaged spectrum (MODEL.md A9: the largest
contrast in 40..=1000 found again, its +-16 bins removed) with a bootstrap SE
over runs instead of the delete-one jackknife (docs/notebook/
2026-12-05-bootstrap-se-of-alpha.md, 2026-12-05). The estimate contains an argmax, which is
not smooth in the data: the project already takes the bootstrap, not the
jackknife, for the peak's velocity (src/analysis/mean_spectrum.rs, v_of_mean).
Each resample finds its own peak, so the spread of where the removed bins
fall is part of the SE.

With --line-rule the estimate is line_rule.py's instead: the peak's bins are
removed only where its contrast beats c*(n) = exp(1.49 / sqrt(n)), and each
resample decides again (and finds its own peak).

usage: bootstrap_alpha.py FIGURE POINT [--resamples B] [--line-rule] SEED_DIR...
  as line_rule.py; B = 400 unless given (the bootstrap of v_of_mean).
Prints one row per seed and the summary of line_rule.py. The SE is called
honest when SD / RMS SE lies within 0.7-1.4 and the coverage is at least
0.85, over at least 10 seeds (fixed before any seed was read with this
script). Needs numpy.
"""
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "waves-fig9"))
sys.path.insert(0, HERE)
from peak_exclusion import GAP, H, J_HI, J_LO, alpha, peak  # noqa: E402
from line_rule import honesty, seed_runs  # noqa: E402


def contrasts(p):
    """P(j) / B(j) for j in J_LO..=J_HI, vectorised; equal to peak_exclusion's
    background() inside the fit range (the window j-H..=j+H fits inside
    1..len-1 there, and every P > 0)."""
    js = np.arange(J_LO, J_HI + 1)
    offs = np.array([o for o in range(-H, H + 1) if abs(o) > GAP])
    i = js[:, None] + offs[None, :]
    x, y = np.log10(i), np.log10(p[i])
    xm, ym = x.mean(1, keepdims=True), y.mean(1, keepdims=True)
    s = ((x - xm) * (y - ym)).sum(1) / ((x - xm) ** 2).sum(1)
    c = ym[:, 0] - s * xm[:, 0]
    return js, p[js] / 10 ** (c + s * np.log10(js))


def fast_peak(p):
    js, con = contrasts(p)
    k = int(np.argmax(con))
    return int(js[k]), float(con[k])


def estimate(p, n, line_rule):
    """(alpha, peak j, whether its bins were removed) of averaged spectrum p
    of n runs."""
    j, c = fast_peak(p)
    removed = not line_rule or c > np.exp(1.49 / np.sqrt(n))
    return alpha(p, j if removed else None), j, removed


def main(argv):
    if len(argv) < 3:
        sys.exit(__doc__.split("usage: ")[1].split("\n")[0])
    figure, point, rest = argv[0], argv[1], argv[2:]
    b, line_rule = 400, False
    while rest[:1] in (["--resamples"], ["--line-rule"]):
        if rest[0] == "--line-rule":
            line_rule, rest = True, rest[1:]
        else:
            b, rest = int(rest[1]), rest[2:]
    rng = np.random.default_rng(0x5EED0029)
    vals = []
    what = "line-rule" if line_rule else "default"
    print(f"{figure} {point}: {what} alpha, bootstrap SE over runs ({b} resamples)")
    print("| seed folder | runs | peak j | contrast | bins removed | alpha | bootstrap SE | resamples with another peak | resamples removing bins |")
    print("|---|---|---|---|---|---|---|---|---|")
    for d, rows in seed_runs(rest, figure, point):
        n = len(rows)
        mean = rows.mean(0)
        j, c = fast_peak(mean)
        j0, c0 = peak(mean)
        assert j == j0 and abs(c - c0) <= 1e-9 * c0, f"vectorised contrast differs: {(j, c)} vs {(j0, c0)}"
        a, _, rem = estimate(mean, n, line_rule)
        boot = []
        moved = removing = 0
        for _ in range(b):
            x, jj, r = estimate(rows[rng.integers(0, n, n)].mean(0), n, line_rule)
            moved += jj != j
            removing += r
            boot.append(x)
        se = float(np.std(boot, ddof=1))
        vals.append((a, se))
        print(f"| {d} | {n} | {j} | {c:.3f} | {'yes' if rem else 'no'} | {a:.4f} | {se:.4f} | {moved} | {removing} |")
    if len(vals) >= 2:
        print(honesty(vals))


if __name__ == "__main__":
    main(sys.argv[1:])
