"""matplotlib helpers shared by the report, the product's plots and the studies.

Importing this module selects the Agg backend (files only, no display); use its plt."""
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402,F401  (re-exported)
import numpy as np  # noqa: E402

from . import files  # noqa: E402

THETA_TICKS = range(-180, 181, 60)


def theta_degrees(theta):
    """Angles of /surface/theta (rad, 0..2 pi) in degrees from V in (-180, 180], and the order
    that sorts them."""
    theta = np.asarray(theta)
    deg = np.degrees(np.where(theta > np.pi, theta - 2 * np.pi, theta))
    return deg, np.argsort(deg)


def theta_axis(ax, label=True):
    """An axis of angle from V: -180..180 degrees, ticks every 60, a zero line."""
    ax.axhline(0, color="0.6", lw=0.5)
    ax.set_xlim(-180, 180)
    ax.set_xticks(THETA_TICKS)
    if label:
        ax.set_xlabel("theta from V (deg)")


def field_extent(x, y, D):
    """imshow extent in units of D of the cell-centred field grid x (nx), y (ny) (m)."""
    return [(x[0] - (x[1] - x[0]) / 2) / D, (x[-1] + (x[1] - x[0]) / 2) / D,
            (y[0] - (y[1] - y[0]) / 2) / D, (y[-1] + (y[1] - y[0]) / 2) / D]


def save(fig, path, dpi=120):
    """Writes @p fig to @p path (atomically: a failed write keeps the old file), closes it;
    the path."""
    fmt = os.path.splitext(path)[1].lstrip(".") or "png"
    try:
        files.write_atomically(path, lambda tmp: fig.savefig(tmp, dpi=dpi, format=fmt))
    finally:
        plt.close(fig)
    return path


def save_in(fig, folder, name, dpi=120):
    """save() into @p folder under @p name."""
    return save(fig, os.path.join(folder, name), dpi)
