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
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "waves-fig9"))
from peak_exclusion import peak  # noqa: E402  (the contrast of src/analysis/fit.rs, written once)

M, K = 16384, 4
N = 2 * M
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


def main(argv):
    if len(argv) < 2 or not (argv[0].isdigit() and argv[1].isdigit()) or min(int(argv[0]), int(argv[1])) < 1:
        sys.exit("usage: no_line_contrast.py RUNS ENSEMBLES [A] [SEED]  (RUNS, ENSEMBLES whole numbers >= 1)")
    runs, ensembles = int(argv[0]), int(argv[1])
    a = float(argv[2]) if len(argv) > 2 else 0.0
    rng = np.random.default_rng(int(argv[3]) if len(argv) > 3 else 29)
    c = np.array(
        [peak(np.mean([run_spectrum(rng, a) for _ in range(runs)], axis=0))[1] for _ in range(ensembles)]
    )
    q = np.quantile(c, [0.5, 0.9, 0.95, 0.99])
    print(f"runs {runs}, ensembles {ensembles}, a = {a}: max contrast median {q[0]:.3f}, "
          f"90 % {q[1]:.3f}, 95 % {q[2]:.3f}, 99 % {q[3]:.3f}, max {c.max():.3f}")


if __name__ == "__main__":
    main(sys.argv[1:])
