#!/usr/bin/env python3
"""PNG plots of a `kind: rev` run: time series of one condition, or the steady tables of a sweep
(mu(I), e(I), T/(d gamma_dot)^2 and, with liquid, mu(J), mu(K)). Usage: plot_rev.py RUN_DIR"""
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def series_plots(run, h5):
    g = h5["series"]
    strain = g["strain"][:]
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.8))
    axes[0].loglog(strain, g["granular_temperature"][:])
    axes[0].set(xlabel="shear strain γ", ylabel="T [m²/s²]", title="granular temperature")
    axes[1].semilogx(strain, g["friction"][:])
    axes[1].set(xlabel="shear strain γ", ylabel="μ = τ/p", title="stress ratio")
    axes[2].semilogx(strain, g["void_ratio"][:])
    axes[2].set(xlabel="shear strain γ", ylabel="e", title="void ratio")
    fig.tight_layout()
    fig.savefig(os.path.join(run, "series.png"), dpi=120)
    plt.close(fig)
    # with force chains: τ and its three parts, p' and r_c
    if "force_chain_shear_stress" in g and np.any(g["force_chain_shear_stress"][:] != 0):
        fig, axes = plt.subplots(1, 2, figsize=(10, 3.8))
        axes[0].semilogx(strain, g["shear_stress"][:], "g", label="τ total")
        axes[0].semilogx(strain, g["force_chain_shear_stress"][:], "k--", label="τ_FC")
        axes[0].semilogx(strain, g["collisional_shear_stress"][:], "r", label="τ_COL")
        axes[0].semilogx(strain, g["liquid_shear_stress"][:], "b", label="τ_L")
        axes[0].set_yscale("symlog", linthresh=1.0)
        axes[0].set(xlabel="shear strain γ", ylabel="τ [Pa]", title="shear stress and its parts")
        axes[0].legend(fontsize=8)
        axes[1].semilogx(strain, g["effective_pressure"][:] / 1e3, "k", label="p'")
        axes[1].semilogx(strain, g["yield_size"][:] / 1e3, "k:", label="r_c")
        axes[1].set(xlabel="shear strain γ", ylabel="[kPa]", title="skeleton: p' and r_c")
        axes[1].legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(run, "force_chains.png"), dpi=120)
        plt.close(fig)


def sweep_plots(run, h5):
    s = h5["steady"]
    I = s["inertial_number"][:]
    order = np.argsort(I)
    d = s.attrs["diameter"]
    gd = s["shear_rate"][:]
    T = s["granular_temperature"][:]
    wet = s.attrs["liquid_enabled"] > 0.5
    panels = 5 if wet else 3
    fig, axes = plt.subplots(1, panels, figsize=(4.2 * panels, 3.8))
    axes[0].semilogx(I[order], s["friction"][:][order], "o-")
    axes[0].set(xlabel="I", ylabel="μ", title="μ(I)")
    axes[1].semilogx(I[order], s["void_ratio"][:][order], "o-")
    axes[1].set(xlabel="I", ylabel="e", title="e(I)")
    axes[2].loglog(I[order], (T / (d * gd) ** 2)[order], "o-")
    axes[2].set(xlabel="I", ylabel="T/(d γ̇)²", title="scaled temperature")
    if wet:
        J = s["viscous_number"][:]
        K = s["unified_number"][:]
        oj, ok = np.argsort(J), np.argsort(K)
        axes[3].semilogx(J[oj], s["friction"][:][oj], "o-")
        axes[3].set(xlabel="J", ylabel="μ", title="μ(J)")
        axes[4].semilogx(K[ok], s["friction"][:][ok], "o-")
        axes[4].set(xlabel="K = J + αI²", ylabel="μ", title="μ(K)")
    fig.tight_layout()
    fig.savefig(os.path.join(run, "steady.png"), dpi=120)


def main():
    run = sys.argv[1]
    with h5py.File(os.path.join(run, "result.h5"), "r") as h5:
        if "series" in h5:
            series_plots(run, h5)
        if "steady" in h5 and len(h5["steady"]["friction"]) > 1:
            sweep_plots(run, h5)


if __name__ == "__main__":
    main()
