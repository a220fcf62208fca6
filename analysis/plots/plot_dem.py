#!/usr/bin/env python3
"""PNG plots of a `kind: dem` run (result.h5, docs/dem_dataset.md).
Every point: series_N.png (mu, sigma_yy, phi, T against strain, steady start marked) and
profile_N.png (steady mean velocity profile against the imposed line).
Sweeps: mu_I.png, phi_I.png, T_I.png with the mu(I) law of docs/dem_dataset.md overlaid:
  mu(I) = mu_s + (mu_2 - mu_s) / (I_0 / I + 1)  (GDR MiDi 2004; Jop et al. 2006:
  mu_s = 0.38, mu_2 = 0.64, I_0 = 0.28), frictionless mu_s ~ 0.10 (Peyneau & Roux 2008),
  critical fractions nu_c ~ 0.587 (mu_p = 0.5) and 0.639 (frictionless) (Chialvo et al. 2012).
Immersed sweeps (liquid.enabled; /steady/viscous_number present): mu_J.png, phi_J.png, mu_K.png,
mu_phi_wet_I.png, stress_parts.png, with Boyer et al. (2011) (docs/dem_dataset.md):
  mu(J) = mu_1 + (mu_2 - mu_1)/(1 + J_0/J) + J + (5/2) nu_m J^(1/2),  phi(J) = nu_m/(1 + J^(1/2)),
  mu_1 = 0.32, mu_2 = 0.7, J_0 = 0.005, nu_m = 0.585; against K = J + alpha I^2 the same law in K
  (Trulsson et al. 2012 form), alpha = fit.alpha of summary.json if present, else the case's.
Fits of the run (/fits of result.h5, dem_coupling/kind/dem_fits.hpp; rewritten by `granflow
report`): the fitted mu(I) and phi(I) per friction on mu_I.png and phi_I.png (the law of attribute
"law": GDR MiDi mu(I) with phi_c - a I, or Peyneau & Roux 2008 for frictionless spheres,
mu_0 + c I^alpha and phi_RCP - b I^beta) with the published DEM values (mu_p = 0.5: mu_s 0.35-0.38, phi_c 0.587, Chialvo et al. 2012; frictionless:
mu_s 0.10, phi_c 0.639, Peyneau & Roux 2008); wet: the free mu(K) fit on mu_K.png and
boyer_split.png (tau_contact/sigma_yy against Boyer's contact part mu_c(J), tau_lub/sigma_yy
against the hydrodynamic part mu_h(J) = J + 2.5 nu_m J^(1/2)).
Usage: plot_dem.py RUN_DIR"""
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

MU_S, MU_2, I_0 = 0.38, 0.64, 0.28
BOYER_MU_1, BOYER_MU_2, BOYER_J_0, BOYER_NU_M = 0.32, 0.7, 0.005, 0.585


def boyer_mu(J):
    return (BOYER_MU_1 + (BOYER_MU_2 - BOYER_MU_1) / (1.0 + BOYER_J_0 / J) + J
            + 2.5 * BOYER_NU_M * np.sqrt(J))


def boyer_phi(J):
    return BOYER_NU_M / (1.0 + np.sqrt(J))


def mu_of_I(I, mu_s=MU_S, mu_2=MU_2, i0=I_0):
    return mu_s + (mu_2 - mu_s) / (i0 / I + 1.0)


def boyer_mu_c(J):
    return BOYER_MU_1 + (BOYER_MU_2 - BOYER_MU_1) / (1.0 + BOYER_J_0 / J)


def boyer_mu_h(J):
    return J + 2.5 * BOYER_NU_M * np.sqrt(J)


# Published DEM values (docs/dem_dataset.md): (mu_s low, mu_s high, phi_c, source).
PUBLISHED = {0.5: (0.35, 0.38, 0.587, "Chialvo 2012"), 0.0: (0.10, 0.10, 0.639, "Peyneau & Roux 2008")}


def friction_fits(h5):
    """{mu_p: attrs of /fits/<label>} for the dry fits present."""
    out = {}
    if "fits" not in h5:
        return out
    for name, g in h5["fits"].items():
        if isinstance(g, h5py.Group) and "particle_friction" in g.attrs:
            out[float(g.attrs["particle_friction"])] = dict(g.attrs)
    return out


def law_name(f):
    return str(f.get("law", "gdr_midi"))


def law_label(f):
    return "Peyneau & Roux" if law_name(f) == "peyneau_roux" else "GDR MiDi"


def fitted_friction(f, I):
    """The fitted mu(I) of /fits/<label>: mu_0 + c I^alpha (peyneau_roux) or GDR MiDi."""
    if law_name(f) == "peyneau_roux":
        return f["mu_0"] + f["c"] * I ** f["alpha"]
    return mu_of_I(I, f["mu_s"], f["mu_2"], f["I_0"])


def fitted_solid_fraction(f, I):
    """phi_RCP - b I^beta (peyneau_roux) or phi_c - a I (GDR MiDi)."""
    if law_name(f) == "peyneau_roux":
        return f["phi_rcp"] - f["b"] * I ** f["beta"]
    return f["phi_c"] - f["a"] * I


class ConditionTable:
    """/steady-like columns of a sweep that has not written /steady (running or interrupted),
    from /conditions/N/steady, whose attributes carry the /steady column names
    (dem_coupling/kind/dem_columns.hpp); a condition that stopped before strain.total is NaN."""

    def __init__(self, run, h5):
        total = np.nan
        try:
            import yaml
            with open(os.path.join(run, "case.yaml")) as f:
                total = float(yaml.safe_load(f)["strain"]["total"])
        except Exception:  # noqa: BLE001 - no case file: keep every condition
            pass
        conds = sorted(h5["conditions"].keys(), key=int)
        names = set()
        for n in conds:
            if "steady" in h5["conditions"][n]:
                names.update(h5["conditions"][n]["steady"].attrs.keys())
        self.columns = {name: np.full(len(conds), np.nan) for name in names}
        self.columns["particle_friction"] = np.full(len(conds), np.nan)
        self.wet = False
        for k, n in enumerate(conds):
            g = h5["conditions"][n]
            self.columns["particle_friction"][k] = g.attrs.get("particle_friction", np.nan)
            self.wet = self.wet or "liquid_viscosity" in g.attrs
            if "steady" not in g:
                continue
            a = g["steady"].attrs
            if np.isfinite(total) and a.get("steady_end_strain", 0.0) < 0.98 * total:
                continue
            for name in names:
                self.columns[name][k] = a.get(name, np.nan)
        self.attrs = {}
        if "fits/mixed_number" in h5:
            self.attrs["fitted_alpha"] = h5["fits/mixed_number"].attrs["alpha"]

    def __getitem__(self, name):
        return self.columns[name]

    def __contains__(self, name):
        return name in self.columns and (self.wet or name not in ("viscous_number",))


def steady_table(run, h5):
    if "steady" in h5 and "friction" in h5["steady"]:
        return h5["steady"]
    if "conditions" in h5:
        return ConditionTable(run, h5)
    return None


def point_plots(run, h5, n):
    g = h5[f"conditions/{n}"]
    if "series" not in g:
        return
    s = g["series"]
    strain = s["strain"][:]
    start = g["steady"].attrs.get("steady_start_strain", np.nan) if "steady" in g else np.nan
    fig, axes = plt.subplots(2, 2, figsize=(11, 6.5), sharex=True)
    # The series and the steady attributes share the names of docs/results.md.
    names = ["friction", "normal_stress", "solid_fraction", "granular_temperature"]
    for ax, name in zip(axes.flat, names):
        ax.plot(strain, s[name][:], lw=0.6)
        if np.isfinite(start):
            ax.axvline(start, color="k", ls="--", lw=0.8, label="steady start (MSER-5)")
        if "steady" in g and name in g["steady"].attrs:
            ax.axhline(g["steady"].attrs[name], color="r", lw=0.8, label="steady mean")
        if name == "normal_stress" and "normal_stress_target" in g.attrs:
            ax.axhline(g.attrs["normal_stress_target"], color="g", lw=0.8, label="servo target")
        unit = s[name].attrs.get("unit", "1")
        ax.set(ylabel=s[name].attrs.get("description", name) + ("" if unit == "1" else f" [{unit}]"))
    for ax in axes[1]:
        ax.set(xlabel="shear strain")
    axes[0][0].legend(fontsize=7)
    fig.suptitle(f"DEM point {n}: γ̇ = {g.attrs['shear_rate']:g} 1/s, μ_p = "
                 f"{g.attrs['particle_friction']:g}, N = {g.attrs['particles']:.0f}")
    fig.tight_layout()
    fig.savefig(os.path.join(run, f"series_{n}.png"), dpi=110)
    plt.close(fig)
    if "profile" in g and "steady" in g:
        v = g["profile/velocity"][:]
        pstrain = g["profile/strain"][:]
        steady = v[pstrain >= start] if np.isfinite(start) else v
        mean = np.nanmean(steady, axis=0)
        bins = mean.size
        ly = s["box_height"][-1]
        y = (np.arange(bins) + 0.5) / bins * ly
        fig, ax = plt.subplots(figsize=(4.5, 4))
        ax.plot(mean, y * 1e3, "o", label="DEM (steady mean)")
        ax.plot(g.attrs["shear_rate"] * y, y * 1e3, "k-", lw=0.8, label="imposed γ̇ (y - ylo)")
        ax.set(xlabel="v_x [m/s]", ylabel="y - ylo [mm]", title="mean velocity profile")
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(os.path.join(run, f"profile_{n}.png"), dpi=110)
        plt.close(fig)


def sweep_plots(run, h5, s):
    I, Ie = s["inertial_number"][:], s["inertial_number_err"][:]
    mu, mue = s["friction"][:], s["friction_err"][:]
    phi, phie = s["solid_fraction"][:], s["solid_fraction_err"][:]
    T, Te = s["scaled_temperature"][:], s["granular_temperature_err"][:]
    Tabs = s["granular_temperature"][:]
    mup = s["particle_friction"][:]
    groups = sorted(set(mup))
    Igrid = np.logspace(-3, 0, 200)
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    for m in groups:
        k = (mup == m) & np.isfinite(mu)
        ax.errorbar(I[k], mu[k], xerr=Ie[k], yerr=mue[k], fmt="o", ms=4, label=f"DEM μ_p = {m:g}")
    fits = friction_fits(h5)
    for c, m in enumerate(groups):
        color = f"C{c}"
        f = fits.get(float(m))
        if f is not None and np.isfinite(f.get("mu_s", np.nan)):
            ax.semilogx(Igrid, fitted_friction(f, Igrid), "-", color=color, lw=1.0,
                        label=f"fit μ_p = {m:g} ({law_label(f)}): μ(0) = {f['mu_s']:.3f} ± "
                        f"{f['mu_s_err']:.3f}, χ²_red = {f['mu_chi2_red']:.2g}")
        pub = PUBLISHED.get(float(m))
        if pub is not None:
            lo, hi, _, src = pub
            if hi > lo:
                ax.axhspan(lo, hi, color=color, alpha=0.15, lw=0, label=f"published μ_s {lo:g}-{hi:g} ({src})")
            else:
                ax.axhline(lo, color=color, ls=":", lw=0.8, label=f"published μ_s ≈ {lo:g} ({src})")
    ax.semilogx(Igrid, mu_of_I(Igrid), "k--", lw=0.6,
                label="glass beads: μ_s=0.38, μ_2=0.64, I_0=0.28 (Jop 2006)")
    ax.set(xlabel="I = γ̇ d / sqrt(σ_yy/ρ_p)", ylabel="μ = τ/σ_yy", title="μ(I)", xlim=(5e-3, 0.5))
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(run, "mu_I.png"), dpi=120)
    plt.close(fig)
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    for m in groups:
        k = (mup == m) & np.isfinite(phi)
        ax.errorbar(I[k], phi[k], xerr=Ie[k], yerr=phie[k], fmt="o", ms=4, label=f"DEM μ_p = {m:g}")
    for c, m in enumerate(groups):
        color = f"C{c}"
        f = fits.get(float(m))
        if f is not None and np.isfinite(f.get("phi_c", np.nan)):
            ax.plot(Igrid, fitted_solid_fraction(f, Igrid), "-", color=color, lw=1.0,
                    label=f"fit ({law_label(f)}): φ(0) = {f['phi_c']:.4f} ± {f['phi_c_err']:.4f}, "
                    f"χ²_red = {f['phi_chi2_red']:.2g}")
        pub = PUBLISHED.get(float(m))
        if pub is not None:
            ax.axhline(pub[2], color=color, ls=":", lw=0.8, label=f"published φ_c ≈ {pub[2]:g} ({pub[3]})")
    ax.set(xscale="log", xlabel="I", ylabel="φ", title="φ(I)", xlim=(5e-3, 0.5))
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(run, "phi_I.png"), dpi=120)
    plt.close(fig)
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    with np.errstate(invalid="ignore", divide="ignore"):
        Tse = T * Te / Tabs
    for m in groups:
        k = (mup == m) & np.isfinite(T)
        ax.errorbar(I[k], T[k], yerr=Tse[k], fmt="o", ms=4, label=f"DEM μ_p = {m:g}")
    ax.set(xscale="log", yscale="log", xlabel="I", ylabel="T / (d γ̇)²", title="scaled temperature")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(run, "T_I.png"), dpi=120)
    plt.close(fig)


def wet_sweep_plots(run, h5, s):
    J, Je = s["viscous_number"][:], s["viscous_number_err"][:]
    K, Ke = s["mixed_number"][:], s["mixed_number_err"][:]
    I, Ie = s["inertial_number"][:], s["inertial_number_err"][:]
    St = s["stokes_number"][:]
    mu, mue = s["friction"][:], s["friction_err"][:]
    phi, phie = s["solid_fraction"][:], s["solid_fraction_err"][:]
    ok = np.isfinite(mu) & (J > 0)
    if not ok.any():
        return
    k_label = "K = J + α I² (case α)"
    if "fitted_alpha" in s.attrs:  # fit.alpha of the run (dem_coupling/kind/mixed_number_fit.hpp)
        alpha = float(s.attrs["fitted_alpha"])
        K = J + alpha * I * I
        Ke = K * Je / J  # J and I² both ∝ 1/σ_yy
        k_label = f"K = J + α I², fitted α = {alpha:.3g}"
    lo, hi = min(J[ok].min(), K[ok].min()), max(J[ok].max(), K[ok].max())
    grid = np.logspace(np.log10(max(lo, 1e-6)) - 0.5, np.log10(hi) + 0.5, 200)

    def scatter(ax, x, xe, y, ye):
        sc = ax.scatter(x[ok], y[ok], c=np.log10(St[ok]), cmap="viridis", s=18, zorder=3)
        ax.errorbar(x[ok], y[ok], xerr=xe[ok], yerr=ye[ok], fmt="none", ecolor="gray", lw=0.6)
        return sc

    for name, x, xe, y, ye, law, xlabel, ylabel in [
            ("mu_J", J, Je, mu, mue, boyer_mu, "J = η0 γ̇ / σ_yy", "μ"),
            ("phi_J", J, Je, phi, phie, boyer_phi, "J", "φ"),
            ("mu_K", K, Ke, mu, mue, boyer_mu, k_label, "μ"),
            ("mu_I_wet", I, Ie, mu, mue, None, "I = γ̇ d / sqrt(σ_yy/ρ_p)", "μ")]:
        fig, ax = plt.subplots(figsize=(5.5, 4.2))
        sc = scatter(ax, x, xe, y, ye)
        if law is not None:
            ax.plot(grid, law(grid), "k-", lw=0.8, label="Boyer et al. 2011"
                    + (" (law in K)" if name == "mu_K" else ""))
            if name == "mu_K" and "fits/mixed_number" in h5:
                f = h5["fits/mixed_number"].attrs
                if np.isfinite(f["alpha"]):
                    ax.plot(grid, f["mu_1"] + (f["mu_2"] - f["mu_1"]) / (1.0 + f["K_0"] / grid),
                            "r-", lw=1.0, label=f"free fit: μ_1 = {f['mu_1']:.3f}, μ_2 = "
                            f"{f['mu_2']:.3f}, K_0 = {f['K_0']:.3g},\nα = {f['alpha']:.3g} ± "
                            f"{f['alpha_err']:.2g}, χ²_red = {f['mu_chi2_red']:.2g}")
            ax.legend(fontsize=7)
        else:
            ax.plot(grid, mu_of_I(grid), "k--", lw=0.8, label="dry μ(I) (Jop 2006)")
            ax.legend(fontsize=7)
        fig.colorbar(sc, ax=ax, label="log10 St")
        ax.set(xscale="log", xlabel=xlabel, ylabel=ylabel, title=f"immersed: {ylabel}({xlabel[0]})")
        fig.tight_layout()
        fig.savefig(os.path.join(run, f"{name}.png"), dpi=120)
        plt.close(fig)
    if "fits/boyer_split" in h5:
        b = h5["fits/boyer_split"]
        Jb = b["viscous_number"][:]
        okb = np.isfinite(b["friction_contact"][:]) & (Jb > 0)
        fig, ax = plt.subplots(figsize=(5.5, 4.2))
        ax.errorbar(Jb[okb], b["friction_contact"][:][okb], yerr=b["friction_contact_err"][:][okb],
                    fmt="o", ms=4, color="C0", label="DEM τ_contact/σ_yy")
        ax.errorbar(Jb[okb], b["friction_lubrication"][:][okb],
                    yerr=b["friction_lubrication_err"][:][okb], fmt="s", ms=4, color="C1",
                    label="DEM τ_lub/σ_yy")
        ax.errorbar(Jb[okb], mu[okb], yerr=mue[okb], fmt="^", ms=4, color="C2", label="DEM μ")
        ax.plot(grid, boyer_mu_c(grid), "-", color="C0", lw=0.8, label="Boyer μ_c(J) (contact)")
        ax.plot(grid, boyer_mu_h(grid), "-", color="C1", lw=0.8,
                label="Boyer μ_h(J) = J + 2.5 ν_m J^½ (hydrodynamic)")
        ax.plot(grid, boyer_mu(grid), "-", color="C2", lw=0.8, label="Boyer μ(J)")
        St_b = b["stokes_number"][:]
        for x, y, st in zip(Jb[okb], b["friction_contact"][:][okb], St_b[okb]):
            ax.annotate(f"St {st:.2g}", (x, y), fontsize=6, xytext=(3, 3), textcoords="offset points")
        ax.set(xscale="log", xlabel="J = η0 γ̇ / σ_yy", ylabel="stress ratio",
               title="contact and hydrodynamic parts vs Boyer 2011")
        ax.legend(fontsize=6)
        fig.tight_layout()
        fig.savefig(os.path.join(run, "boyer_split.png"), dpi=120)
        plt.close(fig)
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    tau = s["shear_stress"][:]
    for key, label in [("shear_stress_contact", "contact"), ("shear_stress_lubrication",
                       "lubrication"), ("shear_stress_drag", "drag"),
                       ("shear_stress_kinetic", "kinetic")]:
        ax.errorbar(St[ok], s[key][:][ok] / tau[ok], yerr=s[key + "_err"][:][ok] / tau[ok],
                    fmt="o-", ms=4, label=label)
    ax.set(xscale="log", xlabel="St = ρ_p d² γ̇ / η0", ylabel="part of τ",
           title="shear stress split")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(run, "stress_parts.png"), dpi=120)
    plt.close(fig)


def main():
    run = sys.argv[1]
    with h5py.File(os.path.join(run, "result.h5"), "r") as h5:
        if "conditions" in h5:
            for n in sorted(h5["conditions"].keys(), key=int):
                point_plots(run, h5, n)
        s = steady_table(run, h5)
        if s is not None and s["friction"][:].shape[0] > 1:
            sweep_plots(run, h5, s)
            if "viscous_number" in s:
                wet_sweep_plots(run, h5, s)


if __name__ == "__main__":
    main()
