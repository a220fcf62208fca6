#!/usr/bin/env python3
"""Test of analysis/python/granflow_results.py on run directories the test made.
Usage: check_results_reader.py RUN_DIR KIND [RUN_DIR KIND ...]
For every run: the kind read back, every table non-empty with a unit on every column and the
columns of the file's own group (never a name list repeated here), the summary loaded; per kind,
the table a user asks for first: the DEM's /steady with one row per condition and its series with
a `condition` column, the REV's steady rows, the MPM's time series, the calibration's data and
fit, the pair's table. Also the --csv export: one CSV per table, header "name [unit]". Exit 1
with a message naming the run and what failed."""
import os
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "analysis", "python"))
import granflow_results as gr  # noqa: E402


def fail(run, message):
    print(f"FAIL {run.directory if hasattr(run, 'directory') else run}: {message}")
    sys.exit(1)


def check(directory, kind):
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
    print(f"ok {directory}: {kind}, {len(names)} tables")


def main(argv):
    if len(argv) < 2 or len(argv) % 2:
        print(__doc__)
        return 2
    for directory, kind in zip(argv[0::2], argv[1::2]):
        check(directory, kind)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
