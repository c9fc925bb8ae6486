"""The grains' friction at the intruder's surface: an effective wall friction mu_w measured on a
DEM run's surface stress, and the nominal slip speed of the surface against the grains.

    from grainlift import wall
    w = wall.wall_friction(theta, sigma_n, sigma_t, sigma_n_err, sigma_t_err)
    w.mu, w.error, w.error_independent, w.angles

Signs are docs/conventions.md's: sigma_n compressive positive, sigma_t positive when the medium
pulls the surface counter-clockwise, theta from V counter-clockwise. A Coulomb wall of friction
mu_w that slides everywhere carries |sigma_t| = mu_w sigma_n; where it sticks, less.
Pure numpy; no file is read here (grainlift.io reads the files)."""
from collections import namedtuple

import numpy as np

from grainlift import stats  # the pooling rule of every grainlift statistic

#: Angles whose sigma_n is at least this fraction of the largest sigma_n enter mu_w.
THRESHOLD = 0.5

WallFriction = namedtuple("WallFriction", "mu error error_independent angles theta_lo theta_hi")
WallFriction.__doc__ = """The effective wall friction of one surface distribution.

mu: sum |sigma_t| / sum sigma_n over the angles S with sigma_n >= threshold max sigma_n, i.e.
    the mean of the local ratio |sigma_t| / sigma_n weighted by sigma_n (the normal load);
error: its standard error with the per-angle errors taken as fully correlated (summed
    linearly over S, then the two relative errors in quadrature): an upper bound, since
    neighbouring angles share contacts through the kernel and blocks load every angle together;
    NaN without per-angle errors;
error_independent: the same with the per-angle errors independent (summed in quadrature): a
    lower bound;
angles: the number of angles in S; theta_lo, theta_hi: the smallest and largest theta in S
    (rad, in (-pi, pi])."""


def wrap(theta):
    """Angles in (-pi, pi]."""
    t = np.angle(np.exp(1j * np.asarray(theta, float)))
    return np.where(t <= -np.pi, np.pi, t)


def slip_speed(theta, spin_ratio):
    """Nominal slip speed of the intruder's surface against the grains, over V (ccw positive).

    The surface moves at omega R along t = z x n; grains arriving at -V (the intruder frame's
    far field, not slowed, not spinning) move along t at V sin(theta). The slip is
    omega R - V sin(theta), over V: Omega - sin(theta). It spans Omega -+ 1 (omega R -+ V); a
    Coulomb wall then carries sigma_t = -mu_w sigma_n sign(slip)."""
    return spin_ratio - np.sin(np.asarray(theta, float))


def loaded(sigma_n, threshold=THRESHOLD):
    """The mask of the angles whose sigma_n is at least threshold times its largest value."""
    sn = np.asarray(sigma_n, float)
    return sn >= threshold * np.max(sn)


def wall_friction(theta, sigma_n, sigma_t, sigma_n_err=None, sigma_t_err=None,
                  threshold=THRESHOLD):
    """The effective wall friction mu_w = sum_S |sigma_t| / sum_S sigma_n (WallFriction).

    @param theta angles (rad); @param sigma_n, sigma_t the surface stresses there (Pa);
    @param sigma_n_err, sigma_t_err their per-angle standard errors (Pa), or None;
    @param threshold the fraction of the largest sigma_n an angle must carry to count.
    Weighting by sigma_n gives each angle its share of the normal load, which is what a
    Coulomb wall's friction multiplies: mu_w is the friction a wall needs to carry the same
    tangential load on the loaded part of the surface."""
    th = wrap(theta)
    sn = np.asarray(sigma_n, float)
    st = np.asarray(sigma_t, float)
    s = loaded(sn, threshold)
    num, den = float(np.sum(np.abs(st[s]))), float(np.sum(sn[s]))
    mu = num / den
    err = err_ind = float("nan")
    if sigma_n_err is not None and sigma_t_err is not None:
        en = np.asarray(sigma_n_err, float)[s]
        et = np.asarray(sigma_t_err, float)[s]
        rel = np.hypot(np.sum(et) / num, np.sum(en) / den)
        rel_ind = np.hypot(np.sqrt(np.sum(et ** 2)) / num, np.sqrt(np.sum(en ** 2)) / den)
        err, err_ind = mu * float(rel), mu * float(rel_ind)
    return WallFriction(mu, err, err_ind, int(np.sum(s)), float(np.min(th[s])),
                        float(np.max(th[s])))


def directed_friction(theta, sigma_n, sigma_t, spin_ratio, threshold=THRESHOLD):
    """-sum_S sign(slip) sigma_t / sum_S sigma_n: mu_w counted with the sign a Coulomb wall
    gives sigma_t (against the nominal slip, slip_speed). Equal to wall_friction's mu where
    the tangential stress opposes the nominal slip at every loaded angle, smaller where it
    does not (grains carried with the surface, or rolling on it)."""
    sn = np.asarray(sigma_n, float)
    st = np.asarray(sigma_t, float)
    s = loaded(sn, threshold)
    sign = np.sign(slip_speed(theta, spin_ratio))[s]
    return float(-np.sum(sign * st[s]) / np.sum(sn[s]))


def peak_ratio(sigma_n, sigma_t):
    """max |sigma_t| / max sigma_n: the tangential stress's peak in units of the normal
    stress's peak (docs/crosscheck.md's "peaks at 0.22 sigma_n")."""
    return float(np.max(np.abs(sigma_t)) / np.max(sigma_n))


def saturating_fit(x, y, err):
    """Weighted least squares of y = a + (b - a) x / (x + c) (a mu(I)-like saturation in a slip
    speed x >= 0) over c on a grid (0.05 to 20, logarithmic), a and b linear.

    Returns (a, b, c, a_err, b_err, chi2 per degree of freedom); a_err, b_err from the
    covariance of the linear part at the best c, scaled by sqrt(chi2/dof) when above 1."""
    x, y, w = (np.asarray(v, float) for v in (x, y, err))
    best = None
    for c in np.geomspace(0.05, 20, 400):
        f = x / (x + c)
        a_mat = np.column_stack([1 - f, f]) / w[:, None]
        coef, *_ = np.linalg.lstsq(a_mat, y / w, rcond=None)
        chi2 = float(np.sum((a_mat @ coef - y / w) ** 2))
        if best is None or chi2 < best[0]:
            best = (chi2, coef, c, a_mat)
    chi2, coef, c, a_mat = best
    dof = max(1, len(x) - 3)
    cov = np.linalg.inv(a_mat.T @ a_mat) * max(1.0, chi2 / dof)
    return (float(coef[0]), float(coef[1]), float(c), float(np.sqrt(cov[0, 0])),
            float(np.sqrt(cov[1, 1])), chi2 / dof)


SlipLaw = namedtuple("SlipLaw", "mu_a mu_b v0 mu_a_err mu_b_err v0_err chi2_per_dof points")
SlipLaw.__doc__ = """The grains' friction at the surface against the slip speed v (m/s):

    mu_w(v) = mu_a + (mu_b - mu_a) |v| / (|v| + v0)

mu_a: the friction of a surface that does not slip (grains rolling on it or carried with it);
mu_b: the friction of a fast slip; v0 (m/s): the slip speed of the half-way point; *_err:
their standard errors (the three-parameter covariance at the optimum, scaled by sqrt(chi2/dof)
when above 1); chi2_per_dof; points: how many (v, ratio) pairs were fitted."""


def slip_law(v, ratio, err):
    """Fit mu_w(v) = mu_a + (mu_b - mu_a) |v| / (|v| + v0) (SlipLaw) to the local friction
    @p ratio = |sigma_t| / sigma_n (standard errors @p err) against the slip speed @p v (m/s).

    v is scaled by its median |v| so that saturating_fit's grid of x0 (0.05 to 20) covers it;
    v0 = x0 times that scale. The errors come from the full Jacobian [1 - f, f, d/dv0] at the
    best fit (a, b and v0 together), not from the linear part alone."""
    v, y, e = (np.abs(np.asarray(q, float)) for q in (v, ratio, err))
    y = np.asarray(ratio, float)
    moving = v[v > 0]
    scale = float(np.median(moving)) if len(moving) else 1.0
    x = v / scale
    a, b, c, _, _, chi = saturating_fit(x, y, e)
    f = x / (x + c)
    jac = np.column_stack([1 - f, f, -(b - a) * x / (x + c) ** 2]) / e[:, None]
    cov = np.linalg.inv(jac.T @ jac) * max(1.0, chi)
    err3 = np.sqrt(np.diag(cov))
    return SlipLaw(a, b, c * scale, float(err3[0]), float(err3[1]), float(err3[2] * scale),
                   chi, len(x))


def slip_law_value(law, v):
    """mu_w at slip speed(s) @p v (m/s) of a SlipLaw."""
    s = np.abs(np.asarray(v, float))
    return law.mu_a + (law.mu_b - law.mu_a) * s / (s + law.v0)


def wall_table(law, friction, friction_err, source=""):
    """The `[wall]` table of a rheology file (docs/case-format.md, `continuum.wall_law =
    "measured"`) for a SlipLaw and the effective constant friction (wall_friction's mu, or
    several runs' stats.pooled_mean) with its error. @p source: a free comment line."""
    lines = ["", "[wall]"]
    if source:
        lines.insert(1, f"# {source}")
    for key, value in (("friction", friction), ("friction_err", friction_err),
                       ("mu_a", law.mu_a), ("mu_a_err", law.mu_a_err), ("mu_b", law.mu_b),
                       ("mu_b_err", law.mu_b_err), ("v0", law.v0), ("v0_err", law.v0_err),
                       ("chi2_per_dof", law.chi2_per_dof)):
        lines.append(f"{key} = {float(value):.17g}")
    lines.append(f"points = {int(law.points)}")
    return "\n".join(lines) + "\n"


def slip_at(theta, theta_lo, theta_hi, slip_velocity):
    """The measured slip velocity (m/s, /histogram/slip_velocity: the surface against the
    grains' contact points, ccw positive) at angles @p theta (rad): the bins' means
    interpolated linearly between bin centres, periodic in theta."""
    c = 0.5 * (np.asarray(theta_lo, float) + np.asarray(theta_hi, float))
    return np.interp(wrap(theta), c, np.asarray(slip_velocity, float), period=2 * np.pi)


def measured_points(results, threshold=THRESHOLD):
    """(|v_s|, ratio, error) at every loaded angle of the DEM results (grainlift.io.Result)
    that recorded the slip velocity: v_s (m/s) the measured slip at that angle (slip_at),
    ratio = |sigma_t| / sigma_n with its error from the per-angle block errors; None when no
    result has /histogram/slip_velocity."""
    vs, ys, es = [], [], []
    for r in results:
        if "histogram/slip_velocity" not in r:
            continue
        th, sn, st = r["surface/theta"], r["surface/sigma_n"], r["surface/sigma_t"]
        en, et = r["surface/sigma_n_stderr"], r["surface/sigma_t_stderr"]
        s = loaded(sn, threshold)
        h = r["histogram"]
        vs.append(np.abs(slip_at(th[s], h["theta_lo"], h["theta_hi"], h["slip_velocity"])))
        ys.append(np.abs(st[s]) / sn[s])
        es.append(np.hypot(et[s], ys[-1] * en[s]) / sn[s])
    if not vs:
        return None
    return np.concatenate(vs), np.concatenate(ys), np.concatenate(es)


WallFit = namedtuple("WallFit", "law friction friction_err runs")
WallFit.__doc__ = """The wall law of several DEM runs (fit): the slip law (SlipLaw) on the
measured slip at every loaded angle, and the effective constant friction, the pooled mean
(grainlift.stats.pooled_mean) of the runs' wall_friction; runs: how many had the slip."""


def fit(results, threshold=THRESHOLD):
    """The WallFit of the DEM results that recorded /histogram/slip_velocity; raises
    ValueError when none did (runs of grainlift before the slip histogram)."""
    pts = measured_points(results, threshold)
    if pts is None:
        raise ValueError("no run has /histogram/slip_velocity (rerun the DEM with this grainlift)")
    used = [r for r in results if "histogram/slip_velocity" in r]
    ws = [wall_friction(r["surface/theta"], r["surface/sigma_n"], r["surface/sigma_t"],
                        r["surface/sigma_n_stderr"], r["surface/sigma_t_stderr"], threshold)
          for r in used]
    p = stats.pooled_mean([w.mu for w in ws], [w.error for w in ws])
    return WallFit(slip_law(*pts), p.mean, p.error, len(used))


def table_problem(f):
    """Why the WallFit @p f cannot be a [wall] table (the ranges read_rheology_file accepts:
    friction, mu_a, mu_b >= 0, v0 > 0, finite errors >= 0, points >= 4), or ""."""
    law = f.law
    for name, value, ok in (("friction", f.friction, f.friction >= 0),
                            ("friction_err", f.friction_err, f.friction_err >= 0),
                            ("mu_a", law.mu_a, law.mu_a >= 0), ("mu_b", law.mu_b, law.mu_b >= 0),
                            ("v0", law.v0, law.v0 > 0), ("mu_a_err", law.mu_a_err,
                                                         law.mu_a_err >= 0),
                            ("mu_b_err", law.mu_b_err, law.mu_b_err >= 0),
                            ("v0_err", law.v0_err, law.v0_err >= 0),
                            ("points", law.points, law.points >= 4)):
        if not (np.isfinite(value) and ok):
            return f"{name} = {value:.4g} is outside what a [wall] table accepts"
    return ""


def with_wall_table(text, table):
    """The rheology file's @p text with its [wall] table (and the comments just above it)
    replaced by @p table (wall_table's), or @p table appended."""
    lines = text.rstrip("\n").split("\n")
    if "[wall]" in lines:
        i = lines.index("[wall]")
        end = next((k for k in range(i + 1, len(lines)) if lines[k].startswith("[")),
                   len(lines))
        while end > i + 1 and lines[end - 1].startswith("#"):  # the next table's comments
            end -= 1
        while i > 0 and lines[i - 1].startswith("#"):
            i -= 1
        lines = lines[:i] + lines[end:]
    return "\n".join(lines).rstrip("\n") + "\n" + table
