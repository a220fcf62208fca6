#!/usr/bin/env python3
"""PNG plot of a `kind: transient_pair` run (docs/transient_pairs.md): the undrained shear from
rest in the DEM (seed mean and band, lowest to highest seed: /transient_pair/group_G/dem)
and in the continuum (the REV's steps, the same group), p'(gamma)/p0 and tau(gamma)/p0, one colour per condition, the continuum with
fitted force-chain parameters (calibrate section) dotted; the liquefaction threshold f p0 dotted
black. With a stop stage (stop.duration), a third panel: T / flowing T against the time since
the shear was stopped (log-log), DEM band and continuum; with a drained stop
(stop.drainage_length), a fourth: sigma_yy / sigma_n against that time (the excess pore pressure
is 1 - it). With a step in the shear rate (rate_step), a second row: mu = tau / sigma_yy, phi and
T against gamma, the step marked.
Usage: plot_transient_pair.py RUN_DIR  ->  RUN_DIR/transient_pair.png"""
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from plot_axes import label_rate_step_axes  # noqa: E402


def main(run):
    with h5py.File(os.path.join(run, "result.h5"), "r") as f_cont:
        names = sorted(f_cont["transient_pair"].keys(), key=lambda n: int(n.split("_")[-1]))
        stopped = any("stop" in f_cont["transient_pair"][n]["dem"] for n in names)
        drained = any("stop_normal_stress" in f_cont["transient_pair"][n].attrs for n in names)
        stepped = any("rate_step_strain" in f_cont["transient_pair"][n].attrs for n in names)
        drained_shear = any("drainage_length" in f_cont["transient_pair"][n].attrs for n in names)
        damped_shear = any("height_resistance" in f_cont["transient_pair"][n].attrs for n in names)
        panels = 4 if drained else 3 if stopped else 2
        rows = 2 if stepped else 1
        columns = max(panels, 3 if stepped else 0)
        fig, axes = plt.subplots(rows, columns, figsize=(5.3 * columns + 0.4, 4.2 * rows),
                                 squeeze=False)
        step_axes = axes[1] if stepped else []
        axes = axes[0]
        ax_p, ax_t = axes[0], axes[1]
        for k, name in enumerate(names):
            cont = f_cont["transient_pair"][name]
            p0 = float(cont.attrs["p0"])
            color = "C{}".format(k)
            label = "phi0 {:.3f}, gamma_dot {:g} 1/s".format(float(cont.attrs["phi0"]),
                                                              float(cont.attrs["shear_rate"]))
            dem = cont["dem"]
            s_dem = np.asarray(dem["strain"])
            for ax, q in ((ax_p, "mean_stress"), (ax_t, "shear_stress")):
                ax.fill_between(s_dem, np.asarray(dem[q + "_min"]) / p0,
                                np.asarray(dem[q + "_max"]) / p0, color=color, alpha=0.2, lw=0)
                ax.plot(s_dem, np.asarray(dem[q + "_mean"]) / p0, color=color, lw=1.2,
                        label="DEM " + label)
                ax.plot(np.asarray(cont["strain"]), np.asarray(cont[q]) / p0, color=color,
                        lw=1.6, ls="--", label="continuum " + label)
                if q + "_cal" in cont:  # the continuum with the fitted force-chain parameters
                    ax.plot(np.asarray(cont["strain_cal"]), np.asarray(cont[q + "_cal"]) / p0,
                            color=color, lw=1.6, ls=":", label="calibrated continuum " + label)
            ax_p.axhline(float(cont.attrs["liquefaction_fraction"]), color="k", ls=":", lw=1)
            if "rate_step_strain" in cont.attrs:  # mu, phi, T across the step in the rate
                dem_q = {"mu": np.asarray(dem["shear_stress_mean"]) /
                         np.asarray(dem["normal_stress_mean"]),
                         "phi": np.asarray(dem["solid_fraction_mean"]),
                         "T": np.asarray(dem["granular_temperature_mean"])}
                for ax, q, band in ((step_axes[1], "phi", "solid_fraction"),
                                    (step_axes[2], "T", "granular_temperature")):
                    ax.fill_between(s_dem, np.asarray(dem[band + "_min"]),
                                    np.asarray(dem[band + "_max"]), color=color, alpha=0.2, lw=0)
                for ax, q in zip(step_axes, ("mu", "phi", "T")):
                    ax.plot(s_dem, dem_q[q], color=color, lw=1.2)
                    ax.axvline(float(cont.attrs["rate_step_strain"]), color="k", ls=":", lw=1)
                for suffix, ls in (("", "--"), ("_cal", ":")):
                    if "strain" + suffix not in cont:
                        continue
                    s_c = np.asarray(cont["strain" + suffix])
                    cont_q = (np.asarray(cont["shear_stress" + suffix]) /
                              np.asarray(cont["normal_stress" + suffix]),
                              np.asarray(cont["solid_fraction" + suffix]),
                              np.asarray(cont["granular_temperature" + suffix]))
                    for ax, y in zip(step_axes, cont_q):
                        ax.plot(s_c, y, color=color, lw=1.6, ls=ls)
            if "stop" in dem:  # T / flowing T after the stop, each side scaled by its own
                ax_s = axes[2]
                t_dem = np.asarray(dem["stop/time"])
                flow = float(cont.attrs["dem_flowing_T"])
                ax_s.fill_between(t_dem, np.asarray(dem["stop/granular_temperature_min"]) / flow,
                                  np.asarray(dem["stop/granular_temperature_max"]) / flow,
                                  color=color, alpha=0.2, lw=0)
                ax_s.plot(t_dem, np.asarray(dem["stop/granular_temperature_mean"]) / flow,
                          color=color, lw=1.2, label="DEM " + label)
                for suffix, ls in (("", "--"), ("_cal", ":")):
                    # (a stop that stopped on a numerical failure has its rows, no metrics)
                    if "stop/time" + suffix in cont and \
                            "cont" + suffix + "_flowing_T" in cont.attrs:
                        ax_s.plot(np.asarray(cont["stop/time" + suffix]),
                                  np.asarray(cont["stop/granular_temperature" + suffix]) /
                                  float(cont.attrs["cont" + suffix + "_flowing_T"]),
                                  color=color, lw=1.6, ls=ls)
            if "stop_normal_stress" in cont.attrs:  # drained: the grains' share of sigma_n
                ax_d = axes[3]
                sigma_n = float(cont.attrs["stop_normal_stress"])
                ax_d.fill_between(t_dem, np.asarray(dem["stop/normal_stress_min"]) / sigma_n,
                                  np.asarray(dem["stop/normal_stress_max"]) / sigma_n,
                                  color=color, alpha=0.2, lw=0)
                ax_d.plot(t_dem, np.asarray(dem["stop/normal_stress_mean"]) / sigma_n,
                          color=color, lw=1.2)
                for suffix, ls in (("", "--"), ("_cal", ":")):
                    if "stop/normal_stress" + suffix in cont:
                        ax_d.plot(np.asarray(cont["stop/time" + suffix]),
                                  np.asarray(cont["stop/normal_stress" + suffix]) / sigma_n,
                                  color=color, lw=1.6, ls=ls)
    ax_p.set_yscale("log")
    ax_p.set_ylabel("p' / p0   (mean stress)")
    ax_t.set_ylabel("tau / p0")
    for ax in (ax_p, ax_t):
        ax.set_xlabel("shear strain gamma")
        ax.grid(alpha=0.3)
    ax_t.legend(fontsize=7)
    if stopped:
        ax_s = axes[2]
        ax_s.set_xscale("log")
        ax_s.set_yscale("log")
        ax_s.set_xlabel("time since the shear was stopped (s)")
        ax_s.set_ylabel("T / flowing T")
        ax_s.grid(alpha=0.3, which="both")
    if drained:
        ax_d = axes[3]
        ax_d.set_xlabel("time since the shear was stopped (s)")
        ax_d.set_ylabel("sigma_yy / sigma_n   (drained: 1 - u / sigma_n)")
        ax_d.grid(alpha=0.3)
    label_rate_step_axes(step_axes)
    for ax in axes[panels:]:
        ax.axis("off")
    ax_p.text(0.98, 0.02, "band: lowest to highest DEM seed; dotted: liquefaction threshold",
              transform=ax_p.transAxes, ha="right", va="bottom", fontsize=7)
    fig.suptitle("{} shear from rest: DEM (solid, band), continuum (dashed), calibrated (dotted)"
                 .format("drained" if drained_shear else
                         "constant normal stress" if damped_shear else "undrained"))
    fig.tight_layout()
    target = os.path.join(run, "transient_pair.png")
    fig.savefig(target, dpi=120)
    print("wrote " + target)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
