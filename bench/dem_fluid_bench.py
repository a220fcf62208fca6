#!/usr/bin/env python3
"""Cost of fix fluid/le relative to a dry step at equal N, and its 2-rank speed-up.

Runs the granflow-dem driver on a self-contained Lees-Edwards shear deck (the study's case:
13^3 = 2197 bidisperse 0.9/1.1 mm Hertz spheres, compressed to phi = 0.55, sheared at 50 1/s,
dt = 4e-6 s), dry, with `fix fluid/le` (drag + rotation + normal and tangential lubrication,
eta = 0.01 Pa s, h_max = 50 um, h_min = 1 um), and with the same fix and `reach skin`, on 1 and
2 MPI ranks, and reads the shear-stage wall time (driver_stats.tsv: liggghts_s, the LIGGGHTS
part of the shear stage).

usage: bench/dem_fluid_bench.py BUILD_DIR [--steps N] [--repeat R] [--out DIR] [--breakdown]
       bench/dem_fluid_bench.py BUILD_DIR --cpu [--baseline OLD_BUILD_DIR] [--steps N] [--repeat R]
Prints a markdown table (s per 1000 steps; wet/dry ratio; speed-up) for
docs/performance.md#dem_fluid.
--breakdown adds LIGGGHTS' own timing split (Pair / Neigh / Comm / Other, 1 rank, one
uninterrupted `run` inside the deck) for: dry; dry with the wet neighbour-list reach
(contact_distance_factor 1.0556 = 1 + h_max/d_small, what fix fluid/le registers); dry with the
same reach through the skin instead (0.25 mm, factor 1: the list is as long, but pair gran skips
the pairs outside contact); drag + rotational drag only (the wet microstructure without
lubrication); drag + normal lubrication (`tangential no`); all fluid forces. The wet variants also
report the mean number of lubricated pairs (f_fluid[27]), and the lubrication's cost per pair is
(Other of a lubricated variant - Other of the drag-only one) / pairs.
"""
import argparse
import os
import resource
import subprocess
import sys
import tempfile

DECK = """# granflow fix fluid/le benchmark deck (see bench/dem_fluid_bench.py)
{header}processors      * * 1
region          box prism 0 0.0169 0 0.0169 0 0.0169 0 0 0 units box
create_box      2 box
neighbor        0.0002 bin
neigh_modify    delay 0
fix m1 all property/global youngsModulus peratomtype 1.e7 1.e7
fix m2 all property/global poissonsRatio peratomtype 0.3 0.3
fix m3 all property/global coefficientRestitution peratomtypepair 2 0.7 0.7 0.7 0.7
fix m4 all property/global coefficientFriction peratomtypepair 2 0.5 0.5 0.5 0.5
pair_style      gran model hertz tangential history
pair_coeff      * *
timestep        4e-6
lattice         sc 0.0013
create_atoms    1 box
set             group all type/fraction 2 0.5 4711
set             type 1 diameter 0.0009 density 2500
set             type 2 diameter 0.0011 density 2500
fix             integr all nve/sphere
compute         gf_virial all pressure thermo_temp virial
thermo_style    custom step atoms ke c_gf_virial[2]
thermo_modify   norm no lost error
thermo          {sample}
compute         rad all property/atom radius
variable        vp atom 4.0/3.0*PI*c_rad^3
compute         vs all reduce sum v_vp
thermo_style    custom step atoms ke c_gf_virial[2] c_vs
run             0
variable        Vs equal c_vs
variable        Lt equal (${{Vs}}/0.55)^(1.0/3.0)
fix             comp all deform 1 x final 0 ${{Lt}} y final 0 ${{Lt}} z final 0 ${{Lt}} remap x
run             10000
unfix           comp
thermo_style    custom step atoms ke c_gf_virial[2]
{fluid}
variable        vtop equal 50*ly
variable        ylo0 equal ylo
variable        yhi0 equal yhi
velocity        all ramp vx 0.0 ${{vtop}} y ${{ylo0}} ${{yhi0}} units box sum yes
fix             gf_shear all deform 1 xy erate 50 remap v
"""

FLUID = ("fix fluid all fluid/le viscosity 0.01 permeability seed_eq26 drag yes rotation yes "
         "lubrication 5e-5 1e-6 tangential yes sums sampled")
DRAG_ONLY = ("fix fluid all fluid/le viscosity 0.01 permeability seed_eq26 drag yes rotation yes")


def deck_header(driver, steps, sample):
    """The deck header granflow-dem reads, from its own definition (granflow-dem --header)."""
    words = ["shear_rate=50", f"total_steps={steps}", f"sample_every={sample}",
             "profile_bins=10", "particle_density=2500"]
    return subprocess.run([driver, "--header"] + words, check=True, capture_output=True,
                          text=True).stdout


def run(driver, workdir, fluid, ranks, steps, cpu=False):
    os.makedirs(workdir, exist_ok=True)
    with open(os.path.join(workdir, "in.bench"), "w") as f:
        f.write(DECK.format(header=deck_header(driver, steps, 100), sample=100, fluid=fluid))
    cmd = [driver, "in.bench", "-log", "log.txt", "-screen", "none"]
    env = dict(os.environ)
    if ranks > 1:
        cmd = ["mpirun", "-np", str(ranks), "--oversubscribe"] + cmd
        env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    subprocess.run(cmd, cwd=workdir, env=env, check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(workdir, "driver_stats.tsv")) as f:
        header, values = f.read().split("\n")[:2]
    stats = dict(zip(header.split("\t"), values.split("\t")))
    key = "liggghts_cpu_s" if cpu else "liggghts_s"  # CPU time summed over ranks, or wall time
    return float(stats[key]) / steps * 1000.0  # s per 1000 steps


# --cpu: CPU time (driver_stats.tsv liggghts_cpu_s) of the shear stage, 1 rank, sampled every 100
# steps as a production run: robust to other jobs on the machine, unlike the wall times.
CPU_VARIANTS = {
    "dry": "",
    "wet (sums sampled)": FLUID,
    "wet, sums every step": FLUID.replace("sums sampled", "sums every"),
    "wet, reach skin": FLUID + " reach skin",
    "wet, h_max = 0.025 d": FLUID.replace("5e-5 1e-6", "2.5e-5 1e-6"),
    "wet, h_max = 0.025 d, reach skin": FLUID.replace("5e-5 1e-6", "2.5e-5 1e-6") + " reach skin",
    "wet, h_max = 0.1 d": FLUID.replace("5e-5 1e-6", "1e-4 1e-6"),
    "wet, h_max = 0.1 d, reach skin": FLUID.replace("5e-5 1e-6", "1e-4 1e-6") + " reach skin",
    "drag + rotational drag only": DRAG_ONLY,
}


def cpu_table(driver, out, steps, repeat, baseline=None):
    rows = []
    for name, fluid in CPU_VARIANTS.items():
        tag = "cpu_" + str(len(rows))
        t = min(run(driver, os.path.join(out, f"{tag}_{r}"), fluid, 1, steps, cpu=True)
                for r in range(repeat))
        rows.append((name, t))
        print(f"{name}: {t:.3f} CPU s / 1000 steps", file=sys.stderr)
    if baseline:  # an older granflow-dem (no 'sums' keyword, no CPU column in its stats):
        # CPU time of the whole process (getrusage of the child) with steps and with steps / 5
        # shear steps; the difference is 0.8 steps of shear (the compression cancels)
        old = FLUID.replace(" sums sampled", "")

        def child_cpu(n, r):
            before = resource.getrusage(resource.RUSAGE_CHILDREN)
            run(baseline, os.path.join(out, f"cpu_base_{n}_{r}"), old, 1, n)
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            return (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)

        t = min((child_cpu(steps, r) - child_cpu(steps // 5, r)) / (steps - steps // 5) * 1000
                for r in range(repeat))
        rows.append(("wet, baseline build (process CPU difference)", t))
    dry = rows[0][1]
    print("\n| variant (1 rank, CPU) | ms per step | / dry |")
    print("|---|---|---|")
    for name, t in rows:
        print(f"| {name} | {t:.3f} | {t / dry:.2f} |")


BREAKDOWN = {
    "dry": "",
    "dry + list reach of the wet run (contact_distance_factor 1.0556)":
        "neigh_modify delay 0 contact_distance_factor 1.0556",
    "dry + the same reach as skin (0.25 mm, factor 1)": "neighbor 0.00025 bin",
    "drag + rotational drag only": DRAG_ONLY,
    "drag + normal lubrication (tangential no)": FLUID.replace("tangential yes", "tangential no"),
    "all fluid forces": FLUID,
    "all fluid forces, reach skin": FLUID + " reach skin",
    "all fluid forces, sums every step": FLUID.replace("sums sampled", "sums every"),
    "all fluid forces, h_max = 0.025 d": FLUID.replace("5e-5 1e-6", "2.5e-5 1e-6"),
    "all fluid forces, h_max = 0.1 d": FLUID.replace("5e-5 1e-6", "1e-4 1e-6"),
    "all fluid forces, h_max = 0.025 d, reach skin": FLUID.replace("5e-5 1e-6", "2.5e-5 1e-6")
                                                    + " reach skin",
}


def breakdown(driver, workdir, steps):
    """LIGGGHTS timing split of one uninterrupted shear run per variant (ms per step)."""
    rows = []
    for name, fluid in BREAKDOWN.items():
        d = os.path.join(workdir, "breakdown_" + str(len(rows)))
        os.makedirs(d, exist_ok=True)
        wet = "fluid/le" in fluid
        # the mean number of lubricated pairs over the run (entry 27 of fix fluid/le)
        # (every 100 steps, with thermo: `sums sampled` forms the sums where the virial is tallied)
        count = ("fix pairs all ave/time 100 1 100 f_fluid[27] ave running\n"
                 "thermo_style custom step atoms ke c_gf_virial[2] f_pairs\n") if wet else ""
        with open(os.path.join(d, "in.bench"), "w") as f:
            f.write(DECK.format(header=deck_header(driver, 100, 100), sample=100, fluid=fluid) + count +
                    f"run {steps}\n")
        subprocess.run([driver, "in.bench", "-log", "log.txt", "-screen", "none"], cwd=d,
                       check=True, stdout=subprocess.DEVNULL)
        text = open(os.path.join(d, "log.txt"), errors="replace").read()
        block = text[text.index(f"for {steps} steps"):]
        times = {}
        for key in ("Pair", "Neigh", "Comm", "Other"):
            line = next(l for l in block.splitlines() if l.startswith(key + " "))
            times[key] = float(line.split("=")[1].split()[0]) / steps * 1e3
        pairs = None
        if wet:  # last thermo line before the timing block: step atoms ke p f_pairs
            thermo = text[:text.index(f"Loop time of", text.index(f"run {steps}"))]
            last = [l.split() for l in thermo.splitlines() if l.split()[:1] and
                    l.split()[0].isdigit()][-1]
            pairs = float(last[-1])
        rows.append((name, times, pairs))
    print("\n| variant (1 rank) | Pair | Neigh | Comm | Other (fixes) | total (ms/step) | "
          "lubricated pairs |")
    print("|---|---|---|---|---|---|---|")
    for name, t, pairs in rows:
        print(f"| {name} | {t['Pair']:.3f} | {t['Neigh']:.3f} | {t['Comm']:.3f} | "
              f"{t['Other']:.3f} | {sum(t.values()):.3f} | "
              f"{'' if pairs is None else f'{pairs:.0f}'} |")
    drag_other = rows[3][1]["Other"]
    for name, t, pairs in rows[4:]:
        print(f"\nlubrication cost, {name}: ({t['Other']:.3f} - {drag_other:.3f}) ms / "
              f"{pairs:.0f} pairs = {(t['Other'] - drag_other) / pairs * 1e6:.1f} ns per pair")
    dry = sum(rows[0][1].values())
    print(f"\ntotal / dry: " + ", ".join(f"{name} {sum(t.values()) / dry:.2f}"
                                       for name, t, _ in rows[1:]))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("build_dir")
    ap.add_argument("--steps", type=int, default=5000)
    ap.add_argument("--repeat", type=int, default=1, help="best of R runs per configuration")
    ap.add_argument("--out", default=None, help="work directory (default: a temporary one)")
    ap.add_argument("--breakdown", action="store_true", help="add the LIGGGHTS timing split")
    ap.add_argument("--cpu", action="store_true",
                    help="only the CPU-time table of the variants (load-robust), 1 rank")
    ap.add_argument("--baseline", default=None,
                    help="with --cpu: another build directory to time the wet deck with")
    a = ap.parse_args()
    driver = os.path.join(os.path.abspath(a.build_dir), "dem_coupling", "granflow-dem")
    out = a.out or tempfile.mkdtemp(prefix="dem_fluid_bench_")
    if a.cpu:
        base = (os.path.join(os.path.abspath(a.baseline), "dem_coupling", "granflow-dem")
                if a.baseline else None)
        cpu_table(driver, out, a.steps, a.repeat, base)
        return
    cases = {"dry": "", "wet": FLUID, "wet, reach skin": FLUID + " reach skin"}
    t = {}
    for kind, fluid in cases.items():
        for ranks in (1, 2):
            name = f"{kind}_{ranks}"
            tag = kind.replace(", ", "_").replace(" ", "_")
            t[name] = min(
                run(driver, os.path.join(out, f"{tag}_{ranks}_{r}"), fluid, ranks, a.steps)
                for r in range(a.repeat))
            print(f"{name}: {t[name]:.3f} s / 1000 steps", file=sys.stderr)
    print("| case | 1 rank (s/1000 steps) | 2 ranks (s/1000 steps) | 2-rank speed-up |")
    print("|---|---|---|---|")
    for kind in cases:
        print(f"| {kind} | {t[kind + '_1']:.3f} | {t[kind + '_2']:.3f} | "
              f"{t[kind + '_1'] / t[kind + '_2']:.2f} |")
    for kind in list(cases)[1:]:
        print(f"\n{kind}/dry cost at equal N: 1 rank {t[kind + '_1'] / t['dry_1']:.2f}, "
              f"2 ranks {t[kind + '_2'] / t['dry_2']:.2f}")
    if a.breakdown:
        breakdown(driver, out, a.steps)


if __name__ == "__main__":
    main()
