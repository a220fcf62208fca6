#!/usr/bin/env python3
"""Opens the DEM particle snapshots of a run directory as a reader would, through their index
snapshots.pvd, with two readers: VTK's own vtkXMLUnstructuredGridReader (Debian python3-vtk9, the
reader ParaView uses) and meshio (python3-meshio, an independent parser). Checks what a user
needs: the index lists every snapshot_<step>.vtu of the directory with increasing times at
the requested strain interval; each file has one point per sphere, one vertex cell per point, the
arrays of the docs (radius, velocity about the streaming profile, ω, force), the same values in
both readers; and the velocity about the streaming profile has zero mean and a thermal scatter.
The LAMMPS text dump of each step, snapshot_<step>.dump (what OVITO opens), is parsed by its
header (ITEM: TIMESTEP / NUMBER OF ATOMS / BOX BOUNDS xy xz yz / ATOMS) and checked against the
.vtu of the same step: the same spheres by id, the same positions and values to the dump's six
significant digits; snapshots.csv lists both files.

usage: check_snapshots.py RUN_DIR PARTICLES SNAPSHOT_STRAIN COUNT SHEAR_RATE
Exit 0 when everything holds, 1 with the first failure on stderr."""
import csv
import os
import re
import sys
import xml.etree.ElementTree as ET

import meshio
import numpy as np

# The arrays of docs/results.md ("ParaView / OVITO") and their components per sphere.
ARRAYS = {"id": 1, "type": 1, "radius": 1, "vx_fluctuation": 1, "vy": 1, "vz": 1, "omega": 3,
          "f": 3}
VTK_VERTEX = 1  # vtkCellType.h
# The .dump's ATOMS columns (dem_coupling/extraction/snapshots.cpp) and the .vtu array (and
# component) each one holds; x y z are the .vtu points.
DUMP_COLUMNS = ["id", "type", "radius", "x", "y", "z", "v_vx_fluctuation", "vy", "vz", "omegax",
                "omegay", "omegaz", "fx", "fy", "fz"]
DUMP_TO_VTU = {"id": ("id", None), "type": ("type", None), "radius": ("radius", None),
               "v_vx_fluctuation": ("vx_fluctuation", None), "vy": ("vy", None),
               "vz": ("vz", None), "omegax": ("omega", 0), "omegay": ("omega", 1),
               "omegaz": ("omega", 2), "fx": ("f", 0), "fy": ("f", 1), "fz": ("f", 2)}
# dump custom writes reals with %g: 6 significant digits, a rounding error of at most 5e-6 of
# the value; the .vtu holds the value to at least float32 (6e-8): 6e-6 relative bounds both.
DUMP_RELATIVE = 6e-6


def fail(message):
    print(f"check_snapshots: {message}", file=sys.stderr)
    sys.exit(1)


def read_with_vtk(path, particles):
    """The file through vtkXMLUnstructuredGridReader: points and arrays as numpy, after checking
    one point per sphere and one vertex cell per point."""
    try:
        from vtkmodules.util.numpy_support import vtk_to_numpy
        from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
    except ImportError as e:
        fail(f"VTK's Python modules are missing ({e}); scripts/install-deps installs python3-vtk9")
    errors = []
    reader = vtkXMLUnstructuredGridReader()
    reader.AddObserver("ErrorEvent", lambda obj, event: errors.append(event))
    reader.SetFileName(path)
    reader.Update()
    grid = reader.GetOutput()
    name = os.path.basename(path)
    if errors or grid is None:
        fail(f"{name}: vtkXMLUnstructuredGridReader reported an error")
    if grid.GetNumberOfPoints() != particles:
        fail(f"{name}: VTK reads {grid.GetNumberOfPoints()} points, expected {particles} spheres")
    if grid.GetNumberOfCells() != particles:
        fail(f"{name}: VTK reads {grid.GetNumberOfCells()} cells, expected one per sphere")
    owner = np.zeros(particles, dtype=int)
    for i in range(grid.GetNumberOfCells()):
        cell = grid.GetCell(i)
        if grid.GetCellType(i) != VTK_VERTEX or cell.GetNumberOfPoints() != 1:
            fail(f"{name}: cell {i} of VTK type {grid.GetCellType(i)} with "
                 f"{cell.GetNumberOfPoints()} points, expected a vertex (type 1) of one point")
        owner[cell.GetPointId(0)] += 1
    if not np.all(owner == 1):
        fail(f"{name}: {np.sum(owner != 1)} points not in exactly one vertex cell")
    data = grid.GetPointData()
    arrays = {}
    for array, components in ARRAYS.items():
        a = data.GetArray(array)
        if a is None or a.GetNumberOfComponents() != components or \
                a.GetNumberOfTuples() != particles:
            present = [data.GetArrayName(i) for i in range(data.GetNumberOfArrays())]
            fail(f"{name}: VTK array {array} missing or not {particles} x {components} "
                 f"(arrays: {present})")
        arrays[array] = vtk_to_numpy(a)
    points = vtk_to_numpy(grid.GetPoints().GetData())
    if not (np.all(np.isfinite(points)) and all(np.all(np.isfinite(v)) for v in arrays.values())):
        fail(f"{name}: non-finite positions or arrays")
    if not np.all(arrays["radius"] > 0):
        fail(f"{name}: a radius <= 0")
    if sorted(arrays["id"]) != list(range(1, particles + 1)):
        fail(f"{name}: the ids are not the spheres 1 ... {particles} once each")
    return points, arrays


def read_dump(path, step, particles):
    """A LAMMPS text dump of one step: {column: values} of its ATOMS section, after checking its
    header: the step, the atom count, a triclinic box (BOX BOUNDS xy xz yz, three lines of
    lo hi tilt) and the columns the deck asked for."""
    name = os.path.basename(path)
    with open(path, encoding="ascii") as f:
        lines = f.read().splitlines()

    def item(k, header):
        if k >= len(lines) or not lines[k].startswith("ITEM: " + header):
            found = lines[k] if k < len(lines) else "end of file"
            fail(f"{name}: line {k + 1} is {found!r}, expected 'ITEM: {header}'")

    item(0, "TIMESTEP")
    if int(lines[1]) != step:
        fail(f"{name}: TIMESTEP {lines[1]}, expected {step}")
    item(2, "NUMBER OF ATOMS")
    if int(lines[3]) != particles:
        fail(f"{name}: NUMBER OF ATOMS {lines[3]}, expected {particles}")
    item(4, "BOX BOUNDS xy xz yz")
    box = np.array([[float(v) for v in lines[k].split()] for k in (5, 6, 7)])
    if box.shape != (3, 3) or not np.all(box[:, 1] > box[:, 0]):
        fail(f"{name}: BOX BOUNDS lines {lines[5:8]} are not three 'lo hi tilt' with hi > lo")
    item(8, "ATOMS")
    columns = lines[8].split()[2:]
    if columns != DUMP_COLUMNS:
        fail(f"{name}: ATOMS columns {columns}, expected {DUMP_COLUMNS}")
    rows = np.array([[float(v) for v in line.split()] for line in lines[9:]])
    if rows.shape != (particles, len(columns)):
        fail(f"{name}: {rows.shape} atom rows, expected ({particles}, {len(columns)})")
    return {c: rows[:, k] for k, c in enumerate(columns)}


def check_dump(run, name, points, arrays, particles):
    """snapshot_<step>.dump against the .vtu `name` of the same step (its points and arrays)."""
    step = int(re.findall(r"\d+", name)[0])
    dump_name = f"snapshot_{step}.dump"
    dump = read_dump(os.path.join(run, dump_name), step, particles)
    # The same spheres: match the dump's rows to the .vtu's points by id (each rank writes its
    # own atoms, so the two orders differ).
    ids = dump["id"].astype(int)
    if sorted(ids) != list(range(1, particles + 1)):
        fail(f"{dump_name}: the ids are not the spheres 1 ... {particles} once each")
    order = np.argsort(ids)
    vtu_order = np.argsort(arrays["id"])
    worst = 0.0
    for column in DUMP_COLUMNS:
        if column in ("x", "y", "z"):
            vtu = points[vtu_order, "xyz".index(column)]
        else:
            array, component = DUMP_TO_VTU[column]
            values = arrays[array] if component is None else arrays[array][:, component]
            vtu = values[vtu_order]
        text = dump[column][order]
        scale = np.abs(vtu)
        if not np.all(np.abs(text - vtu) <= DUMP_RELATIVE * scale):
            k = np.argmax(np.abs(text - vtu) - DUMP_RELATIVE * scale)
            fail(f"{dump_name}: {column} of sphere {k + 1} is {text[k]!r}, the .vtu has "
                 f"{vtu[k]!r} (more than {DUMP_RELATIVE} relative)")
        nonzero = scale > 0
        if np.any(nonzero):
            worst = max(worst, float(np.max(np.abs(text - vtu)[nonzero] / scale[nonzero])))
    return dump_name, worst


def main():
    run, particles, interval, count = sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), \
        int(sys.argv[4])
    shear_rate = float(sys.argv[5])
    sets = ET.parse(os.path.join(run, "snapshots.pvd")).getroot().iter("DataSet")
    frames = [(float(d.get("timestep")), d.get("file")) for d in sets]
    if len(frames) != count:
        fail(f"{len(frames)} snapshots indexed, expected {count}")
    # Every snapshot_<step>.vtu of the directory indexed, in step order, at increasing times
    # (LIGGGHTS writes snapshot_boundingBox_<step>.vtu beside them: not particle files).
    files = sorted((f for f in os.listdir(run) if re.fullmatch(r"snapshot_\d+\.vtu", f)),
                   key=lambda f: int(re.findall(r"\d+", f)[0]))
    if [name for _, name in frames] != files:
        fail(f"snapshots.pvd lists {[name for _, name in frames]}, the directory holds {files}")
    times = [t for t, _ in frames]
    if not all(b > a for a, b in zip(times, times[1:])):
        fail(f"snapshots.pvd times {times} do not increase")
    # snapshots.csv: the same steps, each with its .vtu and its .dump, and no other .dump.
    with open(os.path.join(run, "snapshots.csv"), encoding="ascii") as f:
        rows = list(csv.DictReader(f))
    listed = [(r["file"], r["dump_file"]) for r in rows]
    expected = [(name, re.sub(r"\.vtu$", ".dump", name)) for _, name in frames]
    if listed != expected:
        fail(f"snapshots.csv lists {listed}, expected {expected}")
    dumps = sorted(f for f in os.listdir(run) if re.fullmatch(r"snapshot_\d+\.dump", f))
    if dumps != sorted(d for _, d in expected):
        fail(f"the directory holds the dumps {dumps}, snapshots.csv lists {expected}")
    worst = 0.0
    for k, (strain, name) in enumerate(frames):
        # The k-th snapshot at strain k × interval, to one time step (γ̇ dt ≈ 8e-5 here).
        if abs(strain - k * interval) > 1e-3:
            fail(f"{name}: strain {strain}, expected {k * interval}")
        points, arrays = read_with_vtk(os.path.join(run, name), particles)
        worst = max(worst, check_dump(run, name, points, arrays, particles)[1])
        m = meshio.read(os.path.join(run, name))
        # Two readers, one file: the same positions and values (both parse the same text).
        if not np.array_equal(points, m.points):
            fail(f"{name}: VTK and meshio read different positions")
        for array in ARRAYS:
            if not np.array_equal(arrays[array], m.point_data[array]):
                fail(f"{name}: VTK and meshio read different {array}")
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
    print(f"check_snapshots: {len(frames)} snapshots of {particles} spheres "
          "(vtkXMLUnstructuredGridReader and meshio), each with its LAMMPS text dump "
          f"(largest relative difference to the .vtu {worst:.2g})")


if __name__ == "__main__":
    main()
