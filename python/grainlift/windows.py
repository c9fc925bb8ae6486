"""Means of a DEM run's force samples over a window of the intruder's travel, with block
errors by grainlift.stats.block_mean: the depth, one-box and co-moving-window studies."""
import numpy as np

from grainlift.stats import block_mean


def window_mean(travel, x, lo, hi, block=4.0):
    """Mean of x over lo <= travel < hi (grain diameters) and its standard error from blocks
    of about `block` grain diameters of travel (the files' own: 20 blocks over 80 d), at least
    two; stats.block_mean's rule, its correlation-corrected error (the one the DEM writes in
    /means)."""
    travel, x = np.asarray(travel), np.asarray(x)
    sel = x[(travel >= lo) & (travel < hi)]
    b = block_mean(sel, max(2, int(round((hi - lo) / block))))
    return b.mean, b.stderr_corrected
