"""The statistics of grainlift's results: block means of a correlated series, the pooled mean of
independent beds, and Richardson extrapolation over three mesh levels.

This module is the Python mirror of the C++ module
shared/include/grainlift/shared/statistics/statistics.h (shared/src/statistics/statistics.cc): the
same rules, the same edge cases, the same order of the sums, so that both give the same numbers on
the same input (pinned to 1e-12 relative by tests/scripts/test_statistics_equal.py). Change one
only together with the other.

Pure Python (math only): it imports without numpy and accepts any sequence of numbers,
numpy arrays included.
"""
import math
from collections import namedtuple

NAN = float("nan")

#: Lag-1 autocorrelations of the block means are clipped to [0, MAX_LAG1] before the correction.
MAX_LAG1 = 0.9

BlockMean = namedtuple("BlockMean", "mean stderr lag1 stderr_corrected blocks samples")
BlockMean.__doc__ = """Mean of a correlated series and its standard errors (block_mean()).

mean: mean of the block means (the mean of the samples used);
stderr: sd(block means, ddof=1) / sqrt(B); NaN with fewer than 2 blocks;
lag1: lag-1 autocorrelation of the block means, sum (m_b - m)(m_b+1 - m) / sum (m_b - m)^2;
    0 with fewer than 3 blocks or equal block means;
stderr_corrected: stderr sqrt((1 + r) / (1 - r)), r = lag1 clipped to [0, 0.9];
blocks: B used; samples: B times the block length (the samples used)."""


def block_means(series, blocks):
    """The means of B equal contiguous blocks of series, B = min(blocks, len(series)) (at least
    1); the first len(series) % B samples are dropped so that the blocks end at the last sample
    (the end of a run is the part nearest to steady state). Empty for an empty series."""
    x = [float(v) for v in series]
    n = len(x)
    if n == 0:
        return []
    b_count = max(1, min(int(blocks), n))
    length = n // b_count
    start = n - length * b_count
    means = []
    for b in range(b_count):
        s = 0.0
        lo = start + b * length
        for i in range(lo, lo + length):
            s += x[i]
        means.append(s / length)
    return means


def block_mean_of(means, samples):
    """Mean and errors from B block means taken as one sample each (block_mean()'s rule);
    samples, the number of samples they hold, is only reported."""
    means = [float(m) for m in means]
    b_count = len(means)
    if b_count == 0:
        return BlockMean(NAN, NAN, 0.0, NAN, 0, samples)
    mean = 0.0
    for m in means:
        mean += m
    mean /= b_count
    var = 0.0
    for m in means:
        var += (m - mean) * (m - mean)
    stderr = math.sqrt(var / (b_count - 1) / b_count) if b_count >= 2 else NAN
    lag1 = 0.0
    if b_count >= 3 and var > 0:
        c1 = 0.0
        for b in range(b_count - 1):
            c1 += (means[b] - mean) * (means[b + 1] - mean)
        lag1 = c1 / var
    # AR(1): Var(mean of B) = Var(m_b) / B (1 + r) / (1 - r) for B much larger than 1 / (1 - r)
    rho = min(MAX_LAG1, max(0.0, lag1))
    corrected = stderr * math.sqrt((1 + rho) / (1 - rho))
    return BlockMean(mean, stderr, lag1, corrected, b_count, samples)


def block_mean(series, blocks):
    """Mean and standard error of a correlated time series from B equal contiguous blocks:
    block_mean_of(block_means(series, blocks)).

    The first len(series) % B samples are dropped, so that the blocks end at the last sample:
    the series is cut after its steady-state start, and the end of a run is the part nearest
    to steady state. Each block's mean counts as one sample (Flyvbjerg and Petersen 1989):
    stderr = sd(block means) / sqrt(B), valid when a block is longer than the series'
    correlation time. Where it is not, neighbouring block means are correlated; their lag-1
    autocorrelation r (clipped to [0, 0.9]) corrects the error to the AR(1) value
    stderr sqrt((1 + r) / (1 - r)), never smaller than stderr. A negative r (anticorrelation,
    or noise of the estimate) is not allowed to shrink the error; the clip at 0.9 keeps a
    short series' noisy r from blowing the error up more than sqrt(19) = 4.4 times.

    @param series samples (any sequence of numbers); @param blocks B requested (fewer are used
    when the series has fewer samples; B < 1 counts as 1).
    Returns a BlockMean; an empty series gives NaN mean and errors and 0 blocks.
    """
    means = block_means(series, blocks)
    length = len(series) // len(means) if means else 0
    return block_mean_of(means, length * len(means))


Pooled = namedtuple("Pooled", "mean error between within beds")
Pooled.__doc__ = """Mean over independent beds and its standard error (pooled_mean()).

mean: plain mean of the bed means;
error: max(between, within) of those that are finite (NaN when neither is);
between: sd(bed means, ddof=1) / sqrt(N), NaN for one bed;
within: sqrt(sum e_i^2) / N from the beds' own errors, NaN when none were given;
beds: N."""


def pooled_mean(means, errors=None):
    """Mean of N independent beds (replicas, seeds) of one scene, with its standard error.

    The mean is the plain mean of the bed means: each bed is an equally valid sample of how a
    bed can be packed, and the bed-to-bed spread is larger than a bed's own time-average error
    (docs/crosscheck.md: seed pairs 2.5-3 combined errors apart), so weighting beds by their
    inverse block variance would favour beds by their length rather than by what they show.

    Its error is the larger of two estimates:
      - between, sd(bed means, ddof=1) / sqrt(N): the scatter of the bed means holds both the
        packing spread and each bed's time-average noise, so this alone is the unbiased error
        of the mean; but from 2 or 3 beds it is itself very uncertain (1 or 2 degrees of
        freedom) and can come out near zero by chance;
      - within, sqrt(sum e_i^2) / N: the error the mean would have if the beds differed by
        their time-average noise only, a floor that the true error cannot be below.
    Adding the two in quadrature would count the time-average noise twice; taking the larger
    keeps the unbiased estimate and guards it against a lucky small scatter.

    One bed: the mean is that bed's value, between is NaN (the packing spread is unknown) and
    the error is the bed's own error (a lower bound; NaN when no errors are given).

    @param means the N bed means; @param errors their standard errors (same length), or None
    (or empty) when the beds carry none (then error = between).
    """
    v = [float(m) for m in means]
    n = len(v)
    if errors is not None and len(errors) == 0:
        errors = None  # as the C++ pooled_mean's empty vector
    if errors is not None and len(errors) != n:
        raise ValueError("pooled_mean: %d means but %d errors" % (n, len(errors)))
    if n == 0:
        return Pooled(NAN, NAN, NAN, NAN, 0)
    mean = 0.0
    for m in v:
        mean += m
    mean /= n
    between = NAN
    if n >= 2:
        ss = 0.0
        for m in v:
            ss += (m - mean) * (m - mean)
        between = math.sqrt(ss / (n - 1) / n)
    within = NAN
    if errors is not None:
        s2 = 0.0
        for e in errors:
            s2 += float(e) * float(e)
        within = math.sqrt(s2) / n
    finite = [e for e in (between, within) if math.isfinite(e)]
    return Pooled(mean, max(finite) if finite else NAN, between, within, n)


#: Observed orders accepted by richardson(): below, the differences barely shrink (not in the
#: asymptotic range); above, the last difference is small by a cancellation rather than by
#: convergence (a Q2-Q1 force converges at order 1 to 3), and the correction would be too small.
MIN_ORDER, MAX_ORDER = 0.5, 3.0

Richardson = namedtuple("Richardson", "order limit error accepted")
Richardson.__doc__ = """Richardson extrapolation of three levels (richardson()).

order: observed order p (NaN when the differences are zero or change sign);
limit: the extrapolated value if accepted, else the finest value;
error: |limit - finest| if accepted (the size of the last correction), else the last change
    |f3 - f2|;
accepted: whether the three levels passed the acceptance test."""


def richardson(h, values, min_order=MIN_ORDER, max_order=MAX_ORDER):
    """Observed order and extrapolated limit of a quantity computed on three meshes.

    h: cell sizes h1 > h2 > h3 with a constant ratio r = h1/h2 = h2/h3 (halvings: r = 2);
    values: f1, f2, f3 on them. With f = f_inf + C h^p, the differences e1 = f2 - f1 and
    e2 = f3 - f2 give p = ln(e1 / e2) / ln r and f_inf = f3 + e2 / (r^p - 1).

    Acceptance test (the one rule): e1 and e2 are non-zero with the same sign (monotone
    convergence) and min_order <= p <= max_order (default [0.5, 3]). Then the limit is
    f_inf and its error the size of the last correction |f_inf - f3|. Otherwise the levels
    are not yet in the asymptotic range: the limit is f3 itself and its error the last change
    |f3 - f2|, never an extrapolation from a sequence that does not show its order.

    Raises ValueError unless there are three positive, decreasing cell sizes with a constant
    ratio (to 1e-9 relative) and three values.
    """
    if len(h) != 3 or len(values) != 3:
        raise ValueError("richardson: needs three cell sizes and three values")
    h1, h2, h3 = (float(a) for a in h)
    f1, f2, f3 = (float(a) for a in values)
    if not (h1 > h2 > h3 > 0):
        raise ValueError("richardson: cell sizes must be positive and decreasing")
    r = h1 / h2
    if abs(h2 / h3 - r) > 1e-9 * r:
        raise ValueError("richardson: cell sizes without a constant refinement ratio")
    e1, e2 = f2 - f1, f3 - f2
    if e1 == 0 or e2 == 0 or (e1 > 0) != (e2 > 0):
        return Richardson(NAN, f3, abs(e2), False)
    p = math.log(e1 / e2) / math.log(r)
    if not min_order <= p <= max_order:
        return Richardson(p, f3, abs(e2), False)
    limit = f3 + e2 / (r ** p - 1)
    return Richardson(p, limit, abs(limit - f3), True)
