#!/usr/bin/env python3
"""Height of the wave peak of an averaged spectrum over its background, per rho.

Reads the run files of a `waves-fig9 --out DIR` folder (DIR/waves-fig9/runs/*;
FIGURE as a second argument reads DIR/FIGURE/runs/* instead, e.g. waves-fig10)
and prints, per point (rho, and b, g where they vary): the valid runs, the bin j of the largest value of the
averaged spectrum in 400 <= j * L / 220 < 1000 (the wave speeds 0.27-0.67 at
the paper tier; the speed of bin j is proportional to L), its height over the background (the median of the bins 20-60 away on
either side), and the quartiles of the per-run peak bins j_peak.
Usage: prominence.py DIR [FIGURE]
"""
import glob
import json
import sys

rows = []
figure = sys.argv[2] if len(sys.argv) > 2 else "waves-fig9"
for d in glob.glob(sys.argv[1] + "/" + figure + "/runs/*"):
    params = json.load(open(d + "/config.json"))["config"]["config"]["spectrum"]["params"]
    rho, length = params["rho"], params["length"]
    key = (params["b"], params["g"], rho)
    name = "%.2f" % rho if figure == "waves-fig9" else "b %.2f, g %.2f" % (params["b"], params["g"])
    spectra, peaks = [], []
    for f in sorted(glob.glob(d + "/run-*.json")):
        r = json.load(open(f))["result"]
        if "Valid" in r:
            spectra.append(r["Valid"]["spectrum"])
            peaks.append(r["Valid"]["j_peak"])
    n = len(spectra)
    if n == 0:
        rows.append((key, "| %s | 0 | | | |" % name))
        continue
    mean = [sum(s[j] for s in spectra) / n for j in range(len(spectra[0]))]
    lo, hi = 400 * 220 // length, 1000 * 220 // length
    jm = max(range(lo, hi), key=lambda j: mean[j])
    background = sorted(mean[jm - 60 : jm - 20] + mean[jm + 20 : jm + 60])[40]
    peaks.sort()
    q = (peaks[n // 4], peaks[n // 2], peaks[(3 * n) // 4])
    rows.append((key, "| %s | %d | %d | %.2f | %d, %d, %d |" % ((name, n, jm, mean[jm] / background) + q)))
print("| point | valid runs | peak bin of the averaged spectrum | height / background | per-run peak bin quartiles |")
print("|---|---|---|---|---|")
for _, line in sorted(rows):
    print(line)
