#!/usr/bin/env python3
"""Speed vs accuracy ladder of a DEM shear case (kind: dem; docs/speed-accuracy.md, "DEM").

Run by `granflow study convergence CASE` for a `kind: dem` case: that command validates the case,
makes the study directory OUT, writes the resolved case (defaults filled in, --set applied) to
OUT/case.yaml and starts this script, which runs `granflow run CASE --set ...` once per rung
(child processes from an argument vector, never a shell).

Ladders (--vary, any of):
  particles   dem.particles                       number of spheres          more is better
  strain      strain.total                        shear strain of the run    more is better
  safety      dem.time_step_safety                Δt / (contact time)        less is better
  stiffness   material.youngs_modulus = r σ_yy    r = E/σ_yy (hertz)         more is better
              (hooke: material.normal_stiffness = r σ_yy d)
  sample      strain.sample                       strain between samples     less is better
one factor at a time around the base rung (every factor at the case's value), at each inertial
number of --inertial (γ̇ = I √(σ_yy/ρ_p)/d from the case's σ_yy, ρ_p and d). The reference of a
ladder is its most accurate rung (the others at their base values). For each rung: μ, φ and
T/(d γ̇)² with their standard errors (the run's /steady table), their difference from the
ladder's reference in combined standard errors, the errors
    mu_error  = √((μ − μ_ref)² + se(μ)²) / μ_ref        (bias and statistical error)
    phi_error = √((φ − φ_ref)² + se(φ)²)
and the cost (wall s of the whole `granflow run`, steps from summary.json, particle-steps).
With --seeds N every rung is run with N seeds (statistics.seeds = N: dem.seed, dem.seed + 1, ...,
one after the other in the rung's run): its μ, φ, T are the means over the seeds with the
between-seed standard error s/√N (the run's seeds.* keys), the differences and errors above are
computed on these means, steady means every seed steady and the cost is that of all N runs.
Writes OUT/study.csv, OUT/study.md, OUT/study.json (study.N.<column>) and OUT/pareto.png.

Usage: dem_study.py CASE OUT [--granflow PATH] [--vary particles,strain,safety,stiffness,sample]
           [--ladder NAME=V1,V2,...]... [--inertial 0.01,0.2] [--seeds N] [--jobs N]
           [--set key.path=value]... [--check]
--check validates the arguments only (no case, no directory) and exits 0, or 2 with one line.
Exit: 0 every rung ran; 1 a rung failed (its row says so); 2 bad arguments (one line).
"""
import argparse
import concurrent.futures
import json
import math
import os
import subprocess
import sys
import time

# The case keys of each ladder: spelled here and in the DEM kind's schema only
# (dem_coupling/kind/shear_schema.cpp); a renamed key makes every rung exit 2, naming it.
LADDERS = {
    "particles": dict(key="dem.particles", kind=int, rungs="250,500,1000,2000", better=max,
                      what="spheres"),
    "strain": dict(key="strain.total", kind=float, rungs="2,5,10,20", better=max,
                   what="total strain"),
    "safety": dict(key="dem.time_step_safety", kind=float, rungs="0.05,0.1,0.2", better=min,
                   what="Δt safety"),
    "stiffness": dict(key=None, kind=float, rungs="1e4,1e5,1e6", better=max, what="E/σ_yy"),
    "sample": dict(key="strain.sample", kind=float, rungs="0.005,0.01,0.02", better=min,
                   what="sample strain"),
}
DEFAULT_VARY = "particles,strain,safety,stiffness,sample"
DEFAULT_INERTIAL = "0.01,0.2"
# What the run is told besides the ladder: no particle snapshots.
QUIET_SETS = ["output.snapshot_strain=0"]
COLUMNS = ["row", "n", "inertial_target", "ladder", "label", "reference", "base", "particles", "strain",
           "safety", "stiffness", "sample", "shear_rate", "inertial_number", "steady",
           "mu", "mu_err", "phi", "phi_err", "T", "T_err", "dmu_se", "dphi_se", "dT_se",
           "mu_error", "phi_error", "wall_s", "steps", "particle_steps", "time_step", "failed",
           "seeds", "mu_scatter_ratio"]


class BadInput(Exception):
    pass


class Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit 2 (argparse prints usage + message)
        raise BadInput(message)


def parse_list(name, text, kind):
    try:
        values = [kind(float(v)) if kind is int else kind(v) for v in text.split(",") if v != ""]
    except ValueError:
        raise BadInput(f"{name}: expected comma-separated numbers, got '{text}'")
    if not values or any(not math.isfinite(v) or v <= 0 for v in values):
        raise BadInput(f"{name}: expected positive numbers, got '{text}'")
    return sorted(set(values))


def parse_args(argv):
    ap = Parser(prog="granflow study convergence (kind: dem)")
    ap.add_argument("case")
    ap.add_argument("out")
    ap.add_argument("--granflow", default="granflow")
    ap.add_argument("--vary", default="")
    ap.add_argument("--ladder", action="append", default=[], help="NAME=V1,V2,...")
    ap.add_argument("--inertial", default="")
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--seeds", type=int, default=1)
    ap.add_argument("--set", action="append", default=[], help="case override key.path=value")
    ap.add_argument("--check", action="store_true")
    a = ap.parse_args(argv)
    vary = [v.strip() for v in (a.vary or DEFAULT_VARY).split(",") if v.strip()]
    for v in vary:
        if v not in LADDERS:
            raise BadInput(f"--vary: unknown ladder '{v}' (expected any of {','.join(LADDERS)})")
    rungs = {name: parse_list(f"--ladder {name}", spec["rungs"], spec["kind"])
             for name, spec in LADDERS.items()}
    for item in a.ladder:
        name, sep, values = item.partition("=")
        if not sep or name not in LADDERS:
            raise BadInput(f"--ladder {item}: expected NAME=V1,V2,... with NAME one of "
                           f"{','.join(LADDERS)}")
        rungs[name] = parse_list(f"--ladder {name}", values, LADDERS[name]["kind"])
    inertial = parse_list("--inertial", a.inertial or DEFAULT_INERTIAL, float)
    if a.jobs < 1:
        raise BadInput(f"--jobs: expected a whole number >= 1, got {a.jobs}")
    if not 1 <= a.seeds <= 64:  # the range of statistics.seeds
        raise BadInput(f"--seeds: expected a whole number from 1 to 64, got {a.seeds}")
    return a, vary, rungs, inertial


def case_value(case, path):
    node = case
    for part in path.split("."):
        if not isinstance(node, dict) or part not in node:
            return None
        node = node[part]
    return node


def set_value(case, path, value):
    *parents, leaf = path.split(".")
    for part in parents:
        case = case.setdefault(part, {})
    case[leaf] = value


def required(case, path, origin):
    value = case_value(case, path)
    if value is None:
        raise BadInput(f"{origin}: {path}: expected a value (needed by the DEM study)")
    return value


def stiffness_key(case):
    """(case key, factor): the key holding the contact stiffness and key = factor × E/σ_yy."""
    sigma = float(case_value(case, "control.normal_stress"))
    if case_value(case, "material.contact_law") == "hooke":
        return "material.normal_stiffness", sigma * float(case_value(case, "material.diameter"))
    return "material.youngs_modulus", sigma


def plan(case, origin, vary, rungs, inertial, seeds=1):
    """The rungs to run: dicts with the ladder, label, factor values and the --set list."""
    if case_value(case, "control.mode") != "constant_pressure":
        raise BadInput(f"{origin}: control.mode: expected constant_pressure (the study sets γ̇ "
                       "from I and σ_yy, and the stiffness as E/σ_yy)")
    if seeds > 1 and any(k == "dem.seed" for k, _ in flatten_all(case_value(case, "sweep"))):
        raise BadInput(f"{origin}: sweep.dem.seed: --seeds needs a case that does not sweep "
                       "dem.seed (the study runs the seeds dem.seed, dem.seed + 1, ...)")
    # A swept key other than the shear rate runs at its first value (one condition per run),
    # which is also the value the base and γ̇ are computed from.
    fixed = []
    for k, v in flatten_all(case_value(case, "sweep")):
        if k != "shear_rate":
            fixed.append(f"sweep.{k}=[{v[0]}]")
            set_value(case, k, v[0])
    d = float(required(case, "material.diameter", origin))
    rho = float(required(case, "material.particle_density", origin))
    sigma = float(required(case, "control.normal_stress", origin))
    skey, sfactor = stiffness_key(case)
    base = {}
    for name, spec in LADDERS.items():
        if name == "stiffness":
            base[name] = float(required(case, skey, origin)) / sfactor
        else:
            base[name] = spec["kind"](required(case, spec["key"], origin))

    def sets_of(values, gd):
        out = [f"{LADDERS[n]['key']}={values[n]}" for n in LADDERS if n != "stiffness"]
        out.append(f"{skey}={values['stiffness'] * sfactor:.6g}")
        swept_rate = any(k == "shear_rate" for k, _ in flatten_all(case_value(case, "sweep")))
        out.append(f"sweep.shear_rate=[{gd:.6g}]" if swept_rate else f"shear_rate={gd:.6g}")
        seeded = [f"statistics.seeds={seeds}"] if seeds > 1 else []
        return fixed + out + seeded + QUIET_SETS

    ladder = []
    for i in inertial:
        gd = i * math.sqrt(sigma / rho) / d
        ladder.append(dict(inertial_target=i, ladder="base", label=f"I {i:g} base",
                           values=dict(base), shear_rate=gd))
        for name in vary:
            for v in rungs[name]:
                if math.isclose(v, base[name], rel_tol=1e-9):
                    continue
                values = dict(base, **{name: v})
                ladder.append(dict(inertial_target=i, ladder=name,
                                   label=f"I {i:g} {name} {v:g}", values=values, shear_rate=gd))
    for r in ladder:
        r["sets"] = sets_of(r["values"], r["shear_rate"])
    return ladder, base


def flatten(prefix, node):
    if isinstance(node, dict):
        return [kv for k, v in node.items() for kv in flatten(f"{prefix}.{k}", v)]
    return [(prefix, node if isinstance(node, list) else [node])]


def flatten_all(sweep):
    return [kv for k, v in (sweep or {}).items() for kv in flatten(k, v)]


def run_one(granflow, case, out, sets, seeds=1):
    args = [granflow, "run", case, "--out", out, "--force", "--quiet"]
    for s in sets:
        args += ["--set", s]
    t0 = time.time()
    log_file = out + ".log"
    with open(log_file, "w") as log:
        r = subprocess.run(args, stdout=log, stderr=subprocess.STDOUT)
    wall = time.time() - t0
    if r.returncode != 0:  # the run's last line says why (e.g. a stiffness out of bounds)
        with open(log_file, errors="replace") as log:
            lines = [line.strip() for line in log if line.strip()]
        return dict(failed=True, status=r.returncode, wall=wall,
                    why=lines[-1] if lines else "no output")
    return dict(read_run(out, seeds), failed=False, wall=wall)


def read_run(out, seeds=1):
    import h5py
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)

    def key(name):
        return summary.get(name, summary.get(name + ".0", math.nan))

    with h5py.File(os.path.join(out, "result.h5"), "r") as h5:
        s = h5["steady"]
        rows = {c: [float(x) for x in s[c]] for c in s.keys()
                if s[c].ndim == 1 and len(s[c]) > 0 and s[c].dtype.kind in "fiu"}
        d = float(s.attrs["diameter"])
    col = {c: v[0] for c, v in rows.items()}
    scale = (d * col["shear_rate"]) ** 2  # the same γ̇ for every seed
    particles = key("dem.particles")
    if seeds == 1:
        steps = key("cost.steps")
        return dict(mu=col["friction"], mu_err=col["friction_err"], phi=col["solid_fraction"],
                    phi_err=col["solid_fraction_err"], T=col["granular_temperature"] / scale,
                    T_err=col["granular_temperature_err"] / scale,
                    inertial_number=col["inertial_number"], steady=int(col["steady_reached"]),
                    time_step=col.get("time_step", math.nan), steps=steps,
                    particle_steps=steps * particles, seeds=1)
    # N seeds, points 0 ... N-1 of the rung's run: the means and between-seed errors (seeds.*.0),
    # steady only if every seed is, the cost of all of them.
    steps = sum(summary[f"cost.steps.{k}"] for k in range(seeds))
    particles = summary.get("dem.particles", summary.get("dem.particles.0", math.nan))

    def seed(name):
        return summary.get(f"seeds.{name}.0", math.nan)

    return dict(mu=seed("mu"), mu_err=seed("mu_err"), phi=seed("phi"), phi_err=seed("phi_err"),
                T=seed("T") / scale, T_err=seed("T_err") / scale, inertial_number=seed("I"),
                steady=int(all(v == 1 for v in rows["steady_reached"])),
                time_step=col.get("time_step", math.nan), steps=steps,
                particle_steps=steps * particles, seeds=int(seed("count")),
                mu_scatter_ratio=seed("mu_scatter_ratio"))


def sigma_apart(a, a_err, b, b_err):
    se = math.hypot(a_err, b_err)
    return (a - b) / se if se > 0 else (0.0 if a == b else math.nan)


def fmt(v, spec=".4g"):
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return ""
    return format(v, spec) if isinstance(v, float) else str(v)


def write_outputs(out, rows):
    with open(os.path.join(out, "study.csv"), "w") as f:
        f.write(",".join(COLUMNS) + "\n")
        for r in rows:
            f.write(",".join(fmt(r.get(c), ".10g") for c in COLUMNS) + "\n")
    with open(os.path.join(out, "study.json"), "w") as f:
        json.dump({f"study.{r['row']}.{c}": r[c] for r in rows for c in COLUMNS
                   if c != "row" and r.get(c) is not None
                   and not (isinstance(r[c], float) and not math.isfinite(r[c]))}, f, indent=1)
    head = ("| run | I target | rung | μ | φ | T/(dγ̇)² | Δμ/SE | Δφ/SE | ΔT/SE | μ error | "
            "φ error | steady | wall s | particle-steps |\n"
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n")
    counts = {r.get("seeds") for r in rows if not r["failed"]}
    seeded = (f" Every rung: the mean over {'/'.join(str(c) for c in sorted(counts))} seeds ± "
              "the between-seed standard error s/√N; cost and wall s of all its seeds."
              if any(c and c > 1 for c in counts) else "")
    with open(os.path.join(out, "study.md"), "w") as f:
        f.write("Differences in combined standard errors from the reference of the rung's ladder "
                "(its most accurate rung, marked *; others at the base values); μ error = "
                "√(Δμ² + se²)/μ_ref, φ error = √(Δφ² + se²)." + seeded + "\n\n"
                + head)
        for r in rows:
            label = r["label"] + (" (base)" if r["base"] else "") + (" *" if r["reference"]
                                                                     else "")
            if r["failed"]:
                why = r["why"].replace("|", "/")
                f.write(f"| {r['n']} | {r['inertial_target']:g} | {label} | failed (exit "
                        f"{r['status']}: {why}) | | | | | | | | | {r['wall_s']:.0f} | |\n")
                continue
            f.write(f"| {r['n']} | {r['inertial_target']:g} | {label} | "
                    f"{r['mu']:.4f} ± {r['mu_err']:.4f} | {r['phi']:.4f} ± {r['phi_err']:.4f} | "
                    f"{r['T']:.4g} ± {r['T_err']:.2g} | {fmt(r.get('dmu_se'), '+.1f')} | "
                    f"{fmt(r.get('dphi_se'), '+.1f')} | {fmt(r.get('dT_se'), '+.1f')} | "
                    f"{fmt(r.get('mu_error'), '.2%')} | {fmt(r.get('phi_error'), '.4f')} | "
                    f"{'yes' if r['steady'] else 'no'} | {r['wall_s']:.0f} | "
                    f"{r['particle_steps']:.3g} |\n")


def plot(out, rows):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    levels = sorted({r["inertial_target"] for r in rows})
    fig, axes = plt.subplots(1, len(levels), figsize=(5.5 * len(levels), 4.5), squeeze=False)
    markers = dict(particles="o", strain="^", safety="v", stiffness="D", sample="x")
    for ax, i in zip(axes[0], levels):
        for r in rows:
            if r["inertial_target"] != i or r["failed"] or "mu_error" not in r:
                continue
            if r["base"]:  # the base run, once, in black
                if r["ladder"] == rows[0]["ladder"]:
                    ax.loglog(r["particle_steps"], r["mu_error"], "s", color="k",
                              label=f"base (against the {r['ladder']} reference)")
                continue
            ax.loglog(r["particle_steps"], max(r["mu_error"], 1e-5), markers[r["ladder"]],
                      color="C" + str(list(markers).index(r["ladder"])), label=r["ladder"],
                      mfc="none" if r["reference"] else None)
            ax.annotate(r["label"], (r["particle_steps"], r["mu_error"]), fontsize=6)
        handles, labels = ax.get_legend_handles_labels()
        unique = dict(zip(labels, handles))
        ax.legend(unique.values(), unique.keys(), fontsize=7)
        ax.set(xlabel="particle-steps", ylabel="μ error √(Δμ² + se²)/μ_ref",
               title=f"DEM speed vs accuracy, I = {i:g} (open: ladder reference)")
        ax.grid(alpha=0.3, which="both")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "pareto.png"), dpi=120)
    plt.close(fig)


def table(ladder, results, vary, base):
    """One row per ladder and rung at each I (the base run appears in every ladder), compared
    with the ladder's most accurate rung."""
    rows = []
    for i in sorted({r["inertial_target"] for r in ladder}):
        runs = [(r, res) for r, res in zip(ladder, results) if r["inertial_target"] == i]
        base_run = next((r, res) for r, res in runs if r["ladder"] == "base")
        for name in vary:
            group = [base_run] + [(r, res) for r, res in runs if r["ladder"] == name]
            group.sort(key=lambda rr: rr[0]["values"][name])
            best = LADDERS[name]["better"](r["values"][name] for r, _ in group)
            ref = next(res for r, res in group if r["values"][name] == best)
            for r, res in group:
                v = r["values"]
                row = dict(n=r["n"], inertial_target=i, ladder=name,
                           label=f"{name} {v[name]:g}", particles=v["particles"],
                           strain=v["strain"], safety=v["safety"], stiffness=v["stiffness"],
                           sample=v["sample"], shear_rate=r["shear_rate"],
                           failed=int(res["failed"]), status=res.get("status", 0),
                           why=res.get("why", ""),
                           wall_s=res["wall"], reference=int(v[name] == best),
                           base=int(v == base))
                if not res["failed"]:
                    row.update({k: res.get(k) for k in (
                        "mu", "mu_err", "phi", "phi_err", "T", "T_err", "inertial_number",
                        "steady", "steps", "particle_steps", "time_step", "seeds",
                        "mu_scatter_ratio")})
                    if not ref["failed"]:
                        row["dmu_se"] = sigma_apart(res["mu"], res["mu_err"], ref["mu"],
                                                    ref["mu_err"])
                        row["dphi_se"] = sigma_apart(res["phi"], res["phi_err"], ref["phi"],
                                                     ref["phi_err"])
                        row["dT_se"] = sigma_apart(res["T"], res["T_err"], ref["T"],
                                                   ref["T_err"])
                        row["mu_error"] = math.hypot(res["mu"] - ref["mu"],
                                                     res["mu_err"]) / ref["mu"]
                        row["phi_error"] = math.hypot(res["phi"] - ref["phi"], res["phi_err"])
                row["row"] = len(rows)
                rows.append(row)
    return rows


def main(argv):
    a, vary, rungs, inertial = parse_args(argv)
    if a.check:
        return 0
    import yaml
    case_file = os.path.join(a.out, "case.yaml")
    try:
        with open(case_file) as f:
            case = yaml.safe_load(f)
    except (OSError, yaml.YAMLError) as e:
        raise BadInput(f"{case_file}: cannot read the resolved case: {e}")
    ladder, base = plan(case, a.case, vary, rungs, inertial, a.seeds)
    for n, r in enumerate(ladder):
        r["n"] = n
        r["out"] = os.path.join(a.out, f"run_{n}")
        print(f"[{n}] {r['label']}: {' '.join(r['sets'])}", flush=True)

    def job(r):
        res = run_one(a.granflow, a.case, r["out"], a.set + r["sets"], a.seeds)  # rung last
        state = (f"failed (exit {res['status']}): {res['why']}" if res["failed"] else
                 f"μ {res['mu']:.4f} ± {res['mu_err']:.4f}")
        print(f"[{r['n']}] {r['label']}: {state}, {res['wall']:.0f} s", flush=True)
        return res

    with concurrent.futures.ThreadPoolExecutor(max_workers=a.jobs) as pool:
        results = list(pool.map(job, ladder))
    rows = table(ladder, results, vary, base)
    write_outputs(a.out, rows)
    try:
        plot(a.out, rows)
    except Exception as e:  # the tables are written; the plot is one line
        print(f"warning: {a.out}/pareto.png: {e}", file=sys.stderr)
    print(open(os.path.join(a.out, "study.md")).read())
    failed = [(r, res) for r, res in zip(ladder, results) if res["failed"]]
    for r, res in failed:
        print(f"error: rung {r['label']} ({r['out']}.log): {res['why']}", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    try:
        sys.exit(main(sys.argv[1:]))
    except BadInput as e:
        print(f"error: {e}", file=sys.stderr)
        sys.exit(2)
