#!/usr/bin/env python3
"""granflow_results: a granflow run directory as pandas tables with units.

    import sys; sys.path.insert(0, "<granflow>/analysis/python")
    import granflow_results as gr
    run = gr.open_run("runs/pair_dry")
    run.kind, run.test, run.name     # from the run's case.yaml
    run.case                         # the resolved case as run (dict)
    run.summary                      # summary.json (dict; absent keys were not finite)
    run.tables()                     # {"/steady": DataFrame, "/conditions/0/series": ...}
    run.table("/steady")             # one table; units in .attrs["units"], texts in
                                     # .attrs["descriptions"], the group's attributes in
                                     # .attrs["attributes"]
    run.arrays("/conditions/0/profile")  # the datasets that are not table columns (2-D, ...)
    run.series()                     # every condition's /series in one table, column "condition"
    run.steady()                     # the /steady table with the swept case keys as columns

A table is what granflow writes as one: the one-dimensional datasets of an HDF5 group that share
the group's most common length, one column each, in the order of the group's `columns`
attribute when it has one (else the file's order). Every dataset granflow writes carries `unit`
and `description` attributes, and /steady lists its columns and the swept case keys
(`columns`, `sweep_keys`); they are read, never repeated here (docs/results.md). Strings are
returned as str (variable-length UTF-8 since schema_version 2; older files' fixed-length
strings are decoded too); run.schema_version is the file's vocabulary version (1 before the
attribute existed).

As a program (no pandas needed for --list):
    granflow_results.py RUN_DIR            print each table's name, rows and columns with units
    granflow_results.py RUN_DIR --csv DIR  write one CSV per table (units in the header row:
                                           "name [unit]")
"""
import argparse
import itertools
import json
import os
import sys

import h5py
import numpy as np

__all__ = ["Run", "open_run"]


def _text(value):
    """An HDF5 attribute or string element as str (variable-length UTF-8 since schema_version 2,
    fixed-length bytes before)."""
    if isinstance(value, bytes):
        return value.decode("utf-8", errors="replace").rstrip("\x00")
    if isinstance(value, np.ndarray) and value.dtype.kind in "SO":
        return [_text(v) for v in value.tolist()]
    if isinstance(value, np.generic):
        return value.item()
    return value


def _column(dataset):
    data = dataset[()]
    if data.dtype.kind == "S":
        return np.array([_text(v) for v in data], dtype=object)
    return data


def _load_yaml(path):
    """The resolved case.yaml; PyYAML when installed, else only its top-level scalars."""
    try:
        import yaml  # python3-yaml
    except ImportError:
        yaml = None
    with open(path, encoding="utf-8") as f:
        text = f.read()
    if yaml is not None:
        return yaml.safe_load(text) or {}
    case = {}
    for line in text.splitlines():
        if line and not line[0].isspace() and ":" in line and not line.startswith("#"):
            key, _, value = line.partition(":")
            value = value.strip()
            if value:
                case[key.strip()] = value.strip("'\"")
    return case


class Run:
    """One granflow run directory (case.yaml, summary.json, result.h5)."""

    def __init__(self, directory):
        self.directory = os.fspath(directory)
        case_file = os.path.join(self.directory, "case.yaml")
        summary_file = os.path.join(self.directory, "summary.json")
        self.result_file = os.path.join(self.directory, "result.h5")
        if not os.path.isfile(self.result_file):
            raise FileNotFoundError(f"{self.result_file}: no result.h5; expected a granflow run directory")
        self.case = _load_yaml(case_file) if os.path.isfile(case_file) else {}
        self.summary = {}
        if os.path.isfile(summary_file):
            with open(summary_file, encoding="utf-8") as f:
                self.summary = json.load(f)
        with h5py.File(self.result_file, "r", locking=False) as h5:
            attrs = {k: _text(v) for k, v in h5.attrs.items()}
            self._layout = {}
            h5.visititems(self._visit)
        self.kind = str(self.case.get("kind", attrs.get("kind", "")))
        self.test = str(self.case.get("test", ""))
        self.name = str(self.case.get("name", attrs.get("case_name", "")))
        self.attributes = attrs
        self.schema_version = int(attrs.get("schema_version", 1))

    def _visit(self, name, obj):
        if isinstance(obj, h5py.Group):
            lengths = [len(d) for d in obj.values() if isinstance(d, h5py.Dataset) and d.ndim == 1]
            if lengths:
                # the most common length; ties go to the longest (a series beside a short index)
                counts = {n: lengths.count(n) for n in set(lengths)}
                length = max(counts, key=lambda n: (counts[n], n))
                self._layout["/" + name] = length

    # ---- tables ------------------------------------------------------------------------------
    def table_names(self):
        """Groups that hold a table, in the file's order."""
        return list(self._layout)

    def table(self, group):
        """The table of `group` as a pandas DataFrame (units in .attrs["units"])."""
        import pandas as pd

        group = "/" + group.strip("/")
        if group not in self._layout:
            raise KeyError(f"{self.result_file}: no table in {group}; tables: {', '.join(self._layout)}")
        length = self._layout[group]
        columns, units, descriptions = {}, {}, {}
        with h5py.File(self.result_file, "r", locking=False) as h5:
            g = h5[group]
            order = [_text(c) for c in g.attrs["columns"]] if "columns" in g.attrs else []
            keys = [k for k in order if k in g] + [k for k in g if k not in order]
            for key in keys:
                d = g[key]
                if isinstance(d, h5py.Dataset) and d.ndim == 1 and len(d) == length:
                    columns[key] = _column(d)
                    units[key] = _text(d.attrs.get("unit", ""))
                    descriptions[key] = _text(d.attrs.get("description", ""))
            attributes = {k: _text(v) for k, v in g.attrs.items()}
        df = pd.DataFrame(columns)
        df.attrs["units"] = units
        df.attrs["descriptions"] = descriptions
        df.attrs["attributes"] = attributes
        df.attrs["group"] = group
        return df

    def tables(self):
        return {name: self.table(name) for name in self._layout}

    def units(self, group):
        return self.table(group).attrs["units"]

    def arrays(self, group):
        """The datasets of `group` that are not columns of its table: {name: numpy array}."""
        group = "/" + group.strip("/")
        length = self._layout.get(group)
        out = {}
        with h5py.File(self.result_file, "r", locking=False) as h5:
            for key, d in h5[group].items():
                if isinstance(d, h5py.Dataset) and not (d.ndim == 1 and len(d) == length):
                    out[key] = d[()]
        return out

    # ---- conveniences ------------------------------------------------------------------------
    def conditions(self):
        """The swept case keys of each condition, in the order granflow runs them (the Cartesian
        product of `sweep:`, the first key varying slowest); [] for a single condition."""
        sweep = self.case.get("sweep") or {}
        if not isinstance(sweep, dict) or not sweep:
            return []
        keys = list(sweep)
        values = [v if isinstance(v, list) else [v] for v in sweep.values()]
        return [dict(zip(keys, combo)) for combo in itertools.product(*values)]

    def series(self):
        """Every condition's series in one table with a `condition` column (a single run's
        /series alone when there are no conditions)."""
        import pandas as pd

        parts = []
        for name in self._layout:
            parts_of = name.strip("/").split("/")
            if len(parts_of) == 3 and parts_of[0] == "conditions" and parts_of[2] == "series":
                df = self.table(name)
                df.insert(0, "condition", int(parts_of[1]))
                parts.append(df)
        if not parts:
            return self.table("/series")
        units = dict(parts[0].attrs["units"], condition="1")
        out = pd.concat(parts, ignore_index=True)
        out.attrs["units"] = units
        return out

    def steady(self):
        """The /steady table (one row per condition) with the swept case keys as columns where
        the table does not already carry them: from /conditions/N's attributes for the keys the
        file lists in /steady's `sweep_keys`, else from case.yaml's `sweep:`."""
        df = self.table("/steady")
        keys = df.attrs["attributes"].get("sweep_keys")
        if keys is not None and len(keys) > 0:
            with h5py.File(self.result_file, "r", locking=False) as h5:
                for key in keys:
                    if key in df.columns or key.split(".")[-1] in df.columns:
                        continue
                    values = [h5[f"conditions/{n}"].attrs.get(key, np.nan)
                              if f"conditions/{n}" in h5 else np.nan for n in range(len(df))]
                    df[key] = values
                    df.attrs["units"][key] = "case key"
            return df
        conditions = self.conditions()
        if conditions and len(conditions) == len(df):
            for key in conditions[0]:
                column = key.split(".")[-1]
                if column not in df.columns and key not in df.columns:
                    df[key] = [c[key] for c in conditions]
                    df.attrs["units"][key] = "case key"
        return df


def open_run(directory):
    return Run(directory)


def _main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("run_dir")
    parser.add_argument("--csv", metavar="DIR", help="write one CSV per table into DIR")
    args = parser.parse_args(argv)
    try:
        run = open_run(args.run_dir)
    except (OSError, FileNotFoundError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    print(f"{run.directory}: kind {run.kind}{' / ' + run.test if run.test else ''}, case '{run.name}'")
    if args.csv:
        os.makedirs(args.csv, exist_ok=True)
    for name in run.table_names():
        df = run.table(name)
        units = df.attrs["units"]
        print(f"{name}: {len(df)} rows; " + ", ".join(f"{c} [{units.get(c, '')}]" for c in df.columns))
        if args.csv:
            file = os.path.join(args.csv, name.strip("/").replace("/", "_") + ".csv")
            header = [f"{c} [{units[c]}]" if units.get(c) else c for c in df.columns]
            df.to_csv(file, index=False, header=header)
    return 0


if __name__ == "__main__":
    sys.exit(_main(sys.argv[1:]))
