#!/usr/bin/env python3
"""PNG plots of `kind: dem` runs started from a prepared state (start.preparation;
docs/transient_dem.md): p'(gamma)/p0 and tau(gamma)/p0 with the band (lowest to highest seed)
and the seed mean, from /transient/group_G of result.h5 (dem_coupling/kind/transient.hpp); the
liquefaction threshold f p0 (attribute liquefaction_fraction) is drawn on the p' panel.
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


def groups(run_dir):
    with h5py.File(os.path.join(run_dir, "result.h5"), "r") as f:
        if "transient" not in f:
            return []
        out = []
        names = sorted(f["transient"].keys())
        for name in names:
            g = f["transient"][name]
            d = {k: np.asarray(g[k]) for k in g.keys()}
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
    fig, (ax_p, ax_t) = plt.subplots(1, 2, figsize=(11, 4.2))
    for k, d in enumerate(data):
        color = "C{}".format(k)
        s = d["strain"]
        for ax, name in ((ax_p, "mean_stress"), (ax_t, "shear_stress")):
            ax.fill_between(s, d[name + "_min"] / d["p0"], d[name + "_max"] / d["p0"],
                            color=color, alpha=0.25, lw=0)
            ax.plot(s, d[name + "_mean"] / d["p0"], color=color, lw=1.4, label=d["label"])
        ax_p.axhline(d["fraction"], color="k", ls=":", lw=1)
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
    fig.suptitle("constant-volume shear from rest: seed mean and band (lowest to highest seed)")
    fig.tight_layout()
    target = out or os.path.join(runs[0], "transient.png")
    fig.savefig(target, dpi=120)
    print("wrote " + target)


if __name__ == "__main__":
    main(sys.argv)
