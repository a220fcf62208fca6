#!/usr/bin/env python3
"""PNG plots of `kind: rev` element tests (test: triaxial, isotropic_compression).

One condition: triaxial.png (q-eps_d with the sigma_FC, sigma_COL, sigma_L contributions and a
magnified residual window, effective stress path, T and r_c vs eps_d, u_w and e vs eps_d);
with a reconsolidation stage also reconsolidation.png (T, r_c, p', u_w, e against the time since
the shear rate dropped). A sweep: overlays (sweep.png) and, for a rate sweep, residual q against
the rate with the fitted slopes (rate_sweep.png). Usage: plot_rev_triaxial.py RUN_DIR"""
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def arrays(g):
    return {k: g[k][:] for k in g.keys()}


def triaxial_figure(run, s, title):
    shear = s["stage"] == 0
    ed = s["deviatoric_strain"][shear]
    fig, ax = plt.subplots(2, 3, figsize=(15, 8))
    a = ax[0, 0]
    a.plot(ed, s["q"][shear] / 1e3, "g", label="q total")
    a.plot(ed, s["q_force_chain"][shear] / 1e3, "k--", label="q_FC (force chains)")
    a.plot(ed, s["q_collisional"][shear] / 1e3, "r", label="q_COL")
    a.plot(ed, s["q_liquid"][shear] / 1e3, "b", label="q_L")
    a.set(xlabel="ε_d", ylabel="q [kPa]", title="deviator stress and its three parts")
    a.legend(fontsize=8)
    # magnified residual window (the paper's 0.10 < ε_d < 0.12)
    a = ax[0, 1]
    window = ed >= 0.8 * ed[-1]
    a.plot(ed[window], s["q"][shear][window], "g", label="q total")
    a.plot(ed[window], s["q_force_chain"][shear][window], "k--", label="q_FC")
    a.plot(ed[window], s["q_collisional"][shear][window], "r", label="q_COL")
    a.plot(ed[window], s["q_liquid"][shear][window], "b", label="q_L")
    a.set(xlabel="ε_d", ylabel="q [Pa]", title="residual q (magnified)")
    a.legend(fontsize=8)
    a = ax[0, 2]
    a.plot(s["effective_pressure"] / 1e3, s["q_force_chain"] / 1e3, "k")
    a.set(xlabel="p' = p_FC [kPa]", ylabel="q_FC [kPa]", title="effective stress path")
    a = ax[1, 0]
    a.semilogy(ed, np.maximum(s["granular_temperature"][shear], 1e-30), "r")
    a.set(xlabel="ε_d", ylabel="T [m²/s²]", title="granular temperature T and r_c")
    b = a.twinx()
    b.plot(ed, s["locus_size"][shear] / 1e3, "k")
    b.set_ylabel("r_c [kPa] (black)")
    a = ax[1, 1]
    a.plot(ed, s["pore_pressure"][shear] / 1e3, "b", label="u_w")
    a.plot(ed, s["effective_pressure"][shear] / 1e3, "k", label="p'")
    a.plot(ed, s["collisional_pressure"][shear] / 1e3, "r", label="p_COL")
    a.set(xlabel="ε_d", ylabel="[kPa]", title="pore pressure, p', p_COL")
    a.legend(fontsize=8)
    a = ax[1, 2]
    a.plot(ed, s["void_ratio"][shear], "k")
    a.set(xlabel="ε_d", ylabel="e", title="void ratio")
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(os.path.join(run, "triaxial.png"), dpi=110)
    plt.close(fig)


def reconsolidation_figure(run, s):
    stage = s["stage"] == 1
    if not stage.any():
        return
    t0 = s["time"][np.argmax(stage) - 1]
    t = s["time"][stage] - t0
    fig, ax = plt.subplots(1, 3, figsize=(15, 4))
    ax[0].loglog(t, np.maximum(s["granular_temperature"][stage], 1e-30), "r")
    ax[0].set(xlabel="time since the rate drop [s]", ylabel="T [m²/s²]", title="T decays")
    ax[1].semilogx(t, s["locus_size"][stage] / 1e3, "k", label="r_c")
    ax[1].semilogx(t, s["effective_pressure"][stage] / 1e3, "g", label="p'")
    ax[1].semilogx(t, s["pore_pressure"][stage] / 1e3, "b", label="u_w")
    ax[1].semilogx(t, s["collisional_pressure"][stage] / 1e3, "r", label="p_COL")
    ax[1].set(xlabel="time since the rate drop [s]", ylabel="[kPa]",
              title="r_c regrows, the skeleton takes the load")
    ax[1].legend(fontsize=8)
    ax[2].semilogx(t, s["void_ratio"][stage], "k")
    ax[2].set(xlabel="time since the rate drop [s]", ylabel="e", title="compaction")
    fig.tight_layout()
    fig.savefig(os.path.join(run, "reconsolidation.png"), dpi=110)
    plt.close(fig)


def sweep_figure(run, h5):
    conds = sorted(h5["conditions"].keys(), key=int)
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.2))
    for n in conds:
        g = h5["conditions"][n]
        s = arrays(g["series"])
        label = ", ".join(f"{k.split('.')[-1]}={v:g}" for k, v in g.attrs.items())
        ax[0].plot(s["deviatoric_strain"], s["q"] / 1e3, label=label)
        ax[1].plot(s["effective_pressure"] / 1e3, s["q_force_chain"] / 1e3)
        ax[2].semilogx(np.maximum(s["effective_pressure"], 1.0), s["void_ratio"])
        ax[2].plot(s["effective_pressure"][-1], s["void_ratio"][-1], "ko")
    ax[0].set(xlabel="ε_d", ylabel="q [kPa]", title="deviator stress")
    ax[0].legend(fontsize=7)
    ax[1].set(xlabel="p' [kPa]", ylabel="q_FC [kPa]", title="effective stress paths")
    ax[2].set(xlabel="p' [Pa]", ylabel="e", title="e - p' (end points: black)")
    fig.tight_layout()
    fig.savefig(os.path.join(run, "sweep.png"), dpi=110)
    plt.close(fig)
    if "sweep" in h5:
        rate = h5["sweep/rate"][:]
        q = h5["sweep/residual_q"][:]
        o = np.argsort(rate)
        fig, a = plt.subplots(figsize=(6, 4.5))
        a.loglog(rate[o], q[o], "go-", label="residual q")
        a.loglog(rate[o], h5["sweep/residual_q_col"][:][o], "r^--", label="q_COL")
        a.loglog(rate[o], h5["sweep/residual_q_liq"][:][o], "bs--", label="q_L")
        for key, idx in (("slope_low", o[:3]), ("slope_high", o[-3:])):
            if key in h5["sweep"].attrs:
                k = h5["sweep"].attrs[key]
                x = rate[idx]
                c = np.exp(np.mean(np.log(q[idx]) - k * np.log(x)))
                a.loglog(x, c * x**k, "k:", lw=2)
                a.annotate(f"slope {k:.2f}", (x[1], c * x[1] ** k), textcoords="offset points",
                           xytext=(-40, 10))
        a.set(xlabel="ε̇_d [1/s]", ylabel="q [Pa]", title="residual q against rate")
        a.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(run, "rate_sweep.png"), dpi=110)
        plt.close(fig)


def isotropic_figure(run, s):
    fig, a = plt.subplots(figsize=(6, 4.5))
    a.semilogx(s["effective_pressure"], s["void_ratio"], "k")
    a.set(xlabel="p' [Pa]", ylabel="e", title="isotropic compression")
    fig.tight_layout()
    fig.savefig(os.path.join(run, "isotropic.png"), dpi=110)
    plt.close(fig)


def main(run):
    with h5py.File(os.path.join(run, "result.h5"), "r") as h5:
        if "conditions" in h5:
            sweep_figure(run, h5)
            return
        s = arrays(h5["series"])
        if np.all(s["deviatoric_strain"] == 0):
            isotropic_figure(run, s)
            return
        triaxial_figure(run, s, os.path.basename(os.path.normpath(run)))
        reconsolidation_figure(run, s)


if __name__ == "__main__":
    main(sys.argv[1])
