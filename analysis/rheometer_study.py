#!/usr/bin/env python3
"""Speed vs accuracy ladder of an MPM rheometer case (docs/speed-accuracy.md).

Runs `granflow run CASE --set ...` for a refinement ladder in mesh (cells_r x cells_theta, same
aspect), points per cell and the time-step factor, then compares every run with the finest one:
  error      RMS over time of tau(t) - tau_ref(t) (interpolated on the reference's samples),
             divided by the reference's peak tau
  profile    RMS of the final theta-averaged v_theta profile against the reference's (on the
             reference bins), divided by v_max
and reports the solver wall time. Writes OUT/study.csv, OUT/study.md, OUT/study.json (keys
study.N.error, study.N.profile_error, study.N.wall_s, study.N.label) and OUT/pareto.png.

Usage: rheometer_study.py CASE OUT [--granflow PATH] [--vary mesh,ppc,dt_factor]
                          [--mesh 4x32,6x48,8x64,12x96] [--ppc 1,2,3] [--dt 0.25,0.5,0.9]
                          [--set key.path=value ...] [--check]
--check checks the options only (exit 2 with one line on an unknown --vary name) and runs nothing.
The finest run (the reference) is the last mesh with the largest ppc and the smallest dt factor.
"""
import argparse
import json
import os
import subprocess
import sys
import time

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def run(granflow, case, out, sets):
    args = [granflow, "run", case, "--out", out, "--force"]
    for s in sets:
        args += ["--set", s]
    t0 = time.time()
    r = subprocess.run(args, capture_output=True, text=True)
    if r.returncode != 0:
        sys.stderr.write(r.stdout + r.stderr)
        return None
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    with h5py.File(os.path.join(out, "result.h5"), "r") as h5:
        t = h5["series"]["time"][:]
        tau = h5["series"]["tau"][:]
        keys = sorted(h5["profiles"].keys(), key=int)
        g = h5["profiles"][keys[-1]]
        prof = (g["radius"][:], g["velocity"][:])
    return dict(summary=summary, t=t, tau=tau, profile=prof, wall=summary.get(
        "cost.solver_wall_s", time.time() - t0))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("case")
    ap.add_argument("out")
    ap.add_argument("--granflow", default="granflow")
    ap.add_argument("--vary", default="mesh,ppc,dt_factor")
    ap.add_argument("--mesh", default="4x32,6x48,8x64,12x96")
    ap.add_argument("--ppc", default="1,2,3")
    ap.add_argument("--dt", default="0.25,0.5,0.9")
    ap.add_argument("--set", action="append", default=[], help="extra case overrides k.p=v")
    ap.add_argument("--check", action="store_true", help="check the options only, run nothing")
    a = ap.parse_args()
    vary = a.vary.split(",")
    for v in vary:
        if v not in ("mesh", "ppc", "dt_factor"):
            print(f"error: --vary: unknown ladder '{v}' (expected any of mesh,ppc,dt_factor)",
                  file=sys.stderr)
            sys.exit(2)
    if a.check:
        return
    meshes = [tuple(int(v) for v in m.split("x")) for m in a.mesh.split(",")]
    ppcs = [int(v) for v in a.ppc.split(",")]
    dts = [float(v) for v in a.dt.split(",")]
    base_mesh, base_ppc, base_dt = meshes[-2] if len(meshes) > 1 else meshes[0], 2, 0.5
    ladder = []  # (label, mesh, ppc, dt)
    if "mesh" in vary:
        ladder += [(f"mesh {m[0]}x{m[1]}", m, base_ppc, base_dt) for m in meshes]
    if "ppc" in vary:
        ladder += [(f"ppc {p}", base_mesh, p, base_dt) for p in ppcs if p != base_ppc]
    if "dt_factor" in vary:
        ladder += [(f"dt x{d:g}", base_mesh, base_ppc, d) for d in dts if d != base_dt]
    ref = ("reference", meshes[-1], max(ppcs), min(dts))
    ladder = [r for r in ladder if r[1:] != ref[1:]]  # the reference runs once
    ladder.append(ref)
    os.makedirs(a.out, exist_ok=True)
    results = []
    for k, (label, m, p, d) in enumerate(ladder):
        sets = [f"geometry.cells_r={m[0]}", f"geometry.cells_theta={m[1]}",
                f"geometry.points_per_cell={p}", f"numerics.cfl_factor={d}", "output.frames=0",
                "numerics.threads=1"] + a.set
        print(f"[{k}] {label}: {' '.join(sets)}", flush=True)
        r = run(a.granflow, a.case, os.path.join(a.out, f"run_{k}"), sets)
        results.append((label, m, p, d, r))
    ref_r = results[-1][4]
    if ref_r is None:
        sys.exit("the reference run failed")
    tau_peak = np.max(ref_r["tau"])
    vmax = ref_r["summary"]["rheometer.max_velocity"]
    rows = []
    for k, (label, m, p, d, r) in enumerate(results):
        if r is None:
            rows.append(dict(n=k, label=label, mesh=f"{m[0]}x{m[1]}", ppc=p, dt=d, error=None,
                             profile_error=None, wall_s=None, failed=True))
            continue
        tau_i = np.interp(ref_r["t"], r["t"], r["tau"])
        err = float(np.sqrt(np.mean((tau_i - ref_r["tau"]) ** 2)) / tau_peak)
        v_i = np.interp(ref_r["profile"][0], r["profile"][0], r["profile"][1])
        perr = float(np.sqrt(np.mean((v_i - ref_r["profile"][1]) ** 2)) / vmax)
        rows.append(dict(n=k, label=label, mesh=f"{m[0]}x{m[1]}", ppc=p, dt=d, error=err,
                         profile_error=perr, wall_s=float(r["wall"]),
                         peak_tau=float(np.max(r["tau"])),
                         steps=r["summary"].get("cost.steps"), failed=False))
    with open(os.path.join(a.out, "study.csv"), "w") as f:
        f.write("n,label,mesh,ppc,dt_factor,tau_error,profile_error,wall_s,peak_tau\n")
        for r in rows:
            f.write(f"{r['n']},{r['label']},{r['mesh']},{r['ppc']},{r['dt']},{r['error']},"
                    f"{r['profile_error']},{r['wall_s']},{r.get('peak_tau')}\n")
    with open(os.path.join(a.out, "study.md"), "w") as f:
        f.write("| N | run | mesh | ppc | dt factor | error τ̄(t) / τ̄_peak | error v_θ(r) / v_max "
                "| wall s | peak τ̄ Pa |\n|---|---|---|---|---|---|---|---|---|\n")
        for r in rows:
            if r["failed"]:
                f.write(f"| {r['n']} | {r['label']} | {r['mesh']} | {r['ppc']} | {r['dt']} | "
                        "failed | | | |\n")
            else:
                f.write(f"| {r['n']} | {r['label']} | {r['mesh']} | {r['ppc']} | {r['dt']} | "
                        f"{r['error']:.3g} | {r['profile_error']:.3g} | {r['wall_s']:.3g} | "
                        f"{r['peak_tau']:.4g} |\n")
    study = {}
    for r in rows:
        if not r["failed"]:
            study[f"study.{r['n']}.error"] = r["error"]
            study[f"study.{r['n']}.profile_error"] = r["profile_error"]
            study[f"study.{r['n']}.wall_s"] = r["wall_s"]
        study[f"study.{r['n']}.label"] = r["label"]
    with open(os.path.join(a.out, "study.json"), "w") as f:
        json.dump(study, f, indent=1)
    fig, ax = plt.subplots(figsize=(6, 4.5))
    for r in rows[:-1]:
        if r["failed"]:
            continue
        ax.loglog(r["wall_s"], max(r["error"], 1e-6), "o")
        ax.annotate(r["label"], (r["wall_s"], max(r["error"], 1e-6)), fontsize=7)
    ax.set(xlabel="solver wall time [s]", ylabel="RMS error of τ̄(t) / peak τ̄ (vs finest)",
           title="rheometer: speed vs accuracy")
    ax.grid(alpha=0.3, which="both")
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "pareto.png"), dpi=120)
    print(open(os.path.join(a.out, "study.md")).read())


if __name__ == "__main__":
    main()
