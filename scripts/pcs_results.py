#!/usr/bin/python3
"""Read the project's HDF5 results as pandas DataFrames, with units.

tlm_host's results (host.h5, results.h5, reference.h5) and fe_server's
(fe.h5, fe_results.h5) are time series: one 1-D dataset per series, its
unit in the attribute `unit`, and its time axis named by the attribute
`time` ("/time", "/time_nodes", "/time_elements"). fe_server writes at up
to three rates, so one file can hold several time axes, often of equal
length: a series is paired with its axis by that attribute, never by its
length. (Files written before the attribute existed are paired by length
where exactly one axis fits; where two fit, the reader refuses rather than
guess.)

In Python:

    import sys; sys.path.insert(0, "scripts")
    import pcs_results
    r = pcs_results.load("out/hammer/150bar_6.0mm/tlm10/fe.h5")
    r.producer                      # 'fe_server' or 'tlm_host'
    r.axes                          # {'/time': 8199, '/time_elements': 204997, ...}
    ports = r.frame("ports")        # columns below ports/, indexed by time [s]
    ports.attrs["units"]["cavA.c"]  # 'Pa'
    fy = r.series("sections/101/fy")  # one series; fy.attrs["unit"] == 'N'

From a shell, a listing of what a file holds (axes, series, units):

    scripts/pcs_results.py FILE [GROUP]
    scripts/pcs_results.py FILE GROUP --csv OUT.csv   # that group as CSV

Values are in SI units, as written; pressures are absolute.
"""
import argparse
import sys

import h5py
import numpy as np
import pandas as pd


class ResultsError(ValueError):
    """A file or a request the reader cannot answer without guessing."""


def _text(v):
    return v.decode() if isinstance(v, bytes) else str(v)


class Results:
    """One results file, read into memory series by series on request."""

    def __init__(self, path):
        self.path = str(path)
        import os
        if not os.path.exists(self.path):
            raise ResultsError(f"{self.path}: no such file")
        if not os.path.isfile(self.path):
            raise ResultsError(f"{self.path}: not a regular file")
        try:
            self._h5 = h5py.File(self.path, "r")
        except OSError:
            # a file still being written (or cut by kill -9) is marked as open
            # for writing; the writers use SWMR, so it reads in that mode
            try:
                self._h5 = h5py.File(self.path, "r", swmr=True)
            except OSError as e:
                raise ResultsError(f"{self.path}: cannot open as HDF5 ({e})") from None
        self.attrs = {k: _text(v) for k, v in self._h5.attrs.items()}
        self.producer = self.attrs.get("producer", "")
        self._series = {}  # path without leading '/' -> dataset
        self._h5.visititems(self._collect)
        if "time" not in self._series:
            raise ResultsError(f"{self.path}: no 'time' series: not a tlm_host or fe_server results file")
        axis_names = {"/" + n for n in self._series if n == "time" or n.startswith("time_")}
        for d in self._series.values():  # the axes the series name, even if not time_*
            if "time" in d.attrs:
                axis_names.add(_text(d.attrs["time"]))
        self.axes = {a: self._h5[a].shape[0] for a in sorted(axis_names) if a.lstrip("/") in self._series}

    def _collect(self, name, obj):
        if isinstance(obj, h5py.Dataset) and obj.ndim == 1:
            self._series[name] = obj

    def close(self):
        self._h5.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def names(self, group=""):
        """Every series below `group` (all if empty), the time axes excluded."""
        prefix = group.strip("/")
        out = []
        for n in self._series:
            if "/" + n in self.axes:
                continue
            if not prefix or n == prefix or n.startswith(prefix + "/"):
                out.append(n)
        return sorted(out)

    def unit(self, name):
        d = self._dataset(name)
        return _text(d.attrs.get("unit", ""))

    def axis(self, name):
        """The path of the time axis series `name` is sampled on."""
        d = self._dataset(name)
        if "time" in d.attrs:
            a = _text(d.attrs["time"])
            if a not in self.axes:
                raise ResultsError(f"{self.path}: {name} names the time axis {a}, which the file does not have")
            return a
        fits = [a for a, n in self.axes.items() if n == d.shape[0]]
        if len(fits) == 1:
            return fits[0]
        if not fits:
            raise ResultsError(f"{self.path}: {name} has {d.shape[0]} rows and no time axis that long "
                               f"({', '.join(f'{a}: {n}' for a, n in self.axes.items())})")
        raise ResultsError(f"{self.path}: {name} has no 'time' attribute and {d.shape[0]} rows, as "
                           f"{' and '.join(fits)} do: which one is its axis cannot be told (a file written "
                           "before the series named their axes; read it with h5py and the writer's docs)")

    def _dataset(self, name):
        key = name.strip("/")
        if key not in self._series:
            close = [n for n in self._series if n.endswith("/" + key.split("/")[-1])][:5]
            hint = f"; series of that name: {', '.join(close)}" if close else ""
            raise ResultsError(f"{self.path}: no series '{name}'{hint}")
        return self._series[key]

    def time(self, axis="/time"):
        a = "/" + axis.strip("/")
        if a not in self.axes:
            raise ResultsError(f"{self.path}: no time axis {a} (it has {', '.join(self.axes)})")
        return np.asarray(self._h5[a][:])

    def series(self, name):
        """One series as a pandas Series indexed by its own time [s]; attrs: unit, axis."""
        a = self.axis(name)
        d = self._dataset(name)
        t = self.time(a)
        s = pd.Series(np.asarray(d[:]), index=pd.Index(t, name=f"{a.lstrip('/')} [s]"), name=name.strip("/"))
        s.attrs["unit"] = self.unit(name)
        s.attrs["axis"] = a
        return s

    def frame(self, group="", axis=None):
        """The series below `group` as one DataFrame indexed by their time [s].

        Columns are the names relative to the group. The series must share one
        time axis; where they do not, give `axis` ("/time_elements") to take
        those on it, or read a narrower group. attrs["units"] maps each column
        to its unit, attrs["axis"] names the axis."""
        names = self.names(group)
        if not names:
            raise ResultsError(f"{self.path}: no series below '{group}' "
                               f"(groups: {', '.join(sorted({n.split('/')[0] for n in self.names()}))})")
        by_axis = {}
        for n in names:
            by_axis.setdefault(self.axis(n), []).append(n)
        if axis is not None:
            a = "/" + axis.strip("/")
            if a not in by_axis:
                raise ResultsError(f"{self.path}: no series below '{group}' on {a} "
                                   f"(they are on {', '.join(sorted(by_axis))})")
        elif len(by_axis) == 1:
            a = next(iter(by_axis))
        else:
            raise ResultsError(f"{self.path}: the series below '{group or '/'}' are on "
                               f"{len(by_axis)} time axes ({', '.join(f'{k}: {len(v)} series' for k, v in sorted(by_axis.items()))}); "
                               "give axis=... or a narrower group")
        prefix = group.strip("/")
        cut = len(prefix) + 1 if prefix else 0
        cols = {}
        units = {}
        for n in by_axis[a]:
            col = n[cut:] if n != prefix else n.split("/")[-1]
            cols[col] = np.asarray(self._series[n][:])
            units[col] = self.unit(n)
        t = self.time(a)
        for col, v in cols.items():
            if v.shape[0] != t.shape[0]:  # a file cut mid-flush: rows beyond the shorter one are not whole
                raise ResultsError(f"{self.path}: {col} has {v.shape[0]} rows where its axis {a} has {t.shape[0]}")
        df = pd.DataFrame(cols, index=pd.Index(t, name=f"{a.lstrip('/')} [s]"))
        df.attrs["units"] = units
        df.attrs["axis"] = a
        return df


def load(path):
    """Open a results file (tlm_host's or fe_server's)."""
    return Results(path)


def _listing(r, group):
    print(f"{r.path}: {r.producer or 'unknown producer'}"
          + "".join(f", {k} = {v}" for k, v in r.attrs.items() if k != "producer"))
    by_axis, unknown = {}, []
    for x in r.names(group):
        try:
            by_axis.setdefault(r.axis(x), []).append(x)
        except ResultsError:  # an older file: listed, but its axis is not guessed
            unknown.append(x)
    for a, n in r.axes.items():
        t = r.time(a)
        span = f"{t[0]:.6g} .. {t[-1]:.6g} s" if n else "empty"
        names = by_axis.get(a, [])
        print(f"\n{a}: {n} rows, {span}, {len(names)} series")
        for x in names:
            print(f"  {x} [{r.unit(x) or '-'}]")
    if unknown:
        print(f"\naxis not recorded (a file from before the series named their axes; their length fits "
              f"several axes): {len(unknown)} series")
        for x in unknown:
            print(f"  {x} [{r.unit(x) or '-'}], {r._dataset(x).shape[0]} rows")


def main(argv=None):
    import signal
    signal.signal(signal.SIGPIPE, signal.SIG_DFL)  # `... | head` ends quietly
    ap = argparse.ArgumentParser(description="List, or write as CSV, a tlm_host or fe_server results file "
                                 "(each series with its unit and time axis).")
    ap.add_argument("file")
    ap.add_argument("group", nargs="?", default="", help="only the series below this group (ports, nodes/cavA.P2)")
    ap.add_argument("--csv", metavar="OUT", help="write the group as CSV (time first; units in the header)")
    ap.add_argument("--axis", help="with --csv: the series on this time axis (/time_elements)")
    args = ap.parse_args(argv)
    try:
        with load(args.file) as r:
            if args.csv:
                df = r.frame(args.group, axis=args.axis)
                df.columns = [f"{c} [{df.attrs['units'][c]}]" if df.attrs["units"][c] else c for c in df.columns]
                df.to_csv(args.csv, float_format="%.10g")
                print(f"{args.csv}: {df.shape[1]} series, {df.shape[0]} rows on {df.attrs['axis']}")
            else:
                _listing(r, args.group)
    except ResultsError as e:
        print(f"pcs_results: {e}", file=sys.stderr)
        return 3
    return 0


if __name__ == "__main__":
    sys.exit(main())
