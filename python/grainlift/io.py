"""Reading grainlift's outputs: the one place Python opens a result file.

    from grainlift import io
    r = io.read("out/demo")            # dem.h5 if present, else fem.h5; or io.read(dir, "fem")
    r.means["drag"], r["surface/sigma_n"], r.attrs("far_field"), r.has("lid")
    drag, lift = r.drag_lift()         # the force samples along and across V
    s = io.summary("out/demo", "dem")  # summary.json's "dem" object
    law = io.calibration("law.toml")   # a `grainlift calibrate` file

The layout of the files is docs/schema.md's. A file is read whole (groups, datasets and
attributes into numpy arrays and Python values; strings decoded), so nothing keeps it open."""
import csv
import json
import math
import os
import tomllib

import h5py
import numpy as np

from grainlift.stats import block_mean

SOLVERS = ("dem", "fem")


def text(v):
    """An HDF5 string (bytes or str, attribute or scalar dataset) as str."""
    if isinstance(v, np.ndarray) and v.shape == ():
        v = v[()]
    return v.decode() if isinstance(v, bytes) else str(v)


def _value(v):
    """An attribute value: strings decoded, numpy scalars left as they are."""
    return v.decode() if isinstance(v, bytes) else v


def result_path(path, solver=None):
    """The .h5 file that @p path names: the file itself, or in a folder <solver>.h5 (without a
    solver: dem.h5 if present, else fem.h5). FileNotFoundError when there is none."""
    if not os.path.isdir(path):
        if not os.path.isfile(path):
            raise FileNotFoundError(f"{path}: no such result file")
        return path
    for s in (solver,) if solver else SOLVERS:
        p = os.path.join(path, s + ".h5")
        if os.path.isfile(p):
            return p
    raise FileNotFoundError(f"{path}: no {solver or 'dem or fem'}.h5 here")


def results_in(folder):
    """{solver: path} of the result files present in @p folder (possibly empty)."""
    return {s: os.path.join(folder, s + ".h5") for s in SOLVERS
            if os.path.isfile(os.path.join(folder, s + ".h5"))}


class Group(dict):
    """A group of a Result: its datasets by name (a dict), its attributes as .attrs."""

    def __init__(self, datasets, attrs):
        super().__init__(datasets)
        self.attrs = attrs


class Result:
    """One dem.h5 or fem.h5 in memory. r["forces/fx"] is a dataset (numpy array, or str for
    a string dataset), r["fields"] a Group, r.attrs("geometry") a group's attributes (an empty
    dict when the group is absent); geometry, means, derived, diagnostics, metadata name the
    common ones. Code written for an open h5py.File reads a Result unchanged."""

    def __init__(self, path, datasets, attributes):
        self.path = path
        self._data = datasets
        self._attrs = attributes

    def __getitem__(self, name):
        n = name.strip("/")
        if n in self._data:
            return self._data[n]
        if n in self._attrs:
            return Group(self.datasets(n), self._attrs[n])
        raise KeyError(f"{self.path}: no /{n}")

    def __contains__(self, name):
        """Whether the file has the dataset or group @p name."""
        n = name.strip("/")
        return n in self._data or n in self._attrs

    has = __contains__

    def get(self, name, default=None):
        return self._data.get(name.strip("/"), default)

    def attrs(self, group):
        return self._attrs.get(group.strip("/"), {})

    def datasets(self, group):
        """{name: array} of the datasets directly in @p group."""
        prefix = group.strip("/") + "/"
        return {k[len(prefix):]: v for k, v in self._data.items()
                if k.startswith(prefix) and "/" not in k[len(prefix):]}

    def items(self):
        """(name, array) of every dataset, and the attributes of every group, as
        (group, dict) pairs: for checks that visit the whole file."""
        return list(self._data.items()), list(self._attrs.items())

    geometry = property(lambda self: self.attrs("geometry"))
    means = property(lambda self: self.attrs("means"))
    derived = property(lambda self: self.attrs("derived"))
    diagnostics = property(lambda self: self.attrs("diagnostics"))
    metadata = property(lambda self: self.attrs("metadata"))

    @property
    def solver(self):
        return text(self.metadata.get("solver", self.attrs("").get("solver", "")))

    @property
    def wall_seconds(self):
        return float(self.metadata.get("wall_seconds", float("nan")))

    def velocity(self):
        """(vx, vy) of the intruder (m/s)."""
        g = self.geometry
        return float(g["velocity_x"]), float(g["velocity_y"])

    def drag_lift(self):
        """Drag (against V) and lift (V turned +90 degrees) of every force sample (N/m)."""
        vx, vy = self.velocity()
        v = math.hypot(vx, vy)
        ex, ey = vx / v, vy / v
        fx, fy = self["forces/fx"], self["forces/fy"]
        return -(fx * ex + fy * ey), -fx * ey + fy * ex

    def block_errors(self):
        """{"drag_stderr", "lift_stderr", "torque_stderr"} of a DEM run by the one statistics
        rule (grainlift.stats.block_mean's correlation-corrected error over the file's
        averaged samples and blocks), whichever binary wrote the file: a file written since
        the rule became the DEM's (/means) holds the same numbers; an older one holds the
        uncorrected block error. Empty for a file without averaged samples (FEM, replicas)."""
        m = self.means
        n, blocks = int(m.get("samples", 0)), int(m.get("blocks", 0))
        if self.solver != "dem" or n < 2 or blocks < 2 or "forces/fx" not in self:
            return {}
        drag, lift = self.drag_lift()
        series = {"drag": drag, "lift": lift, "torque": self["forces/torque"]}
        return {k + "_stderr": block_mean(np.asarray(x)[-n:], blocks).stderr_corrected
                for k, x in series.items()}

    def travel(self):
        """The intruder's travel at every force sample, in grain diameters."""
        return (self["forces/time"] * math.hypot(*self.velocity())
                / float(self.geometry["grain_diameter"]))

    def case(self):
        """The case file as a dict (tomllib), with the run's --set overrides applied."""
        case = tomllib.loads(text(self["case/text"]))
        for line in text(self.get("case/overrides", "")).splitlines():
            key, _, value = line.partition("=")
            section, _, k = key.strip().rpartition(".")
            if not k:
                continue
            try:
                v = tomllib.loads(f"v = {value.strip()}")["v"]
            except tomllib.TOMLDecodeError:
                v = value.strip()
            node = case
            for part in section.split(".") if section else []:
                node = node.setdefault(part, {})
            node[k] = v
        return case


def read(path, solver=None):
    """The result file that @p path names (result_path) as a Result."""
    p = result_path(path, solver)
    data, attrs = {}, {}
    with h5py.File(p, "r") as f:
        attrs[""] = {k: _value(v) for k, v in f.attrs.items()}

        def visit(name, obj):
            if isinstance(obj, h5py.Dataset):
                v = obj[()]
                data[name] = text(v) if isinstance(v, bytes) else v
            if len(obj.attrs) or isinstance(obj, h5py.Group):
                attrs[name] = {k: _value(v) for k, v in obj.attrs.items()}
        f.visititems(visit)
    return Result(p, data, attrs)


def summary(folder, solver=None):
    """summary.json of a run folder; with @p solver, its object for that solver."""
    with open(os.path.join(folder, "summary.json"), encoding="utf-8") as f:
        s = json.load(f)
    return s[solver] if solver else s


def calibration(path):
    """A rheology file of `grainlift calibrate` (TOML: [mu_i], [phi_i], [source], [[point]])."""
    with open(path, "rb") as f:
        return tomllib.load(f)


def calibration_points(law):
    """The calibration's points as arrays: {"I", "mu", "mu_stderr", "phi", "phi_stderr"}."""
    pts = law.get("point", [])
    return {k: np.array([p[k] for p in pts], float)
            for k in ("I", "mu", "mu_stderr", "phi", "phi_stderr")}


def sweep_rows(path):
    """The rows of a sweep.csv (docs/schema.md) as dicts of strings."""
    with open(path, newline="", encoding="utf-8") as f:
        return list(csv.DictReader(f))
