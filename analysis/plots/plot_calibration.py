#!/usr/bin/env python3
"""PNG plots of a `kind: calibrate` run (analysis/calibration): DEM data with error bars against
the continuum steady simple shear before and after calibration, per fitted observable vs I
(calibration.png), and the normalised residuals of the fit (residuals.png). A row shows the
observables its protocol predicts (constant pressure: φ, μ, T*; constant volume: p*, μ, T*).
Usage: plot_calibration.py RUN_DIR"""
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

LABELS = {
    "friction": "μ = τ/σ_yy",
    "solid_fraction": "φ",
    "scaled_temperature": "T / (d γ̇)²",
    "scaled_pressure": "σ_yy / (ρ_p d² γ̇²)",
}
# the observable each protocol imposes (/data/protocol: 0 constant pressure, 1 constant volume)
IMPOSED = {0: "scaled_pressure", 1: "solid_fraction"}


def main(run):
    with h5py.File(os.path.join(run, "result.h5"), "r") as h5:
        d = h5["data"]
        I = d["inertial_number"][:]
        protocol = d["protocol"][:] if "protocol" in d else np.zeros(len(I))
        attr = h5["fit"].attrs["observables"]
        fitted = (attr.decode() if isinstance(attr, bytes) else str(attr)).split()
        names = [n for n in LABELS if n in fitted] or list(LABELS)[:3]
        fig, axes = plt.subplots(1, len(names), figsize=(4.7 * len(names), 4), squeeze=False)
        axes = axes[0]
        for ax, name in zip(axes, names):
            tested = np.array([IMPOSED[int(k)] != name for k in protocol]) & np.isfinite(d[name][:])
            train = (d["training"][:] > 0.5) & tested
            held = (d["training"][:] <= 0.5) & tested
            y = d[name][:]
            err = d[name + "_fit_err"][:] if name + "_fit_err" in d else d[name + "_err"][:]
            ax.errorbar(I[train], y[train], yerr=err[train], fmt="ko", ms=4, capsize=2,
                        label="DEM (fitted)")
            if np.any(held):
                ax.errorbar(I[held], y[held], yerr=err[held], fmt="o", mfc="white",
                            mec="k", ecolor="k", ms=5, capsize=2, label="DEM (held out)")
            order = np.argsort(I)
            order = order[tested[order]]
            for group, style in (("uncalibrated", "b--"), ("calibrated", "r-")):
                pred = h5["prediction"][group][name][:]
                ax.plot(I[order], pred[order], style, marker=".", label=f"continuum, {group}")
            ax.set_xscale("log")
            if name in ("scaled_temperature", "scaled_pressure"):
                ax.set_yscale("log")
            ax.set(xlabel="inertial number I (DEM)", ylabel=LABELS[name])
        axes[0].legend(fontsize=8)
        fig.suptitle("calibration: " + h5["fit"].attrs["parameters"].decode()
                     if isinstance(h5["fit"].attrs["parameters"], bytes)
                     else "calibration: " + str(h5["fit"].attrs["parameters"]))
        fig.tight_layout()
        fig.savefig(os.path.join(run, "calibration.png"), dpi=120)
        plt.close(fig)

        r = h5["fit"]["normalised_residuals"][:]
        if r.ndim == 1:
            r = r[:, None]
        obs = fitted
        fig, ax = plt.subplots(figsize=(6, 3.8))
        training = d["training"][:] > 0.5
        for k in range(r.shape[1]):
            ax.plot(I[training], r[:, k], "o", label=obs[k] if k < len(obs) else str(k))
        ax.axhline(0, color="k", lw=0.8)
        for s in (-2, 2):
            ax.axhline(s, color="grey", ls=":", lw=0.8)
        ax.set_xscale("log")
        ax.set(xlabel="inertial number I (DEM)", ylabel="(y − f)/σ",
               title=f"normalised residuals, χ²_red = {h5['fit'].attrs['chi2_red']:.3g}")
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(run, "residuals.png"), dpi=120)
        plt.close(fig)


if __name__ == "__main__":
    main(sys.argv[1])
