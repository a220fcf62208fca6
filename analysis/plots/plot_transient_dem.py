#!/usr/bin/env python3
"""PNG plots of `kind: dem` runs started from a prepared state (start.preparation;
docs/transient_dem.md): p'(gamma)/p0 and tau(gamma)/p0 with the band (lowest to highest seed)
and the seed mean, from /transient/group_G of result.h5 (dem_coupling/kind/transient.hpp); the
liquefaction threshold f p0 (attribute liquefaction_fraction) is drawn on the p' panel. With a
stop stage (/transient/group_G/stop) a third panel, T / flowing T after the stop (log-log); with
a drained stop (attribute normal_stress of the stop) a fourth, sigma_yy / sigma_n and phi. With a
step in the shear rate (attribute rate_step_strain) a second row: mu = tau / sigma_yy, phi and T
against gamma, the step marked.
Usage: plot_transient_dem.py RUN_DIR [RUN_DIR ...] [--out FILE.png]
One run: RUN_DIR/transient.png. Several (e.g. a loose and a dense packing): all on one figure,
written to --out (default: transient.png in the first RUN_DIR)."""
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from plot_axes import label_rate_step_axes  # noqa: E402


def groups(run_dir):
    with h5py.File(os.path.join(run_dir, "result.h5"), "r") as f:
        if "transient" not in f:
            return []
        out = []
        names = sorted(f["transient"].keys())
        for name in names:
            g = f["transient"][name]
            d = {k: np.asarray(g[k]) for k in g.keys() if isinstance(g[k], h5py.Dataset)}
            if "stop" in g:
                stop = g["stop"]
                d["stop"] = {k: np.asarray(stop[k]) for k in stop.keys()}
                d["flowing_T"] = float(g.attrs["mean_flowing_T"])
                if "normal_stress" in stop.attrs:
                    d["sigma_n"] = float(stop.attrs["normal_stress"])
            if "rate_step_strain" in g.attrs:
                d["step"] = float(g.attrs["rate_step_strain"])
            d["p0"] = float(g.attrs["mean_p0"])
            d["phi0"] = float(g.attrs["mean_phi0"])
            d["fraction"] = float(g.attrs["liquefaction_fraction"])
            d["seeds"] = int(g.attrs["seeds"])
            d["label"] = "{}{} (phi0 {:.3f}, {} seed{})".format(
                os.path.basename(os.path.normpath(run_dir)),
                " " + name if len(names) > 1 else "", d["phi0"], d["seeds"],
                "s" if d["seeds"] > 1 else "")
            out.append(d)
        return out


def main(argv):
    out = None
    if "--out" in argv:
        i = argv.index("--out")
        out = argv[i + 1]
        argv = argv[:i] + argv[i + 2:]
    runs = argv[1:]
    if not runs:
        sys.exit(__doc__)
    data = [g for r in runs for g in groups(r)]
    if not data:
        print("plot_transient_dem.py: no /transient group in " + ", ".join(runs))
        return
    stopped = any("stop" in d for d in data)
    drained = any("sigma_n" in d for d in data)
    stepped = any("step" in d for d in data)
    panels = 4 if drained else 3 if stopped else 2
    columns = max(panels, 3 if stepped else 0)
    fig, axes = plt.subplots(2 if stepped else 1, columns, figsize=(5.3 * columns + 0.4,
                                                                    4.2 * (2 if stepped else 1)),
                             squeeze=False)
    step_axes = axes[1] if stepped else []
    axes = axes[0]
    for ax in axes[panels:]:
        ax.axis("off")
    ax_p, ax_t = axes[0], axes[1]
    for k, d in enumerate(data):
        color = "C{}".format(k)
        s = d["strain"]
        for ax, name in ((ax_p, "mean_stress"), (ax_t, "shear_stress")):
            ax.fill_between(s, d[name + "_min"] / d["p0"], d[name + "_max"] / d["p0"],
                            color=color, alpha=0.25, lw=0)
            ax.plot(s, d[name + "_mean"] / d["p0"], color=color, lw=1.4, label=d["label"])
        ax_p.axhline(d["fraction"], color="k", ls=":", lw=1)
        if "step" in d:  # mu, phi, T across the step in the shear rate
            mu = d["shear_stress_mean"] / d["normal_stress_mean"]
            step_axes[0].plot(s, mu, color=color, lw=1.4)
            for ax, name in ((step_axes[1], "solid_fraction"),
                             (step_axes[2], "granular_temperature")):
                ax.fill_between(s, d[name + "_min"], d[name + "_max"], color=color, alpha=0.25,
                                lw=0)
                ax.plot(s, d[name + "_mean"], color=color, lw=1.4)
            for ax in step_axes:
                ax.axvline(d["step"], color="k", ls=":", lw=1)
        if "stop" in d:
            t = d["stop"]["time"]
            T = "granular_temperature"
            axes[2].fill_between(t, d["stop"][T + "_min"] / d["flowing_T"],
                                 d["stop"][T + "_max"] / d["flowing_T"], color=color, alpha=0.25,
                                 lw=0)
            axes[2].plot(t, d["stop"][T + "_mean"] / d["flowing_T"], color=color, lw=1.4)
        if "sigma_n" in d:
            axes[3].fill_between(t, d["stop"]["normal_stress_min"] / d["sigma_n"],
                                 d["stop"]["normal_stress_max"] / d["sigma_n"], color=color,
                                 alpha=0.25, lw=0)
            axes[3].plot(t, d["stop"]["normal_stress_mean"] / d["sigma_n"], color=color, lw=1.4)
            phi = axes[3].twinx()
            phi.plot(t, d["stop"]["solid_fraction_mean"], color=color, lw=1.0, ls="--")
            phi.set_ylabel("phi (dashed)")
    ax_p.set_yscale("log")
    ax_t.set_yscale("log")  # dense packings dilate: tau and p grow by decades
    ax_p.set_ylabel("p' / p0  (mean stress tr(sigma)/3)")
    ax_t.set_ylabel("tau / p0")
    for ax in (ax_p, ax_t):
        ax.set_xlabel("shear strain gamma")
        ax.grid(alpha=0.3)
    ax_p.text(0.98, 0.02, "dotted: liquefaction threshold", transform=ax_p.transAxes,
              ha="right", va="bottom", fontsize=8)
    ax_t.legend(fontsize=8)
    if stopped:
        axes[2].set_xscale("log")
        axes[2].set_yscale("log")
        axes[2].set_xlabel("time since the shear was stopped (s)")
        axes[2].set_ylabel("T / flowing T")
        axes[2].grid(alpha=0.3, which="both")
    if drained:
        axes[3].set_xlabel("time since the shear was stopped (s)")
        axes[3].set_ylabel("sigma_yy / sigma_n (solid)")
        axes[3].grid(alpha=0.3)
    label_rate_step_axes(step_axes, "mu = tau / sigma_yy (seed means)")
    fig.suptitle("shear from rest: seed mean and band (lowest to highest seed)")
    fig.tight_layout()
    target = out or os.path.join(runs[0], "transient.png")
    fig.savefig(target, dpi=120)
    print("wrote " + target)


if __name__ == "__main__":
    main(sys.argv)
