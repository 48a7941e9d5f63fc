#!/usr/bin/env python3
"""SD of the seeds' values over RMS SE, and the coverage of +-2 SE, of the
alpha SEs filed in docs/acceptance (the SE each summary states), for
docs/notebook/2026-12-05-bootstrap-se-of-alpha.md (2026-12-05).
Run from the repository root. Needs numpy."""
import json,glob,numpy as np,sys
def stats(pairs):
    a=np.array([p[0] for p in pairs]); se=np.array([p[1] for p in pairs])
    w=1/se**2; pooled=(a*w).sum()/w.sum(); cov=np.mean(np.abs(a-pooled)<=2*se)
    sd=a.std(ddof=1); rms=np.sqrt((se**2).mean())
    return f"seeds {len(a)}: mean {a.mean():.4f}, SD {sd:.4f}, RMS SE {rms:.4f}, SD/SE {sd/rms:.2f}, coverage {cov:.2f}, SE range {se.min():.4f}-{se.max():.4f}"
def summ(fig):
    out=[]
    for f in sorted(glob.glob(f"docs/acceptance/{fig}/seed-*/{fig}/summary.json"))+sorted(glob.glob(f"docs/acceptance/{fig}/seed-*/summary.json")):
        out.append(json.load(open(f)))
    return out
for fig,check in [("fig2","alpha"),("waves-fig6","alpha"),("waves-fig7","alpha_p0"),("waves-fig7","alpha_b0")]:
    pairs=[(c["measured"],c["error"]) for s in summ(fig) for c in s["checks"] if c["name"]==check]
    print(fig,check,stats(pairs))
ss=summ("waves-fig9")
print(sorted(k for k in ss[0].get("metrics",{}) if "rho0.2" in k))
for pt in ["rho0.2","rho0.4","rho0.6","rho0.8","rho1","rho1.2","rho1.4","rho1.6","rho1.8","rho2"]:
    pairs=[(s["metrics"][f"alpha_of_mean_{pt}"],s["metrics"][f"alpha_of_mean_{pt}_jackknife_se"]) for s in ss if f"alpha_of_mean_{pt}" in s.get("metrics",{})]
    if pairs: print("fig9",pt,stats(pairs))
