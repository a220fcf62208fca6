#!/usr/bin/env python3
"""PNG plots of a `kind: pair` run (analysis/pair): DEM points (± error) against the continuum
models drawn as smooth curves over I (/pair/curve: the case's model, kinetic theory alone and,
when the case calibrates, the calibrated model) for μ, φ and T (pair.png); the share of τ carried
by the force chains (pair_shares.png); immersed pairs over η0 also against J (pair_J.png,
/pair/curve_J); the relative errors of μ, e, T per point (pair_errors.png).
Usage: plot_pair.py RUN_DIR"""
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402
import numpy as np  # noqa: E402
from plot_axes import spans_a_decade  # noqa: E402

REGIMES = {0: "quasi-static", 1: "dense inertial", 2: "collisional", 3: "viscous"}


def scale_axes(ax):
    """Log x and y axes where the drawn data span a decade, linear otherwise."""
    xs = [line.get_xdata() for line in ax.get_lines()]
    ys = [line.get_ydata() for line in ax.get_lines()]
    if xs and spans_a_decade(xs):
        ax.set_xscale("log")
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())  # narrow ranges
    if ys and spans_a_decade(ys):
        ax.set_yscale("log")


def main(run):
    with h5py.File(os.path.join(run, "result.h5"), "r") as h5:
        g = h5["pair"]
        I = g["inertial_number_dem"][:]
        gd = g["shear_rate"][:]
        order = np.argsort(I)
        fig, axes = plt.subplots(1, 3, figsize=(14, 4))
        panels = [("friction", "μ = τ/σ_yy"), ("solid_fraction", "φ"),
                  ("granular_temperature", "T [m²/s²]")]
        for ax, (name, label) in zip(axes, panels):
            y = g[name + "_dem"][:]
            err = g[name + "_dem_err"][:]
            ax.errorbar(I, y, yerr=err, fmt="ko", capsize=2, label="DEM (LIGGGHTS)", zorder=3)
            if "curve" in g:
                c = g["curve"]
                Ic = c["inertial_number"][:]
                styles = [("model", "r-", "continuum (case's model)"),
                          ("kt", "b--", "kinetic theory alone"),
                          ("cal", "g-", "continuum, calibrated")]
                for tag, style, text in styles:
                    if name + "_" + tag in c:
                        ax.plot(Ic, c[name + "_" + tag][:], style, lw=1.5, label=text)
            else:
                ax.plot(I[order], g[name + "_cont"][:][order], "r-", marker="s", ms=4,
                        label="continuum (steady REV)")
            scale_axes(ax)
            ax.set(xlabel="inertial number I", ylabel=label)
        axes[0].legend(fontsize=8)
        for i in range(len(I)):
            axes[0].annotate(REGIMES.get(int(g["regime"][i]), "?"), (I[i], g["friction_dem"][i]),
                             fontsize=6, xytext=(3, 3), textcoords="offset points")
        fig.suptitle(f"DEM vs continuum, {len(I)} points (γ̇ = {', '.join(f'{v:g}' for v in gd)} 1/s)")
        fig.tight_layout()
        fig.savefig(os.path.join(run, "pair.png"), dpi=120)
        plt.close(fig)

        if "curve_J" in g:  # immersed pair over η0: μ, φ, T against J, one curve per σ_yy level
            J = g["viscous_number_dem"][:]
            fig, axes = plt.subplots(1, 3, figsize=(14, 4))
            for ax, (name, label) in zip(axes, panels):
                ax.errorbar(J, g[name + "_dem"][:], yerr=g[name + "_dem_err"][:], fmt="ko",
                            capsize=2, label="DEM (LIGGGHTS)", zorder=3)
                for level in sorted(g["curve_J"].keys(), key=int):
                    c = g["curve_J"][level]
                    sigma = c.attrs.get("normal_stress", float("nan"))
                    for tag, style, text in (("model", "r-", "continuum"),
                                             ("kt", "b--", "kinetic theory alone"),
                                             ("cal", "g-", "calibrated")):
                        if name + "_" + tag in c:
                            ax.plot(c["viscous_number"][:], c[name + "_" + tag][:], style, lw=1.2,
                                    label=f"{text}, σ_yy = {sigma:.3g} Pa")
                scale_axes(ax)
                ax.set(xlabel="viscous number J = η0 γ̇ / σ_yy", ylabel=label)
            axes[0].legend(fontsize=6)
            fig.suptitle("immersed: DEM vs continuum over the viscous number")
            fig.tight_layout()
            fig.savefig(os.path.join(run, "pair_J.png"), dpi=120)
            plt.close(fig)

        if "curve" in g and "share_tau_fc_model" in g["curve"]:
            c = g["curve"]
            fig, ax = plt.subplots(figsize=(6, 3.8))
            ax.plot(c["inertial_number"][:], c["share_tau_fc_model"][:], "r-", label="force chains τ_FC/τ")
            ax.plot(c["inertial_number"][:], 1 - c["share_tau_fc_model"][:], "b-",
                    label="collisions + liquid (τ_COL + τ_L)/τ")
            if "share_tau_fc_cal" in c:
                ax.plot(c["inertial_number"][:], c["share_tau_fc_cal"][:], "g--", label="force chains, calibrated")
            if spans_a_decade([c["inertial_number"][:]]):
                ax.set_xscale("log")
            ax.set(xlabel="inertial number I", ylabel="share of τ", ylim=(-0.02, 1.02),
                   title="who carries the shear stress (continuum)")
            ax.legend(fontsize=8)
            fig.tight_layout()
            fig.savefig(os.path.join(run, "pair_shares.png"), dpi=120)
            plt.close(fig)

        fig, ax = plt.subplots(figsize=(6, 3.8))
        for name, style, label in (("friction", "o-", "μ"), ("void_ratio", "s-", "e"),
                                   ("granular_temperature", "^-", "T")):
            ax.plot(I[order], 100 * g[name + "_rel_err"][:][order], style, label=label)
        ax.axhline(0, color="k", lw=0.8)
        if spans_a_decade([I]):
            ax.set_xscale("log")
        ax.set(xlabel="inertial number I", ylabel="continuum / DEM − 1 [%]",
               title="relative difference, point by point")
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(run, "pair_errors.png"), dpi=120)
        plt.close(fig)


if __name__ == "__main__":
    main(sys.argv[1])
