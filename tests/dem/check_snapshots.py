#!/usr/bin/env python3
"""Opens the DEM particle snapshots of a run directory as a reader would (meshio, Debian
python3-meshio: the VTK XML files ParaView and OVITO open) through their index snapshots.pvd and
checks what a user needs: one vertex cell per sphere, the arrays of the docs, times at the
requested strain interval, and the velocity about the streaming profile.

usage: check_snapshots.py RUN_DIR PARTICLES SNAPSHOT_STRAIN COUNT SHEAR_RATE
Exit 0 when everything holds, 1 with the first failure on stderr."""
import os
import sys
import xml.etree.ElementTree as ET

import meshio
import numpy as np


def fail(message):
    print(f"check_snapshots: {message}", file=sys.stderr)
    sys.exit(1)


def main():
    run, particles, interval, count = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), \
        int(sys.argv[4])
    shear_rate = float(sys.argv[5])
    sets = ET.parse(os.path.join(run, "snapshots.pvd")).getroot().iter("DataSet")
    frames = [(float(d.get("timestep")), d.get("file")) for d in sets]
    if len(frames) != count:
        fail(f"{len(frames)} snapshots indexed, expected {count}")
    for k, (strain, name) in enumerate(frames):
        # The k-th snapshot at strain k × interval, to one time step (γ̇ dt ≈ 8e-5 here).
        if abs(strain - k * interval) > 1e-3:
            fail(f"{name}: strain {strain}, expected {k * interval}")
        m = meshio.read(os.path.join(run, name))
        if m.points.shape != (particles, 3):
            fail(f"{name}: points {m.points.shape}, expected ({particles}, 3)")
        cells = [(b.type, len(b.data)) for b in m.cells]
        if cells != [("vertex", particles)]:
            fail(f"{name}: cells {cells}, expected one vertex per sphere")
        for array, shape in (("radius", (particles,)), ("vx_fluctuation", (particles,)),
                             ("vy", (particles,)), ("omega", (particles, 3)),
                             ("f", (particles, 3))):
            if array not in m.point_data or m.point_data[array].shape != shape:
                fail(f"{name}: {array} missing or not of shape {shape}: "
                     f"{ {a: v.shape for a, v in m.point_data.items()} }")
        if k == 0:
            continue
        # The x velocity about the streaming profile u = γ̇ (y − ylo): zero mean (the profile
        # carries the mean flow), and a scatter (the thermal √T ≈ 0.5 d γ̇ at I ≈ 0.1) well below
        # that of the profile itself across the box, γ̇ L/√12 (≈ 1.9 d γ̇ for 300 spheres).
        fluct = m.point_data["vx_fluctuation"]
        if not np.all(np.isfinite(fluct)):
            fail(f"{name}: non-finite vx_fluctuation")
        if abs(fluct.mean()) > 5 * fluct.std() / np.sqrt(particles):
            fail(f"{name}: mean vx_fluctuation {fluct.mean()} is not 0 within 5 standard errors "
                 f"({fluct.std() / np.sqrt(particles)})")
        box = np.ptp(m.points[:, 1])
        if not fluct.std() < 0.5 * shear_rate * box / np.sqrt(12):
            fail(f"{name}: rms vx_fluctuation {fluct.std()} not below half the profile's "
                 f"{shear_rate * box / np.sqrt(12)}")
    print(f"check_snapshots: {len(frames)} snapshots of {particles} spheres")


if __name__ == "__main__":
    main()
