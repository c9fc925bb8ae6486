"""The hydrostatic check of a DEM bed under a lid and gravity, for
studies/depth/plot_depth_study.py.

Across a horizontal line through the whole (periodic) width, the time-averaged vertical stress
carries everything above it: the lid's pressure, the weight of the grains between the line and
the lid, and, below the intruder's centre, the intruder's own vertical force on the grains (its
lift L, pushed down onto the bed: +L / W). So with the DEM's own fields (the area fraction phi
and the contact stress sigma_yy on the intruder-frame grid, which must span the bed up to the
lid) the expected whole-width stress is

    sigma_yy(y) = p_lid + rho_s g int_y^top <phi>(y') dy' + [y < y_c] L / W,

with nothing taken from the case's nominal numbers. The bed's pressure at the intruder's depth
(its overburden) is the same sum from the centre line, over columns clear of the intruder; the
loader's equivalent depth assumes instead a real bed reaching the box top at the nominal area
fraction.

The run dict (read_run of plot_depth_study.py) must hold fx, fy (grid centres), fphi, fsyy
(compressive positive), lid_mean (Pa, nan without a lid), rho_s, g_grains, width, lift (or
lift_fields, the lift over the fields' averaging window, when the two windows differ), D and
top (the box top above the intruder's centre, m).
"""

import numpy as np

# Bands inside the bed (in D from the intruder's centre), from the bottom of the field grid to
# 0.75 D above the centre. Higher up the free-disk lid is not flat: it bulges to 2 D over the
# intruder and sinks to 1.2 D far from it at h = 12 D, so a whole-width line there crosses the
# lid's disks, whose imposed force is no contact stress.
BED_BANDS = ((-2.0, -1.5), (-1.5, -1.0), (-1.0, -0.5), (-0.5, 0.0), (0.0, 0.5), (0.5, 0.75))


def _integral_above(phi_rows, dy):
    """Integral of phi from each row's centre to the top of the grid."""
    above = np.cumsum((phi_rows * dy)[::-1])[::-1]
    return above - 0.5 * phi_rows * dy


def grid_holds_the_bed(r):
    """The field grid spans the box's whole (periodic) width and reaches its top, so that it
    holds every grain above a horizontal line."""
    if "fphi" not in r:
        return False
    dx, dy = float(r["fx"][1] - r["fx"][0]), float(r["fy"][1] - r["fy"][0])
    span = float(r["fx"][-1] - r["fx"][0]) + dx
    return span >= r["width"] * (1 - 1e-6) and float(r["fy"][-1]) + 0.5 * dy >= r["top"] - 1e-9


def bed_balance(r):
    """Whole-width vertical stress in the bands BED_BANDS against the force balance above:
    band centres y, measured and expected stress, the largest relative deviation, and the
    bed's gradient below the intruder over rho_s <phi> g (1 for a hydrostatic column) and
    over the nominal rho g."""
    if not grid_holds_the_bed(r) or "fsyy" not in r:
        return None
    D, y = r["D"], r["fy"]
    dy = float(y[1] - y[0])
    phi = r["fphi"].mean(axis=1)
    syy = r["fsyy"].mean(axis=1)
    lid = 0.0 if r["lid_mean"] != r["lid_mean"] else r["lid_mean"]
    g = r["g_grains"]
    lift = r.get("lift_fields", r["lift"])  # the lift over the fields' own averaging window
    expected = (lid + r["rho_s"] * g * _integral_above(phi, dy)
                + np.where(y < 0, lift / r["width"], 0.0))
    yb, sb, eb = [], [], []
    for lo, hi in BED_BANDS:
        rows = (y >= lo * D) & (y < hi * D)
        yb.append(0.5 * (lo + hi) * D)
        sb.append(float(syy[rows].mean()))
        eb.append(float(expected[rows].mean()))
    yb, sb, eb = np.array(yb), np.array(sb), np.array(eb)
    below = yb < 0
    slope = -np.polyfit(yb[below], sb[below], 1)[0]
    rows_below = (y >= BED_BANDS[0][0] * D) & (y < -0.5 * D)
    rho_bed = r["rho_s"] * float(phi[rows_below].mean())
    return {
        "y": yb, "syy": sb, "expected": eb,
        "max_dev": float(np.max(np.abs(sb / eb - 1))),
        "slope_over_bed": slope / (rho_bed * g) if g > 0 else float("nan"),
        "slope_over_nominal": slope / (r["rho"] * g) if g > 0 else float("nan"),
    }


def overburden(r):
    """The bed's mean vertical load at the intruder's depth: the lid's pressure plus the weight
    per unit width of the grains above the centre line (Pa), and the real bed above the centre
    as a height at the bed's own packing (the grains' area above the line over the width and
    over the mean area fraction between 0.5 D and 0.75 D above the centre), in m. None without
    a grid holding the bed."""
    if not grid_holds_the_bed(r):
        return None
    D, y = r["D"], r["fy"]
    dy = float(y[1] - y[0])
    phi = r["fphi"].mean(axis=1)
    lid = 0.0 if r["lid_mean"] != r["lid_mean"] else r["lid_mean"]
    area = float(np.sum(phi[y >= 0]) * dy)
    bulk = float(phi[(y >= 0.5 * D) & (y < 0.75 * D)].mean())
    return {"load": lid + r["rho_s"] * r["g_grains"] * area, "surface": area / bulk}
