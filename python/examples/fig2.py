"""PH94 Fig. 2 from Python: the density spectrum at p = g = b = 0.5 and its
exponent alpha, the same numbers as `cargo run --release --bin fig2` at the
same tier and seed; then a plain NumPy engine of the pipe checked by
`validate`, and a wrong one that fails.

    pip install ./python matplotlib
    python python/examples/fig2.py [--tier quick] [--seed 1] [--out fig2-python.png]
"""

import argparse

import numpy as np

import granular_automata as ga
from numpy_engine import NumpyPipe, WrongPipe

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--tier", default="quick")
parser.add_argument("--seed", type=int, default=1)
parser.add_argument("--out", default="fig2-python.png")
args = parser.parse_args()

# 1. The figure: fig2's ensemble (the same seeds, engine and estimator)
ens = ga.spectrum_ensemble(tier=args.tier, seed=args.seed)
runs = len(ens["seeds"])
print(f"alpha = {ens['alpha']:.4f} +- {ens['alpha_err']:.4f} (mean of {runs} per-run fits)")
print(f"v_peak = {ens['v_peak']:.4f} (peak of the averaged spectrum)")

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    p = ens["mean_spectrum"]
    j = np.arange(len(p))
    fig, ax = plt.subplots(figsize=(7, 5))
    ax.loglog(j[1:], p[1:], lw=0.8, label=f"P(j), mean of {runs} runs")
    ref = p[10] * (j[1:] / 10.0) ** -1.33
    ax.loglog(j[1:], ref, "--", label="slope of the published alpha = 1.33")
    ax.set_xlabel("j")
    ax.set_ylabel("P(j)")
    ax.set_title(f"PH94 Fig. 2 from Python ({args.tier} tier, seed {args.seed}): alpha = {ens['alpha']:.3f}")
    ax.legend()
    fig.savefig(args.out, dpi=100)
    print(f"figure: {args.out}")
except ImportError:
    print("matplotlib is not installed: no figure (pip install matplotlib)")

# 2. A NumPy engine checked against the reference, and a wrong one
for name, engine in [("numpy", NumpyPipe), ("numpy-wrong-R1", WrongPipe)]:
    report = ga.validate(engine, level="1", tier="quick", name=name)
    l1 = report["level1"]
    verdict = "PASS" if report["pass"] else "FAIL"
    print(f"validate level 1, {name}: {verdict} ({len(l1['differences'])} differences in {l1['tests']} tests)")
