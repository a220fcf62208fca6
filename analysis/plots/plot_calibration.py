#!/usr/bin/env python3
"""PNG plots of a `kind: calibrate` run (analysis/calibration): the DEM rows with error bars
against the continuum steady simple shear before and after calibration (calibration.png), and the
normalised residuals of the fit (residuals.png).

The model is drawn as the smooth curves the C++ forward model wrote over the swept range of the
data's condition variable (result.h5 /curve/N, analysis/calibration/model_curves.hpp): against
the inertial number I at constant pressure (γ̇ swept), the solid fraction φ at constant volume,
the viscous number J for an immersed sweep of η0. Nothing of the model is computed here. A row
on no curve (a condition alone in its series) shows the model at its own conditions as a marker
(/prediction). One row of panels per abscissa, one panel per fitted observable its protocol
predicts (constant pressure: φ, μ, T*; constant volume: p*, μ, T*). An axis is logarithmic only
when its values span a decade.
Usage: plot_calibration.py RUN_DIR"""
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from plot_axes import spans_a_decade  # noqa: E402

LABELS = {
    "friction": "friction μ = τ/σ_yy [–]",
    "solid_fraction": "solid fraction φ [–]",
    "scaled_temperature": "scaled temperature T/(d γ̇)² [–]",
    "scaled_pressure": "scaled pressure σ_yy/(ρ_p d² γ̇²) [–]",
}
AXES = {
    "inertial_number": "inertial number I = γ̇ d/√(σ_yy/ρ_p) [–]",
    "solid_fraction": "imposed solid fraction φ [–]",
    "viscous_number": "viscous number J = η0 γ̇/σ_yy [–]",
}
# the observable each protocol imposes (/data/protocol: 0 constant pressure, 1 constant volume)
IMPOSED = {0: "scaled_pressure", 1: "solid_fraction"}
MODELS = (("uncalibrated", "b--", "continuum, starting parameters"),
          ("calibrated", "r-", "continuum, calibrated"))


def text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def point_axes(h5):
    """Per /data row: the abscissa its curve is drawn against, and its value there."""
    d = h5["data"]
    n = len(d["shear_rate"])
    protocol = d["protocol"][:] if "protocol" in d else np.zeros(n, dtype=int)
    member = d["curve"][:] if "curve" in d else np.full(n, -1)
    curves = h5["curve"] if "curve" in h5 else {}
    axis = []
    for i in range(n):
        if member[i] >= 0 and str(member[i]) in curves:
            axis.append(text(curves[str(member[i])].attrs["axis"]))
        else:
            axis.append("solid_fraction" if protocol[i] == 1 else "inertial_number")
    eta0 = d["liquid_viscosity"][:] if "liquid_viscosity" in d else np.full(n, np.nan)
    values = {"inertial_number": d["inertial_number"][:],
              "solid_fraction": d["solid_fraction"][:],
              "viscous_number": eta0 * d["shear_rate"][:] / d["normal_stress"][:]}
    x = np.array([values[a][i] for i, a in enumerate(axis)])
    return np.array(axis), x, protocol, member


def level_label(curve, count):
    """Which series a curve is, when a row of panels holds several."""
    if count < 2:
        return ""
    if "normal_stress" in curve:
        return f", σ_yy ≈ {np.median(curve['normal_stress'][:]):.3g} Pa"
    return f", γ̇ ≈ {np.median(curve['shear_rate'][:]):.3g} 1/s"


def draw_calibration(h5, run, fitted):
    d = h5["data"]
    axis, x, protocol, member = point_axes(h5)
    training = d["training"][:] > 0.5
    curves = h5["curve"] if "curve" in h5 else {}
    rows = [a for a in AXES if a in set(axis)]
    columns = {a: [n for n in LABELS if n in fitted and
                   any(IMPOSED[int(protocol[i])] != n for i in np.flatnonzero(axis == a))]
               for a in rows}
    width = max(len(c) for c in columns.values())
    fig, axes = plt.subplots(len(rows), width, figsize=(4.8 * width, 4.1 * len(rows)),
                             squeeze=False)
    for r, a in enumerate(rows):
        on_axis = axis == a
        in_row = [k for k in curves if text(curves[k].attrs["axis"]) == a]
        for c in range(len(columns[a]), width):
            axes[r][c].set_visible(False)
        for ax, name in zip(axes[r], columns[a]):
            y = d[name][:]
            err = d[name + "_fit_err"][:] if name + "_fit_err" in d else d[name + "_err"][:]
            tested = on_axis & np.isfinite(y) & np.array([IMPOSED[int(p)] != name
                                                          for p in protocol])
            xs, ys = [x[tested]], [y[tested]]
            for k in in_row:
                curve = curves[k]
                for group, style, label in MODELS:
                    cy = curve[group][name][:]
                    ax.plot(curve[a][:], cy, style, lw=1.5,
                            label=label + level_label(curve, len(in_row)))
                    xs.append(curve[a][:])
                    ys.append(cy)
            alone = tested & (member < 0)
            for group, style, label in MODELS:  # rows on no curve: the model at the row
                if np.any(alone):
                    p = h5["prediction"][group][name][:]
                    ax.plot(x[alone], p[alone], style[0] + "x", ms=7, ls="none",
                            label=label + " (at the row)")
                    ys.append(p[alone])
            fit = tested & training
            ax.errorbar(x[fit], y[fit], yerr=err[fit], fmt="ko", ms=4, capsize=2, zorder=3,
                        label="DEM, fitted")
            held = tested & ~training
            if np.any(held):
                ax.errorbar(x[held], y[held], yerr=err[held], fmt="o", mfc="white", mec="k",
                            ecolor="k", ms=5, capsize=2, zorder=3, label="DEM, held out")
            if spans_a_decade(xs):
                ax.set_xscale("log")
            if spans_a_decade(ys):
                ax.set_yscale("log")
            ax.set(xlabel=AXES[a], ylabel=LABELS[name])
        axes[r][0].legend(fontsize=7)
    fig.suptitle("calibration: " + text(h5["fit"].attrs["parameters"]))
    fig.tight_layout()
    fig.savefig(os.path.join(run, "calibration.png"), dpi=120)
    plt.close(fig)


def draw_residuals(h5, run, fitted):
    axis, x, _, _ = point_axes(h5)
    training = h5["data"]["training"][:] > 0.5
    r = h5["fit"]["normalised_residuals"][:]
    if r.ndim == 1:
        r = r[:, None]
    if len(set(axis[training])) == 1:
        xt, label = x[training], AXES[axis[training][0]]
    else:  # several abscissae: the training rows in order
        xt, label = np.arange(np.count_nonzero(training)), "training row"
    fig, ax = plt.subplots(figsize=(6, 3.8))
    for k in range(r.shape[1]):
        ax.plot(xt, r[:, k], "o", label=fitted[k] if k < len(fitted) else str(k))
    ax.axhline(0, color="k", lw=0.8)
    for s in (-2, 2):
        ax.axhline(s, color="grey", ls=":", lw=0.8)
    if spans_a_decade([xt]):
        ax.set_xscale("log")
    ax.set(xlabel=label, ylabel="normalised residual (y − f)/σ [–]",
           title=f"normalised residuals, χ²_red = {h5['fit'].attrs['chi2_red']:.3g}")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(run, "residuals.png"), dpi=120)
    plt.close(fig)


def main(run):
    with h5py.File(os.path.join(run, "result.h5"), "r") as h5:
        fitted = text(h5["fit"].attrs["observables"]).split()
        draw_calibration(h5, run, fitted)
        draw_residuals(h5, run, fitted)


if __name__ == "__main__":
    main(sys.argv[1])
