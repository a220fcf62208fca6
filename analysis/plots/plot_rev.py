#!/usr/bin/env python3
"""PNG plots of a `kind: rev` run: time series of one condition, or the steady tables of a sweep
(mu(I), e(I), T/(d gamma_dot)^2 and, with liquid, mu(J), mu(K)). Usage: plot_rev.py RUN_DIR"""
import os
import sys

import h5py
import matplotlib

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))
import granflow_results as gr  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from plot_axes import spans_a_decade  # noqa: E402


def series_plots(run, h5):
    g = h5["series"]
    strain = g["strain"][:]
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.8))
    T = g["granular_temperature"][:]
    axes[0].semilogx(strain, T)
    # log in T only where it spans a decade or more (else log ticks are unreadable)
    if spans_a_decade([T]):
        axes[0].set_yscale("log")
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
        axes[1].semilogx(strain, g["locus_size"][:] / 1e3, "k:", label="r_c")
        axes[1].set(xlabel="shear strain γ", ylabel="[kPa]", title="skeleton: p' and r_c")
        axes[1].legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(run, "force_chains.png"), dpi=120)
        plt.close(fig)


def sweep_plots(run):
    """The steady table through the reader (analysis/python/granflow_results.py): the axes are
    labelled with the descriptions and units the file carries."""
    s = gr.open_run(run).steady()
    units, text = s.attrs["units"], s.attrs["descriptions"]

    def label(name):
        unit = units.get(name, "1")
        return text.get(name, name).split(",")[0] + ("" if unit == "1" else f" [{unit}]")

    s = s.sort_values("inertial_number")
    wet = int(s.attrs["attributes"].get("liquid_enabled", 0)) == 1
    panels = [("inertial_number", "friction", "semilogx"), ("inertial_number", "void_ratio", "semilogx"),
              ("inertial_number", "scaled_temperature", "loglog")]
    if wet:
        panels += [("viscous_number", "friction", "semilogx"), ("mixed_number", "friction", "semilogx")]
    fig, axes = plt.subplots(1, len(panels), figsize=(4.2 * len(panels), 3.8))
    for ax, (x, y, style) in zip(axes, panels):
        t = s.sort_values(x)
        getattr(ax, style)(t[x], t[y], "o-")
        ax.set(xlabel=label(x), ylabel=label(y))
        ax.title.set_text(f"{y} against {x}")
        ax.title.set_fontsize(9)
        ax.xaxis.label.set_fontsize(8)
        ax.yaxis.label.set_fontsize(8)
    fig.tight_layout()
    fig.savefig(os.path.join(run, "steady.png"), dpi=120)
    plt.close(fig)


def main():
    run = sys.argv[1]
    with h5py.File(os.path.join(run, "result.h5"), "r") as h5:
        if "series" in h5:
            series_plots(run, h5)
        several = "steady" in h5 and len(h5["steady"]["friction"]) > 1
    if several:
        sweep_plots(run)


if __name__ == "__main__":
    main()
