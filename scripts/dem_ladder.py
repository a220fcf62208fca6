#!/usr/bin/python3
"""The DEM validation ladder against kinetic theory (docs/dem_validation.md).

Runs constant-volume simple shear of three materials over phi, one point after the other, then
tabulates every point's T/(d gd)^2, sigma_yy/(rho_p d^2 gd^2) and mu against kinetic theory's
closed form for homogeneous steady shear (docs/model/closures.md, L = d):

    T/(d gd)^2 = f2/f3,   sigma_yy/(rho_p d^2 gd^2) = f1 f2/f3,   mu = sqrt(f2 f3)/f1

with f1 = nu (1 + 2 (1+e) G), f2 = 8 nu G J/(5 sqrt(pi)), f3 = 12 nu G (1 - eps^2)/sqrt(pi),
G = nu g0(nu), J of Garzo & Dufty 1999 as written by Berzi & Jenkins
(continuum/model/kinetic_theory_coefficients.hpp), g0 of Carnahan & Starling, and
eps = e - 1.5 mu_p exp(-3 mu_p) (Chialvo & Sundaresan 2013). The dense column "CS g0" uses
Chialvo & Sundaresan's g0 with its pole at phi_c instead (T/(d gd)^2 hardly depends on g0 at
large G: f2/f3 = 2 J/(15 (1 - eps^2)); the stresses scale with G).

    /usr/bin/python3 scripts/dem_ladder.py run      # runs what is missing under runs/ladder/
    /usr/bin/python3 scripts/dem_ladder.py table    # markdown tables from runs/ladder/*/result.h5

Options: --granflow PATH (default build/app/granflow), --out DIR (default runs/ladder),
--only NAME[,NAME] (blocks below). Each block is one `granflow run`; a block whose result.h5
is finished (summary.json) is not rerun.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import time

import h5py
import numpy as np
import yaml

PHI = [0.1, 0.2, 0.3, 0.4, 0.5, 0.55, 0.58]
PHI_LIST = "[" + ",".join(str(p) for p in PHI) + "]"
# k_n/(rho_p d^3 gd^2) = 1e4 at rho_p 2500, d 1 mm, gd 20 1/s: k_n = 10 N/m.
SOFT = ["--set", "material.normal_stiffness=10", "--set", "material.size_distribution=bidisperse",
        "--set", "control.solid_fraction=0.66"]

# name: (case, [--set ...], what it is)
N1000 = ["--set", "dem.particles=1000"]
BLOCKS = {
    "e09": ("cases/dem/gas_point.yaml",
            N1000 + ["--set", f"sweep.control.solid_fraction={PHI_LIST}"],
            "frictionless, e 0.9, 1000 monodisperse hooke spheres"),
    "e07": ("cases/dem/gas_point.yaml",
            N1000 + ["--set", "material.restitution=0.7",
                     "--set", f"sweep.control.solid_fraction={PHI_LIST}"],
            "frictionless, e 0.7, 1000 monodisperse hooke spheres"),
    "mu05": ("cases/dem/cv_sweep.yaml", [],
             "mu_p 0.5, e 0.7, 1000 bidisperse hertz spheres (cases/dem/cv_sweep.yaml)"),
    "size300": ("cases/dem/gas_point.yaml", ["--set", "statistics.seeds=2"],
                "system size: 300 spheres at phi 0.2, frictionless e 0.9, seeds 1-2"),
    "size2000": ("cases/dem/gas_point.yaml",
                 ["--set", "dem.particles=2000", "--set", "statistics.seeds=2"],
                 "system size: 2000 spheres at phi 0.2, frictionless e 0.9, seeds 1-2"),
    "seeds_e09": ("cases/dem/gas_point.yaml",
                  N1000 + ["--set", "control.solid_fraction=0.58", "--set", "dem.seed=2",
                           "--set", "statistics.seeds=2"],
                  "seeds 2-3 at phi 0.58, frictionless e 0.9, 1000 spheres (seed 1: e09)"),
    "seeds_mu05": ("cases/dem/cv_sweep.yaml",
                   ["--set", "sweep.control.solid_fraction=[0.58]", "--set", "dem.seed=2",
                    "--set", "statistics.seeds=2"],
                   "seeds 2-3 at phi 0.58, mu_p 0.5 e 0.7, 1000 spheres (seed 1: mu05)"),
    "soft066": ("cases/dem/gas_point.yaml", SOFT,
                "soft frictionless bidisperse, k_n/(rho_p d^3 gd^2) = 1e4, phi 0.66"),
}


# --- kinetic theory (continuum/model/kinetic_theory_coefficients.hpp, L = d) -----------------
def g0_cs(nu):
    return (1.0 - 0.5 * nu) / (1.0 - nu) ** 3


def g0_chialvo(nu, nu_c):
    return g0_cs(nu) + 0.58 * nu * nu / (nu_c - nu) ** 1.5


def kinetic(nu, e, mu_p, g0=None):
    """(T*, sigma*, mu) of steady homogeneous shear, T* = T/(d gd)^2, sigma* = p/(rho d^2 gd^2)."""
    G = nu * (g0 if g0 is not None else g0_cs(nu))
    eps = e - 1.5 * mu_p * math.exp(-3.0 * mu_p)
    J = 0.5 * (1 + e) + (math.pi / 32) * (5 + 2 * (1 + e) * (3 * e - 1) * G) * \
        (5 + 4 * (1 + e) * G) / ((24 - 6 * (1 - e) ** 2 - 5 * (1 - e * e)) * G * G)
    f1 = nu * (1 + 2 * (1 + e) * G)
    f2 = 1.6 * nu * G * J / math.sqrt(math.pi)
    f3 = 12 * nu * G * (1 - eps * eps) / math.sqrt(math.pi)
    return f2 / f3, f1 * f2 / f3, math.sqrt(f2 * f3) / f1


def f1_of(nu, e):
    return nu * (1 + 2 * (1 + e) * nu * g0_cs(nu))


def grad_dilute(e):
    """Grad's 13-moment solution of dilute steady uniform shear against Navier-Stokes.

    Moments of the Boltzmann equation for inelastic hard spheres in Grad's approximation: the
    pressure tensor relaxes at beta = (1+e)(3-e)/4 and cools at zeta* = (5/12)(1-e^2) (units of
    p/eta_0, eta_0 the elastic dilute viscosity). Steady uniform shear u_x = a y:
    a P_yy = -beta P_xy, P_yy = P_zz = p (1 - zeta*/beta), 2 a P_xy = -3 zeta* p, so
    eta/eta_0 = (beta - zeta*)/beta^2 against the Navier-Stokes 1/(beta - zeta*/2) (Garzo & Dufty
    1999, first Sonine, no c*); T scales as eta, mu = sqrt(3 zeta*/(2 (beta - zeta*))).
    Returns (T_Grad/T_NS, P_yy/p, mu_Grad/mu_NS). Santos, Garzo & Dufty 2004; Montanero, Garzo,
    Santos & Brey 1999.
    """
    beta = (1 + e) * (3 - e) / 4
    zeta = 5.0 / 12.0 * (1 - e * e)
    return ((beta - zeta) * (beta - zeta / 2) / beta ** 2, 1 - zeta / beta,
            math.sqrt((beta - zeta / 2) / (beta - zeta)))


# --- running -------------------------------------------------------------------------------
def run_blocks(args):
    os.makedirs(args.out, exist_ok=True)
    for name in args.only:
        case, sets, what = BLOCKS[name]
        out = os.path.join(args.out, name)
        if os.path.exists(os.path.join(out, "summary.json")):
            print(f"{name}: {out}/summary.json exists, not rerun")
            continue
        cmd = [args.granflow, "run", case, "--out", out, "--force"] + sets
        print(f"{name}: {what}\n  " + " ".join(cmd), flush=True)
        t0 = time.time()
        rc = subprocess.call(cmd, stdout=subprocess.DEVNULL)
        print(f"  exit {rc}, {time.time() - t0:.0f} s wall", flush=True)


# --- tabulating ----------------------------------------------------------------------------
def load(out, name):
    path = os.path.join(out, name, "result.h5")
    if not os.path.exists(os.path.join(out, name, "summary.json")):
        return None  # not run, or still running
    with open(os.path.join(out, name, "summary.json")) as f:
        summary = json.load(f)
    with open(os.path.join(out, name, "case.yaml")) as f:
        case_seed = int(yaml.safe_load(f)["dem"]["seed"])
    rows = []
    with h5py.File(path) as h:
        s = h["steady"]
        rho = float(s.attrs["particle_density"])
        e = float(s.attrs["restitution"])
        n = len(s["friction"])
        for k in range(n):
            c = h[f"conditions/{k}"]
            st = c["steady"].attrs
            d = float(c.attrs["mean_diameter"])
            gd = float(s["shear_rate"][k])
            scale = (d * gd) ** 2
            suffix = f".{k}" if n > 1 else ""
            rows.append(dict(
                phi=float(s["solid_fraction"][k]), e=e, mu_p=float(s["particle_friction"][k]),
                n_part=int(c.attrs["particles"]),
                T=float(s["granular_temperature"][k]) / scale,
                T_err=float(s["granular_temperature_err"][k]) / scale,
                sig=float(s["normal_stress"][k]) / (rho * scale),
                sig_err=float(s["normal_stress_err"][k]) / (rho * scale),
                mu=float(s["friction"][k]), mu_err=float(s["friction_err"][k]),
                Z=float(s["coordination"][k]),
                start=float(s["start_strain"][k]), end=float(st["end_strain"]),
                reached=int(s["steady_reached"][k]), drift=float(s["drift_max"][k]),
                frozen=int(st["frozen"]), overlap=float(st.get("overlap", float("nan"))),
                wall=float(s["wall_s"][k]),
                steps=summary.get("cost.steps" + suffix, float("nan")),
                sig_p=float(s["normal_stress"][k]) / float(s["pressure"][k]),
                seed=int(c.attrs.get("dem.seed", case_seed))))
    return rows


def rel(x, ref):
    return 100.0 * (x / ref - 1.0)


def ladder_table(rows, title):
    print(f"\n{title}\n")
    print("| φ | T/(dγ̇)² DEM | KT | Δ | σ_yy/(ρ_p d²γ̇²) DEM | KT | Δ | σ_yy/(ρ_p f1 T) | "
          "μ DEM | KT | Δ | Z | strain to steady (of) | steady | wall s | steps |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        T, sig, mu = kinetic(r["phi"], r["e"], r["mu_p"])
        flag = "yes" if r["reached"] else f"no ({r['drift']:.1f} SE)"
        print(f"| {r['phi']:.2f} | {r['T']:.4g} ± {r['T_err']:.2g} | {T:.4g} | "
              f"{rel(r['T'], T):+.1f} % | {r['sig']:.4g} ± {r['sig_err']:.2g} | {sig:.4g} | "
              f"{rel(r['sig'], sig):+.1f} % | {r['sig'] / (f1_of(r['phi'], r['e']) * r['T']):.3f} | "
              f"{r['mu']:.4f} ± {r['mu_err']:.4f} | {mu:.4f} | "
              f"{rel(r['mu'], mu):+.1f} % | {r['Z']:.2f} | {r['start']:.1f} ({r['end']:.0f}) "
              f"| {flag} | {r['wall']:.0f} | {r['steps']:.3g} |")


def dense_table(rows, title, nu_c):
    """Near jamming: the measured ratios against the CS-g0 stresses and the L/d that T needs."""
    print(f"\n{title}: anisotropy, against KT with Chialvo-Sundaresan g0 (φ_c {nu_c})\n")
    print("| φ | σ_yy / (tr P/3) | σ* / KT (CS g0) | μ / KT (CS g0) "
          "| T* / (f2/f3): the L/d that Γ ∝ 1/L needs |")
    print("|---|---|---|---|---|")
    for r in rows:
        cs = "–"
        if r["phi"] < nu_c:
            _, sig, mu = kinetic(r["phi"], r["e"], r["mu_p"], g0_chialvo(r["phi"], nu_c))
            cs = f"{r['sig'] / sig:.3f} | {r['mu'] / mu:.3f}"
        T, _, _ = kinetic(r["phi"], r["e"], r["mu_p"])
        print(f"| {r['phi']:.2f} | {r['sig_p']:.3f} | {cs} | {r['T'] / T:.3f} |")


def table(args):
    e = {name: load(args.out, name) for name in BLOCKS}
    total = sum(r["wall"] for rows in e.values() if rows for r in rows)
    labels = {"e09": "Frictionless, e 0.9", "e07": "Frictionless, e 0.7",
              "mu05": "Frictional μ_p 0.5, e 0.7 (ε = e − 1.5 μ_p exp(−3μ_p) = 0.533)"}
    for name, label in labels.items():
        if e[name]:
            ladder_table(e[name], label)
            dense_table(e[name], label, 0.587 if name == "mu05" else 0.64)
    for x in (0.9, 0.7, 0.7 - 1.5 * 0.5 * math.exp(-1.5)):
        t, pyy, m = grad_dilute(x)
        print(f"\nDilute uniform shear, Grad / Navier-Stokes at e {x:.3f}: T {t:.3f}, "
              f"P_yy/p {pyy:.3f}, μ {m:.3f}")
    for name in ("size300", "size2000", "seeds_e09", "seeds_mu05"):
        if not e[name]:
            continue
        if name.startswith("seeds") and e[name[6:]]:  # seed 1 is the ladder's own φ 0.58 point
            e[name] = [r for r in e[name[6:]] if abs(r["phi"] - 0.58) < 1e-9] + e[name]
        print(f"\n{BLOCKS[name][2]}\n")
        print("| N | seed | φ | T/(dγ̇)² | Δ KT | σ* | μ | strain to steady | steady | wall s |")
        print("|---|---|---|---|---|---|---|---|---|---|")
        for r in e[name]:
            T, _, _ = kinetic(r["phi"], r["e"], r["mu_p"])
            print(f"| {r['n_part']} | {r['seed']} | {r['phi']:.2f} | {r['T']:.4g} ± "
                  f"{r['T_err']:.2g} | {rel(r['T'], T):+.1f} % | {r['sig']:.4g} ± "
                  f"{r['sig_err']:.2g} | {r['mu']:.4f} ± {r['mu_err']:.4f} | {r['start']:.1f} | "
                  f"{r['reached']} | {r['wall']:.0f} |")
        if name.startswith("seeds"):
            for key, lab in (("T", "T*"), ("sig", "σ*"), ("mu", "μ")):
                v = np.array([r[key] for r in e[name]])
                w = np.array([r[key + "_err"] for r in e[name]])
                print(f"\n{lab}: mean {v.mean():.4g}, between-seed SD {v.std(ddof=1):.2g} "
                      f"(per-run SE {w.mean():.2g}, ratio {v.std(ddof=1) / w.mean():.2f})")
    if e["soft066"]:
        r = e["soft066"][0]
        print(f"\nsoft φ 0.66: T* {r['T']:.4g} ± {r['T_err']:.2g}, σ* {r['sig']:.4g} ± "
              f"{r['sig_err']:.2g}, μ {r['mu']:.4f} ± {r['mu_err']:.4f}, Z {r['Z']:.2f}, "
              f"<δ>/d {r['overlap']:.3g}, steady from {r['start']:.1f} of {r['end']:.0f}, "
              f"reached {r['reached']} (drift {r['drift']:.1f} SE), {r['wall']:.0f} s")
    print(f"\nTotal wall time of the points: {total:.0f} s")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("what", choices=["run", "table"])
    ap.add_argument("--granflow", default="build/app/granflow")
    ap.add_argument("--out", default="runs/ladder")
    ap.add_argument("--only", default=",".join(BLOCKS))
    args = ap.parse_args()
    args.only = [x for x in args.only.split(",") if x]
    for x in args.only:
        if x not in BLOCKS:
            sys.exit(f"unknown block {x}; blocks: {', '.join(BLOCKS)}")
    run_blocks(args) if args.what == "run" else table(args)


if __name__ == "__main__":
    main()
