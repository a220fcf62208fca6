#!/usr/bin/env python3
"""closures.png of a `granflow study closures` directory (analysis/calibration/closure_study.cpp):
the DEM points with their error bars (fitted: filled, held out: open) against the smooth steady
predictions of the best three closure combinations (ranked by AIC): at constant pressure over I at
the mean DEM σ_yy, panels μ, φ and T/(dγ̇)²; at constant volume over the imposed φ at the mean
DEM γ̇, panels μ, σ_yy/(ρ_p d²γ̇²) and T/(dγ̇)². Reads only STUDY_DIR/closures.h5, written by the
C++ (its /curves attribute `protocol` says which).
Usage: plot_closures.py STUDY_DIR"""
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

PANELS = {
    "constant_pressure": [
        ("friction", "μ = τ/σ_yy"),
        ("solid_fraction", "φ"),
        ("scaled_temperature", "T / (d γ̇)²"),
    ],
    "constant_volume": [
        ("friction", "μ = τ/σ_yy"),
        ("scaled_pressure", "σ_yy / (ρ_p d² γ̇²)"),
        ("scaled_temperature", "T / (d γ̇)²"),
    ],
}
LOG_Y = {"scaled_temperature", "scaled_pressure"}
STYLES = ["r-", "b--", "g-."]


def text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def main(study):
    with h5py.File(os.path.join(study, "closures.h5"), "r") as h5:
        d = h5["data"]
        train = d["training"][:] > 0.5
        curves = h5["curves"]
        protocol = text(curves.attrs.get("protocol", "constant_pressure"))
        if protocol == "constant_volume":
            x, grid = d["solid_fraction_imposed"][:], curves["solid_fraction"][:]
            xlabel, log_x = "solid fraction φ (imposed)", False
            title = "curves at γ̇ = {:.4g} 1/s, constant volume".format(
                float(curves.attrs["shear_rate"]))
        else:
            x, grid = d["inertial_number"][:], curves["inertial_number"][:]
            xlabel, log_x = "inertial number I", True
            title = "curves at σ_yy = {:.4g} Pa".format(float(curves.attrs["normal_stress"]))
        count = int(curves.attrs["count"])
        fig, axes = plt.subplots(1, 3, figsize=(15, 4.6))
        for ax, (name, label) in zip(axes, PANELS[protocol]):
            y, err = d[name][:], d[name + "_err"][:]
            ax.errorbar(x[train], y[train], yerr=err[train], fmt="ko", ms=4, capsize=2,
                        label="DEM (fitted)")
            if np.any(~train):
                ax.errorbar(x[~train], y[~train], yerr=err[~train], fmt="o", mfc="white",
                            mec="k", ecolor="k", ms=5, capsize=2, label="DEM (held out)")
            for rank in range(1, count + 1):
                g = curves[str(rank)]
                ax.plot(grid, g[name][:], STYLES[(rank - 1) % len(STYLES)],
                        label="rank {}: {} (AIC {:.4g}, χ²_red {:.3g})".format(
                            int(g.attrs["rank"]), text(g.attrs["label"]), float(g.attrs["aic"]),
                            float(g.attrs["chi2_red"])))
            if log_x:
                ax.set_xscale("log")
            if name in LOG_Y:
                ax.set_yscale("log")
            ax.set_xlabel(xlabel)
            ax.set_ylabel(label)
            ax.grid(True, which="both", alpha=0.3)
        fig.suptitle("Best closure combinations against the DEM ({})".format(title))
        handles, labels = axes[0].get_legend_handles_labels()
        fig.legend(handles, labels, loc="lower center", ncol=2, fontsize=8, frameon=False)
        fig.tight_layout(rect=(0, 0.16, 1, 0.95))
        out = os.path.join(study, "closures.png")
        fig.savefig(out, dpi=120)
        print(out)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
