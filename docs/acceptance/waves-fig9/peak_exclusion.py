#!/usr/bin/env python3
"""Why the jackknife SE of alpha_zero_rho0.2 is heavy-tailed (EXPERIMENTS.md,
"Fig. 9 over fresh base seeds"): the default fit of MODEL.md A9 removes the
+-16 bins around the spectrum's largest contrast even where there is no line,
and the jackknife re-finds that maximum in every leave-one-out mean.

Replicates src/analysis/fit.rs (estimate_alpha: fit range 40..=1000 at
m = 16384, local power-law background over 33 bins without the central +-2,
peak = largest contrast, +-16 bins removed, OLS of log10 P on log10 j) and
src/analysis/mean_spectrum.rs (alpha_of_mean, delete-one jackknife).

usage: peak_exclusion.py POINT [--figure FIGURE] [--bootstrap N] SEED_DIR...
  SEED_DIR is a figure's --out folder (holding FIGURE/runs/; FIGURE is
  waves-fig9 unless given); POINT is a sweep point (waves-fig9: rho0.2) or a
  set-up (waves-fig7: p0).
Prints one row per seed: the default alpha of the mean spectrum, its peak and
contrast, the default jackknife SE, the leave-outs whose peak moved, the SE
with the removed bins fixed at the full ensemble's peak, the alpha with no
bins removed and its jackknife SE, and optionally a bootstrap SE of the
default alpha. Needs numpy.
"""
import glob
import json
import sys

import numpy as np

H, GAP, J_LO, J_HI, HALF = 16, 2, 40, 1000, 16


def background(p, j):
    n = len(p)
    lo = max(j - H, 1)
    hi = min(lo + 2 * H, n - 1)
    lo = max(hi - 2 * H, 1)
    i = np.arange(lo, hi + 1)
    i = i[np.abs(i - j) > GAP]
    i = i[p[i] > 0]
    s, c = np.polyfit(np.log10(i), np.log10(p[i]), 1)
    return 10 ** (c + s * np.log10(j))


def peak(p):
    js = np.arange(J_LO, J_HI + 1)
    con = np.array([p[j] / background(p, j) for j in js])
    k = int(np.argmax(con))
    return int(js[k]), float(con[k])


def alpha(p, removed=None):
    js = np.arange(J_LO, J_HI + 1)
    keep = js[p[js] > 0]
    if removed is not None:
        keep = keep[np.abs(keep - removed) > HALF]
    s, _ = np.polyfit(np.log10(keep), np.log10(p[keep]), 1)
    return -s


def default(p):
    j, _ = peak(p)
    return alpha(p, j), j


def jackknife(values):
    v = np.asarray(values)
    n = len(v)
    return float(np.sqrt((n - 1) / n * ((v - v.mean()) ** 2).sum()))


def load(seed_dir, point, figure="waves-fig9"):
    """The spectra of the finished runs of `point` (a sweep point such as rho0.2,
    or a set-up such as p0) under `figure`'s --out folder."""
    for d in glob.glob(f"{seed_dir}/{figure}/runs/*"):
        config = json.load(open(d + "/run-00000.json"))["key"]["config"]["config"]
        if point not in (config.get("sweep-point"), config.get("set-up")):
            continue
        rows = [json.load(open(f))["result"] for f in sorted(glob.glob(d + "/run-*.json"))]
        rows = [r.get("Valid", r) for r in rows if "Invalid" not in r]
        return np.array([r["spectrum"] for r in rows])
    return None


def main(argv):
    if len(argv) < 2:
        sys.exit("usage: peak_exclusion.py POINT [--figure FIGURE] [--bootstrap N] SEED_DIR...")
    point, rest = argv[0], argv[1:]
    boot, figure = 0, "waves-fig9"
    while rest[:1] in (["--bootstrap"], ["--figure"]):
        if rest[0] == "--bootstrap":
            boot = int(rest[1])
        else:
            figure = rest[1]
        rest = rest[2:]
    rng = np.random.default_rng(29)
    print("| seed dir | runs | alpha | peak j | contrast | jackknife SE | leave-outs moving the peak "
          "| SE, removed bins fixed | alpha, none removed | its SE |" + (" bootstrap SE |" if boot else ""))
    print("|---|---|---|---|---|---|---|---|---|---|" + ("---|" if boot else ""))
    for sd in rest:
        p = load(sd, point, figure)
        if p is None or len(p) < 3:
            print(f"| {sd} | no finished runs at {point} |")
            continue
        n = len(p)
        total = p.sum(0)
        mean = total / n
        a, j = default(mean)
        _, con = peak(mean)
        loo = [default((total - p[i]) / (n - 1)) for i in range(n)]
        moved = sum(1 for _, jj in loo if jj != j)
        fixed = [alpha((total - p[i]) / (n - 1), j) for i in range(n)]
        none = [alpha((total - p[i]) / (n - 1)) for i in range(n)]
        row = (f"| {sd} | {n} | {a:.4f} | {j} | {con:.2f} | {jackknife([x for x, _ in loo]):.4f} | {moved} "
               f"| {jackknife(fixed):.4f} | {alpha(mean):.4f} | {jackknife(none):.4f} |")
        if boot:
            bs = [default(p[rng.integers(0, n, n)].mean(0))[0] for _ in range(boot)]
            row += f" {np.std(bs, ddof=1):.4f} |"
        print(row)


if __name__ == "__main__":
    main(sys.argv[1:])
