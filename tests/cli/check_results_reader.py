#!/usr/bin/env python3
"""Test of analysis/python/granflow_results.py on run directories the test made.
Usage: check_results_reader.py [--granflow BINARY] RUN_DIR KIND [RUN_DIR KIND ...]
For every run: the kind read back, every table non-empty with a unit on every column and the
columns of the file's own group (never a name list repeated here), the summary loaded; per kind,
the table a user asks for first: the DEM's /steady with one row per condition and its series with
a `condition` column, the REV's steady rows, the MPM's time series, the calibration's data and
fit, the pair's table. Also the --csv export: one CSV per table, header "name [unit]"; the
file's types (schema_version 2 an integer, string attributes str, the steady flags integers);
every dataset listed in docs/results.md under its kind with the file's unit; and, with
--granflow BINARY, `granflow export RUN_DIR --csv` against the reader's tables. Exit 1 with a
message naming the run and what failed."""
import csv
import os
import re
import subprocess
import sys
import tempfile

import h5py
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "analysis", "python"))
import granflow_results as gr  # noqa: E402


def fail(run, message):
    print(f"FAIL {run.directory if hasattr(run, 'directory') else run}: {message}")
    sys.exit(1)


RESULTS_MD = os.path.join(os.path.dirname(__file__), "..", "..", "docs", "results.md")


def documented(kind):
    """{(group, name): unit} of the tables in the `kind: KIND` section of docs/results.md; a
    group is the heading's path with /conditions/N/ dropped (a sweep's series are the single
    run's)."""
    text = open(RESULTS_MD, encoding="utf-8").read()
    section = re.search(r"^## `kind: " + kind + r"`\n(.*?)(?=^## |\Z)", text, re.S | re.M)
    if not section:
        return {}
    rows, group = {}, None
    for line in section.group(1).splitlines():
        heading = re.match(r"^#+ `(/[^`]*)`", line)
        if heading:
            group = re.sub(r"^/conditions/N", "", heading.group(1)) or "/"
            continue
        row = re.match(r"^\| `([^`]+)` \| ([^|]*) \|", line)
        if row and group:
            rows[(group, row.group(1))] = row.group(2).strip()
    return rows


def check_file(run, kind):
    """Types and documentation of every dataset of the run's result.h5."""
    rows = documented(kind)
    if not rows:
        fail(run, f"docs/results.md has no tables for kind: {kind}")
    with h5py.File(run.result_file, "r") as h5:
        version = h5.attrs.get("schema_version")
        if not isinstance(version, (int, np.integer)) or version != 2:
            fail(run, f"root schema_version {version!r}, expected the integer 2")
        if not isinstance(h5.attrs["kind"], str):
            fail(run, f"root attribute kind is {type(h5.attrs['kind']).__name__}, expected str")
        if "steady/steady_reached" in h5 and h5["steady/steady_reached"].dtype.kind != "i":
            fail(run, "/steady/steady_reached is not an integer dataset")

        def visit(name, obj):
            if not isinstance(obj, h5py.Dataset):
                return
            unit = obj.attrs.get("unit")
            if not isinstance(unit, str):
                fail(run, f"/{name}: unit attribute is {type(unit).__name__}, expected str")
            path = re.sub(r"/\d+(?=/|$)", "/N", re.sub(r"/curve_J/[^/]+", "/curve_J/L", "/" + name))
            path = re.sub(r"/group_\d+(?=/|$)", "/group_G", path)  # /transient*/group_G
            group, leaf = path.rsplit("/", 1)
            group = re.sub(r"^/conditions/N", "", group) or "/"
            if (group, leaf) not in rows:
                fail(run, f"/{name} is not listed under `{group}` of kind: {kind} in docs/results.md")
            if rows[(group, leaf)] != unit:
                fail(run, f"/{name}: unit {unit!r} in the file, {rows[(group, leaf)]!r} in docs/results.md")
        h5.visititems(visit)


def check_export(run, granflow):
    """`granflow export RUN --csv`: one CSV per table with the reader's columns and units."""
    with tempfile.TemporaryDirectory() as out:
        r = subprocess.run([granflow, "export", run.directory, "--csv", "--out", out],
                           capture_output=True, text=True)
        if r.returncode != 0:
            fail(run, f"granflow export exit {r.returncode}: {r.stderr.strip()}")
        for name in run.table_names():
            df = run.table(name)
            file = os.path.join(out, name.strip("/").replace("/", "_") + ".csv")
            if not os.path.isfile(file):
                fail(run, f"granflow export wrote no {os.path.basename(file)} for {name}")
            with open(file, encoding="utf-8") as f:
                rows = list(csv.reader(f))
            units = df.attrs["units"]
            expected = sorted(f"{c} [{units[c]}]" for c in df.columns)
            if sorted(rows[0]) != expected:
                fail(run, f"{file}: header {rows[0]} != the reader's {expected}")
            if len(rows) - 1 != len(df):
                fail(run, f"{file}: {len(rows) - 1} rows, the reader has {len(df)}")
            # The first column's values back, exactly (17 significant digits round-trip).
            column = rows[0][0].split(" [")[0]
            values = np.array([float(row[0]) for row in rows[1:]])
            if not np.array_equal(values, df[column].to_numpy(dtype=float), equal_nan=True):
                fail(run, f"{file}: {column} differs from result.h5")
        if not os.path.isfile(os.path.join(out, "attributes.csv")):
            fail(run, "granflow export wrote no attributes.csv")


def check(directory, kind, granflow=None):
    run = gr.open_run(directory)
    if run.kind != kind:
        fail(run, f"kind {run.kind!r}, expected {kind!r}")
    if not run.summary:
        fail(run, "summary.json not loaded")
    names = run.table_names()
    if not names:
        fail(run, "no table")
    for name in names:
        df = run.table(name)
        if len(df) == 0 or len(df.columns) == 0:
            fail(run, f"{name} is empty")
        for column in df.columns:
            if not df.attrs["units"].get(column):
                fail(run, f"{name}/{column} has no unit")
    if kind == "dem":
        steady = run.steady()
        conditions = run.conditions()
        if len(steady) != max(1, len(conditions)):
            fail(run, f"/steady has {len(steady)} rows for {len(conditions)} conditions")
        series = run.series()
        if "condition" not in series.columns or series["condition"].nunique() != len(steady):
            fail(run, "series() without one condition per steady row")
        if not (steady["friction"] > 0).all():
            fail(run, "steady friction not positive")
    elif kind == "rev":
        if not any(n.endswith("series") or n.endswith("steady") for n in names):
            fail(run, f"no series or steady table among {names}")
    elif kind == "mpm":
        series = run.table("/series")
        if "time" not in series.columns or not (series["time"].diff().dropna() > 0).all():
            fail(run, "/series has no increasing time")
    elif kind == "calibrate":
        for name in ("/data", "/fit"):
            if name not in names:
                fail(run, f"no {name} table")
    elif kind == "pair":
        if not names:
            fail(run, "no pair table")
    with tempfile.TemporaryDirectory() as out:
        if gr._main([directory, "--csv", out]) != 0:
            fail(run, "--csv failed")
        written = sorted(os.listdir(out))
        if len(written) != len(names):
            fail(run, f"{len(written)} CSV files for {len(names)} tables")
        with open(os.path.join(out, written[0]), encoding="utf-8") as f:
            header = f.readline()
        if "[" not in header:
            fail(run, f"CSV header without units: {header!r}")
    check_file(run, kind)
    if granflow:
        check_export(run, granflow)
    print(f"ok {directory}: {kind}, {len(names)} tables")


def main(argv):
    granflow = None
    if len(argv) >= 2 and argv[0] == "--granflow":
        granflow, argv = argv[1], argv[2:]
    if len(argv) < 2 or len(argv) % 2:
        print(__doc__)
        return 2
    for directory, kind in zip(argv[0::2], argv[1::2]):
        check(directory, kind, granflow)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
