"""Pooling DEM runs of one scene on several beds (dem.seed), and the two fits the depth study
makes of them (a power law, a line): studies/depth/plot_depth_study.py, studies/lammps,
studies/preparation.

A run's block standard error (/means drag_stderr, lift_stderr) measures the time-average
fluctuation on one bed; how a bed was packed moves the mean further (docs/crosscheck.md: seed
pairs 2.5-3 combined errors apart). So a pooled result is the mean over beds with, as its
error, the larger of
  - the between-bed standard error, std(bed means, ddof=1) / sqrt(N), and
  - the within-bed one, sqrt(sum e_i^2) / N,
both kept so a table can show which one dominates.
"""
import math

import numpy as np

from grainlift.stats import pooled_mean

SCALARS = ("drag", "lift")
ARRAYS = ("sn", "sym", "anti", "fp", "fsyy")


def pooled_error(values, errors):
    """(error, between-bed error, within-bed error) of the mean of N bed values with block
    errors `errors`, as the module docstring says (grainlift.stats.pooled_mean); between is
    nan for one bed."""
    p = pooled_mean(values, errors)
    return p.error, p.between, p.within


def mean_and_between(values):
    """(mean, between-bed standard error std(ddof=1) / sqrt(N)) of N bed values; nan error for
    one bed. The studies that compare beds by their spread alone (lammps_study.py,
    preparation_study.py) use this."""
    p = pooled_mean(values)
    return p.mean, p.between


def pool(members):
    """One run dict from the runs of one scene on N beds (read_run dicts): scalars and
    surface/field arrays averaged, errors as in the module docstring; 'beds' = N, and for each
    scalar X the keys X_err_between (nan for one bed), X_err_within."""
    r = dict(members[0])
    r["beds"] = len(members)
    if len(members) == 1:
        for k in SCALARS:
            r[k + "_err_between"], r[k + "_err_within"] = float("nan"), r[k + "_err"]
        return r
    for k in SCALARS:
        p = pooled_mean([m[k] for m in members], [m[k + "_err"] for m in members])
        r[k] = p.mean
        r[k + "_err"], r[k + "_err_between"], r[k + "_err_within"] = p.error, p.between, p.within
    for k in ARRAYS:
        if all(k in m for m in members):
            r[k] = np.mean([m[k] for m in members], axis=0)
    if all(m.get("sn_err") is not None for m in members):  # pooled_mean's rule, per angle
        stack = np.array([m["sn"] for m in members])
        within = np.sqrt(np.sum(np.square([m["sn_err"] for m in members]), axis=0)) / len(members)
        between = np.std(stack, axis=0, ddof=1) / math.sqrt(len(members))
        r["sn_err"] = np.maximum(within, between)
    for k in ("wall_s", "far_field", "lid_mean", "lift_fields"):
        if all(k in m for m in members):
            r[k] = float(np.mean([m[k] for m in members]))
    r["Cd"] = r["drag"] / (r["rgD"] * r["h"]) if r["h"] > 0 else float("nan")
    return r


def pool_series(runs, base, extras, pooled_name):
    """Adds to runs (keyed (series, name)) a series pooled_name holding, for every run name of
    base, the pool of it and the runs of the same name in the extras series (when none of them
    has it, the base run alone, beds = 1). Nothing is added when no extras series exists."""
    if not any(k[0] in extras for k in runs):
        return runs
    for (s, name), r in list(runs.items()):
        if s == base:
            others = [runs[(e, name)] for e in extras if (e, name) in runs]
            runs[(pooled_name, name)] = pool([r] + others)
    return runs


def power_law(x, y, yerr):
    """Weighted least-squares fit of ln y = a ln x + c with sigma(ln y) = yerr / y: (a, error
    of a). The error is scaled by sqrt(chi2 / dof) when that exceeds 1."""
    lx, ly = np.log(np.asarray(x, float)), np.log(np.asarray(y, float))
    w = (np.asarray(y, float) / np.asarray(yerr, float)) ** 2
    A = np.vstack([lx, np.ones_like(lx)]).T
    cov = np.linalg.inv(A.T @ (A * w[:, None]))
    coef = cov @ (A.T @ (w * ly))
    dof = len(lx) - 2
    scale = 1.0
    if dof > 0:
        chi2 = float(np.sum(w * (ly - A @ coef) ** 2))
        scale = max(1.0, math.sqrt(chi2 / dof))
    return float(coef[0]), float(math.sqrt(cov[0, 0]) * scale)


def line_fit(x, y, yerr):
    """Weighted least-squares line y = a + b x: (a, error of a, b, error of b, chi2 / dof).
    The errors are not rescaled; chi2 / dof says whether the line is consistent with them."""
    x, y, w = np.asarray(x, float), np.asarray(y, float), 1 / np.asarray(yerr, float) ** 2
    A = np.vstack([np.ones_like(x), x]).T
    cov = np.linalg.inv(A.T @ (A * w[:, None]))
    a, b = cov @ (A.T @ (w * y))
    dof = len(x) - 2
    chi2 = float(np.sum(w * (y - a - b * x) ** 2))
    return (float(a), float(math.sqrt(cov[0, 0])), float(b), float(math.sqrt(cov[1, 1])),
            chi2 / dof if dof > 0 else float("nan"))
