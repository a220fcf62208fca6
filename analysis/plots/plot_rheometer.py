#!/usr/bin/env python3
"""PNG plots of a `kind: mpm, test: rheometer` run (seed section 6, Figs. 3-6).

Usage: plot_rheometer.py RUN_DIR [OTHER_RUN_DIR ...]
  rheometer_averages.png  tau vs sigma_G and tau vs gamma (all runs given, plus the sibling
                          rheometer runs found next to RUN_DIR)
  rheometer_steady.png    steady tau vs averaged shear rate, one point per run
  rheometer_profiles.png  radial profiles of gamma, v_theta (uniform-shear dashed), tau_rtheta
                          (quasi-static 1/r^2 dotted), porosity and r_c at several times;
                          fluidized fraction of the inner/middle/outer crowns against time
  rheometer_fields.png    r_c and porosity of the solid points at several times
  rheometer_history.png   mean pore pressure, mixture volume, fluidized fraction, std of n, T
"""
import glob
import json
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def is_rheometer(run):
    """A rheometer run: its result.h5 has the averaged series (summary.json may not exist yet
    while the run's own plot step executes)."""
    try:
        with h5py.File(os.path.join(run, "result.h5"), "r") as h5:
            return "series" in h5 and "tau" in h5["series"]
    except OSError:
        return False


def load(run):
    with h5py.File(os.path.join(run, "result.h5"), "r") as h5:
        s = {k: v[:] for k, v in h5["series"].items() if isinstance(v, h5py.Dataset)}
        vmax = float(h5["series"].attrs["max_velocity"])
    try:
        with open(os.path.join(run, "summary.json")) as f:
            summary = json.load(f)
    except (OSError, ValueError):
        summary = {}
    if "steady.tau" not in summary:  # as the kind computes it: mean over the last 20 %
        last = s["time"] >= 0.8 * s["time"][-1]
        summary["steady.tau"] = float(np.mean(s["tau"][last]))
        summary["steady.gamma_dot"] = float(np.mean(s["gamma_dot"][last]))
    summary["rheometer.max_velocity"] = vmax
    return summary, s


def averages(runs, out):
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.2))
    for run in runs:
        summary, s = load(run)
        label = f"v_max = {summary['rheometer.max_velocity']:g} m/s"
        axes[0].plot(s["sigma_G"] / 1e3, s["tau"] / 1e3, "-", label=label)
        axes[1].plot(s["gamma"], s["tau"] / 1e3, "-", label=label)
        axes[2].plot(summary["steady.gamma_dot"], summary["steady.tau"] / 1e3, "o", label=label)
    axes[0].set(xlabel="averaged σ_G [kPa]", ylabel="averaged τ [kPa]", title="stress path")
    axes[1].set(xlabel="averaged γ", ylabel="averaged τ [kPa]", title="τ̄ - γ̄")
    axes[2].set(xlabel="steady averaged shear rate [1/s]", ylabel="steady τ̄ [kPa]",
                title="steady state", xscale="log", yscale="log")
    for a in axes:
        a.legend(fontsize=7)
        a.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "rheometer_averages.png"), dpi=120)
    plt.close(fig)


def profiles(run):
    with h5py.File(os.path.join(run, "result.h5"), "r") as h5:
        if "profiles" not in h5:
            return
        r1 = h5["series"].attrs["inner_radius"]
        r2 = h5["series"].attrs["outer_radius"]
        fig, axes = plt.subplots(2, 3, figsize=(15, 8))
        axes = axes.ravel()
        for key in sorted(h5["profiles"].keys(), key=int):
            g = h5["profiles"][key]
            t = g.attrs["time"]
            vw = g.attrs["wall_velocity"]
            label = f"t = {t*1e3:.3g} ms"
            line, = axes[0].plot(g["radius"][:], g["shear_strain"][:], "-", label=label)
            col = line.get_color()
            axes[1].plot(g["radius"][:], g["velocity"][:], "-", color=col, label=label)
            rr = np.linspace(r1, r2, 50)
            # uniform shear (rigid-free Couette of a Newtonian fluid): v = A r + B / r
            A = vw * r2 / (r2 * r2 - r1 * r1)
            axes[1].plot(rr, A * (rr - r1 * r1 / rr), "--", color=col, lw=0.8)
            if "porosity" not in g:  # runs made before these profiles existed
                continue
            tau = g["shear_stress"][:]
            axes[2].plot(g["radius"][:], tau / 1e3, "-", color=col, label=label)
            # quasi-static torque balance: τ r² uniform (dotted, through the mean of τ r²)
            c = np.mean(tau * g["radius"][:] ** 2)
            axes[2].plot(rr, c / rr**2 / 1e3, ":", color=col, lw=0.8)
            axes[3].plot(g["radius"][:], g["porosity"][:], "-", color=col, label=label)
            axes[4].plot(g["radius"][:], g["locus_size"][:] / 1e3, "-", color=col, label=label)
        if "crowns" in h5:  # crown means, sampled with /series/time
            t = h5["series"]["time"][:] * 1e3
            for name, style in (("inner", "-"), ("middle", "--"), ("outer", ":")):
                c = h5["crowns"][name]
                axes[5].plot(t, c["fluidized_fraction"][:], style,
                             label=f"{name} crown, r_c = 0 fraction")
        axes[0].set(xlabel="r [m]", ylabel="θ-averaged γ", title="shear strain")
        axes[1].set(xlabel="r [m]", ylabel="θ-averaged v_θ [m/s]",
                    title="velocity (dashed: uniform shear)")
        axes[2].set(xlabel="r [m]", ylabel="θ-averaged σ'_rθ [kPa]",
                    title="shear stress (dotted: quasi-static τ ∝ 1/r²)")
        axes[3].set(xlabel="r [m]", ylabel="θ-averaged n", title="porosity")
        axes[4].set(xlabel="r [m]", ylabel="θ-averaged r_c [kPa]", title="locus size r_c")
        axes[5].set(xlabel="t [ms]", ylabel="fraction", title="fluidization of the crowns")
        for a in axes:
            a.legend(fontsize=7)
            a.grid(alpha=0.3)
        fig.tight_layout()
        fig.savefig(os.path.join(run, "rheometer_profiles.png"), dpi=110)
        plt.close(fig)


def fields(run):
    files = sorted(glob.glob(os.path.join(run, "fields", "step_*.h5")))
    if not files:
        return
    # frames nearest to 0.6, 1.2 and 2.5 ms (the skeleton's collapse) and the last one
    times = []
    for f in files:
        with h5py.File(f, "r") as h5:
            times.append(float(np.ravel(h5.attrs["time"])[0]))
    times = np.array(times)
    wanted = [6e-4, 1.2e-3, 2.5e-3, times[-1]]
    picks = [files[i] for i in sorted(set(int(np.argmin(np.abs(times - w))) for w in wanted))]
    frames = []
    for f in picks:
        with h5py.File(f, "r") as h5:
            xy = h5["solid"]["xy"][:]
            frames.append((float(np.ravel(h5.attrs["time"])[0]), xy,
                           h5["solid"]["r_c"][:] / 1e3 if "r_c" in h5["solid"]
                           else np.zeros(len(xy)), h5["solid"]["porosity"][:]))
    # One colour scale per row across the times, so that the frames compare by colour.
    rc_max = max(float(np.max(fr[2])) for fr in frames) or 1.0
    n_min = min(float(np.min(fr[3])) for fr in frames)
    n_max = max(float(np.max(fr[3])) for fr in frames)
    fig, axes = plt.subplots(2, len(picks), figsize=(3.6 * len(picks), 7), squeeze=False)
    for k, (t, xy, rc, n) in enumerate(frames):
        sc = axes[0][k].scatter(xy[:, 0], xy[:, 1], c=rc, s=3, cmap="viridis", vmin=0,
                                vmax=rc_max)
        fig.colorbar(sc, ax=axes[0][k], label="r_c [kPa]")
        axes[0][k].set(title=f"r_c, t = {t*1e3:.3g} ms", aspect="equal", xlabel="x [m]",
                       ylabel="y [m]")
        sc = axes[1][k].scatter(xy[:, 0], xy[:, 1], c=n, s=3, cmap="coolwarm", vmin=n_min,
                                vmax=n_max)
        fig.colorbar(sc, ax=axes[1][k], label="porosity n [-]")
        axes[1][k].set(title=f"porosity, t = {t*1e3:.3g} ms", aspect="equal", xlabel="x [m]",
                       ylabel="y [m]")
    fig.tight_layout()
    fig.savefig(os.path.join(run, "rheometer_fields.png"), dpi=110)
    plt.close(fig)


def history(run):
    _, s = load(run)
    t = s["time"] * 1e3
    numerics = "pore_pressure_std" in s
    fig, axes = plt.subplots(1, 5 if numerics else 4, figsize=(21 if numerics else 17, 3.8))
    axes[0].plot(t, s["pore_pressure"] / 1e3)
    axes[0].set(xlabel="t [ms]", ylabel="mean pore pressure [kPa]",
                title="pore pressure (paper: constant)")
    axes[1].plot(t, s["mixture_volume"] / s["mixture_volume"][0] - 1.0)
    axes[1].set(xlabel="t [ms]", ylabel="ΔV / V0", title="mixture volume of the solid points")
    axes[2].plot(t, s["fluidized_fraction"], label="r_c = 0 fraction")
    axes[2].plot(t, s["porosity_std"] / max(np.max(s["porosity_std"]), 1e-12),
                 label="std n (scaled)")
    axes[2].set(xlabel="t [ms]", title="fluidization, heterogeneity")
    axes[2].legend(fontsize=7)
    axes[3].semilogy(t, np.maximum(s["temperature"], 1e-12))
    axes[3].set(xlabel="t [ms]", ylabel="mean T [m²/s²]", title="granular temperature")
    if numerics:
        # Numerical health: the flow is axisymmetric, so the spread of p around its ring means
        # and the solid v_r stay small unless a grid mode grows (docs/rheometer.md).
        axes[4].semilogy(t, np.maximum(s["pore_pressure_std"], 1e-3), label="θ-spread of p [Pa]")
        axes[4].semilogy(t, np.maximum(s["radial_velocity_rms"], 1e-9) * 1e3,
                         label="rms solid v_r [mm/s]")
        axes[4].set(xlabel="t [ms]", title="numerical health (axisymmetry)")
        axes[4].legend(fontsize=7)
    for a in axes:
        a.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(run, "rheometer_history.png"), dpi=110)
    plt.close(fig)


def main():
    run = sys.argv[1]
    runs = [r for r in sys.argv[1:] if is_rheometer(r)]
    runs = runs or [run]
    parent = os.path.dirname(os.path.abspath(run))
    for sib in sorted(glob.glob(os.path.join(parent, "rheometer_test*"))):
        if os.path.abspath(sib) not in [os.path.abspath(r) for r in runs] and is_rheometer(sib):
            runs.append(sib)
    averages(runs, run)
    profiles(run)
    fields(run)
    history(run)


if __name__ == "__main__":
    main()
