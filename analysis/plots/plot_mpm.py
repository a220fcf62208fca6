#!/usr/bin/env python3
"""PNG plots of a `kind: mpm` run: Terzaghi isochrones and settlement, Couette v_theta(r), or the
elastic column's sigma_yy(y) and base stress. Usage: plot_mpm.py RUN_DIR"""
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def terzaghi(run, h5):
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    p0 = h5["series"].attrs["p0"]
    for key in sorted(h5["isochrones"].keys(), key=int):
        g = h5["isochrones"][key]
        depth, p, pe = g["depth"][:], g["pressure"][:], g["pressure_exact"][:]
        order = np.argsort(depth)
        tv = g.attrs["time_factor"]
        line, = axes[0].plot(pe[order] / p0, depth[order], "-", label=f"T_v = {tv:g} exact")
        axes[0].plot(p[order] / p0, depth[order], ".", color=line.get_color(), ms=3,
                     label=f"T_v = {tv:g} MPM")
    axes[0].invert_yaxis()
    axes[0].set(xlabel="p / p0", ylabel="depth [m]", title="pore pressure isochrones")
    axes[0].legend(fontsize=7)
    s = h5["series"]
    axes[1].plot(s["time"][:], 1e3 * s["settlement_exact"][:], "-", label="Terzaghi")
    axes[1].plot(s["time"][:], 1e3 * s["settlement"][:], "--", label="MPM")
    axes[1].set(xlabel="t [s]", ylabel="settlement [mm]", title="settlement of the top")
    axes[1].legend()
    fig.tight_layout()
    fig.savefig(os.path.join(run, "terzaghi.png"), dpi=120)


def couette(run, h5):
    g = h5["profile"]
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    ax.plot(g["radius"][:], g["velocity_exact"][:], "-", label="A r + B/r")
    ax.plot(g["radius"][:], g["velocity"][:], "o", ms=4, label="MPM (grid, averaged)")
    ax.set(xlabel="r [m]", ylabel="v_θ [m/s]", title="Couette flow")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(run, "couette.png"), dpi=120)


def column(run, h5):
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    g = h5["profile"]
    y0 = g["y0"][:]
    order = np.argsort(y0)
    axes[0].plot(-g["syy_exact"][:][order] / 1e3, y0[order], "-", label="ρ g (H - y)")
    axes[0].plot(-g["syy"][:][order] / 1e3, y0[order], ".", ms=3, label="MPM points")
    axes[0].set(xlabel="-σ_yy [kPa]", ylabel="y0 [m]", title="vertical stress at rest")
    axes[0].legend()
    s = h5["series"]
    axes[1].plot(s["time"][:], -s["base_stress"][:] / 1e3)
    axes[1].set(xlabel="t [s]", ylabel="-σ_yy bottom row [kPa]", title="base stress")
    fig.tight_layout()
    fig.savefig(os.path.join(run, "column.png"), dpi=120)


def main():
    run = sys.argv[1]
    with h5py.File(os.path.join(run, "result.h5"), "r") as h5:
        if "isochrones" in h5:
            terzaghi(run, h5)
        elif "profile" in h5 and "radius" in h5["profile"]:
            couette(run, h5)
        elif "profile" in h5:
            column(run, h5)


if __name__ == "__main__":
    main()
