#!/usr/bin/env python3
"""The largest peak contrast of an averaged spectrum that has no line
(EXPERIMENTS.md "The same effect in PH95 Figs. 7, 8 and 10"): the null
distribution a "line present" rule would be calibrated on, before any
verdict is read.

Each synthetic run is Gaussian noise with spectrum ~ f^-a, analysed as
src/analysis/spectrum.rs does at the acceptance tier (NR spctrm, k = 4,
m = 16384: 8 segments of 32768 samples, the 1988 triangle window, no
overlap). The spectra of `runs` runs are averaged, and the contrast of
src/analysis/fit.rs (P over the local power-law background of 33 bins
without the central +-2) is maximised over the fit range 40..=1000.

usage: no_line_contrast.py RUNS ENSEMBLES [A] [SEED]
Prints the quantiles of the maximum contrast over ENSEMBLES ensembles.
Needs numpy.
"""
import sys

import numpy as np

M, K = 16384, 4
N = 2 * M
H, GAP, J_LO, J_HI = 16, 2, 40, 1000
I = np.arange(N)
WINDOW = 1 - np.abs((I - (N - 1) / 2) / ((N + 1) / 2))


def run_spectrum(rng, a):
    """The spctrm estimate of one run of 2K segments of f^-a noise."""
    f = np.fft.rfftfreq(2 * K * N)
    shape = np.where(f > 0, np.abs(f + (f == 0)) ** (-a / 2), 0.0)
    x = np.fft.irfft(np.fft.rfft(rng.standard_normal(2 * K * N)) * shape, 2 * K * N)
    x = (x - x.mean()).reshape(2 * K, N) * WINDOW
    power = np.abs(np.fft.fft(x, axis=1)) ** 2
    p = power[:, :M].copy()
    p[:, 1:] += power[:, N - 1 : N - M : -1]
    return p.mean(0) / (N * (WINDOW**2).sum())


def max_contrast(p):
    logs = np.log10(np.arange(len(p)) + (np.arange(len(p)) == 0))
    best = 0.0
    for j in range(J_LO, J_HI + 1):
        lo = max(j - H, 1)
        hi = min(lo + 2 * H, len(p) - 1)
        lo = max(hi - 2 * H, 1)
        i = np.arange(lo, hi + 1)
        i = i[np.abs(i - j) > GAP]
        s, c = np.polyfit(logs[i], np.log10(p[i]), 1)
        best = max(best, p[j] / 10 ** (c + s * logs[j]))
    return best


def main(argv):
    runs, ensembles = int(argv[0]), int(argv[1])
    a = float(argv[2]) if len(argv) > 2 else 0.0
    rng = np.random.default_rng(int(argv[3]) if len(argv) > 3 else 29)
    c = np.array(
        [max_contrast(np.mean([run_spectrum(rng, a) for _ in range(runs)], axis=0)) for _ in range(ensembles)]
    )
    q = np.quantile(c, [0.5, 0.9, 0.95, 0.99])
    print(f"runs {runs}, ensembles {ensembles}, a = {a}: max contrast median {q[0]:.3f}, "
          f"90 % {q[1]:.3f}, 95 % {q[2]:.3f}, 99 % {q[3]:.3f}, max {c.max():.3f}")


if __name__ == "__main__":
    main(sys.argv[1:])
