#!/usr/bin/env python3
"""Opens the XDMF series of an MPM field directory with meshio (Debian python3-meshio) and checks
what a reader needs: one frame per step file at the written times, the material points as vertex
cells (one per point), the grid as quads, vectors and tensors with their components, and a unit
on every HDF5 dataset.

usage: check_xdmf.py FIELD_DIR SOLID_POINTS LIQUID_POINTS GRID_NODES GRID_CELLS TIME...
Exit 0 when everything holds, 1 with the first failure on stderr."""
import sys

import h5py
import meshio
import numpy as np


def fail(message):
    print(f"check_xdmf: {message}", file=sys.stderr)
    sys.exit(1)


def main():
    directory = sys.argv[1]
    solid, liquid, nodes, quads = (int(a) for a in sys.argv[2:6])
    times = [float(t) for t in sys.argv[6:]]
    expected = {"solid": (solid, "vertex", solid), "liquid": (liquid, "vertex", liquid),
                "grid": (nodes, "quad", quads)}
    for series, (points, cell_type, cells) in expected.items():
        path = f"{directory}/{series}.xmf"
        with meshio.xdmf.TimeSeriesReader(path) as reader:
            xy, blocks = reader.read_points_cells()
            if reader.num_steps != len(times):
                fail(f"{path}: {reader.num_steps} frames, expected {len(times)}")
            if xy.shape != (points, 2):
                fail(f"{path}: points {xy.shape}, expected ({points}, 2)")
            if len(blocks) != 1 or blocks[0].type != cell_type or len(blocks[0].data) != cells:
                fail(f"{path}: cells {[(b.type, len(b.data)) for b in blocks]}, "
                     f"expected {cells} {cell_type}")
            for k, t_expected in enumerate(times):
                t, point_data, _ = reader.read_data(k)
                if not np.isclose(t, t_expected, rtol=1e-12, atol=0):
                    fail(f"{path}: frame {k} at t = {t}, expected {t_expected}")
                for name, values in point_data.items():
                    if len(values) != points:
                        fail(f"{path}: frame {k}: {name} has {len(values)} values for {points}")
                vectors = ["velocity"] if series != "grid" else ["velocity_solid",
                                                                 "velocity_liquid"]
                for name in vectors:
                    if point_data[name].shape != (points, 2):
                        fail(f"{path}: {name} {point_data[name].shape}, expected ({points}, 2)")
                if series == "solid" and point_data["stress"].shape != (points, 6):
                    fail(f"{path}: stress {point_data['stress'].shape}, expected ({points}, 6)")
            # The grid at t = 0 is the projection of the points: all of their mass is there.
            if series == "grid":
                _, point_data, _ = reader.read_data(0)
                if not point_data["mass_solid"].sum() > 0:
                    fail(f"{path}: no solid mass on the grid at t = 0")
    # Units on every dataset of every step file.
    import glob
    for name in sorted(glob.glob(f"{directory}/step_*.h5")):
        with h5py.File(name, "r") as f:
            missing = []
            f.visititems(lambda n, o: missing.append(n)
                         if isinstance(o, h5py.Dataset) and "unit" not in o.attrs else None)
            if missing:
                fail(f"{name}: no unit on {missing[:5]}")
    print(f"check_xdmf: {len(times)} frames of solid, liquid and grid open with meshio "
          f"{meshio.__version__}")


if __name__ == "__main__":
    main()
