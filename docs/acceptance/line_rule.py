#!/usr/bin/env python3
"""The "line rule" reading of the averaged-spectrum alpha (docs/notebook/
2026-12-05-bootstrap-se-of-alpha.md, 2026-12-05), measured on saved runs
before any Rust estimator changes:

- a line is present when the largest contrast of the averaged spectrum of n
  runs exceeds c*(n) = exp(Z / sqrt(n)), Z = 1.49: the 99th percentile of
  that contrast in synthetic no-line spectra (no_line_contrast.py: 1.141 at
  128 runs, 1.64-1.71 at 8);
- with a line, its +-16 bins (found once, on the mean of all runs) are
  removed, and the delete-one jackknife refits with the same bins removed;
- without one, no bin is removed, in the estimate and in the jackknife.

usage: line_rule.py FIGURE POINT SEED_DIR...
  FIGURE a figure binary (waves-fig9), POINT a sweep point (rho0.2) or a
  set-up (p0, spectrum); SEED_DIR a --out folder holding FIGURE/runs/.
Prints one row per seed and, over the seeds, the mean, the SD of the seeds'
values, the RMS of their SEs, SD / RMS SE (1 for an honest SE) and the share
of seeds whose value +- 2 SE holds the inverse-variance pooled value.
The SE is called honest when SD / RMS SE lies within 0.7-1.4 and the
coverage is at least 0.85, over at least 10 seeds (fixed before any seed was
read with this script). Needs numpy.
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "waves-fig9"))
from peak_exclusion import alpha, jackknife, load, peak  # noqa: E402

Z = 1.49


def threshold(n):
    return float(np.exp(Z / np.sqrt(n)))


def line_rule(rows):
    n = len(rows)
    total = rows.sum(0)
    mean = total / n
    j, c = peak(mean)
    line = c > threshold(n)
    removed = j if line else None
    a = alpha(mean, removed)
    se = jackknife([alpha((total - rows[i]) / (n - 1), removed) for i in range(n)])
    return a, se, j, c, line


def seed_runs(dirs, figure, point):
    """(folder, spectra) of each seed folder with at least 3 runs of `point`;
    a table row saying so for the others."""
    for d in dirs:
        rows = load(d, point, figure)
        if rows is None or len(rows) < 3:
            print(f"| {d} | no runs of {point} |")
            continue
        yield d, rows


def honesty(vals, extra=""):
    """The summary line over the seeds' (alpha, SE, ...) tuples: mean, SD, RMS
    SE, SD / RMS SE, coverage of +-2 SE around the inverse-variance pooled
    value."""
    a = np.array([v[0] for v in vals])
    se = np.array([v[1] for v in vals])
    w = 1 / se**2
    pooled = (a * w).sum() / w.sum()
    cover = np.mean(np.abs(a - pooled) <= 2 * se)
    sd, rms = a.std(ddof=1), np.sqrt((se**2).mean())
    return (f"\nseeds {len(vals)}{extra}: mean {a.mean():.4f}, SD {sd:.4f}, RMS SE {rms:.4f}, "
            f"SD/SE {sd / rms:.2f}, coverage of +-2 SE {cover:.2f}, SE range {se.min():.4f}-{se.max():.4f}")


def main(argv):
    if len(argv) < 3:
        sys.exit(__doc__.split("usage: ")[1].split("\n")[0])
    figure, point, dirs = argv[0], argv[1], argv[2:]
    vals = []
    print(f"{figure} {point}: threshold c*(n) = exp({Z}/sqrt(n))")
    print("| seed folder | runs | peak j | contrast | c*(n) | line | alpha | jackknife SE |")
    print("|---|---|---|---|---|---|---|---|")
    for d, rows in seed_runs(dirs, figure, point):
        a, se, j, c, line = line_rule(rows)
        vals.append((a, se, line))
        print(f"| {d} | {len(rows)} | {j} | {c:.3f} | {threshold(len(rows)):.3f} | {'yes' if line else 'no'} | {a:.4f} | {se:.4f} |")
    if len(vals) >= 2:
        print(honesty(vals, f" (line in {sum(v[2] for v in vals)})"))


if __name__ == "__main__":
    main(sys.argv[1:])
