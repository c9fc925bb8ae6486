#include "grainlift/shared/results/compare.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "grainlift/shared/results/json_writer.h"
#include "grainlift/shared/surface/surface_stress.h"

namespace grainlift {
namespace {

constexpr double pi = 3.14159265358979323846;

std::optional<double> relative(double a, double b) {
  if (a == 0) return std::nullopt;
  return (b - a) / std::abs(a);
}

/// Periodic linear interpolation of (theta, v) at angle t.
double interpolate(const std::vector<double>& theta, const std::vector<double>& v, double t) {
  const std::size_t n = theta.size();
  if (n == 1) return v[0];
  t = std::fmod(std::fmod(t, 2 * pi) + 2 * pi, 2 * pi);
  // theta is sorted ascending within [0, 2 pi)
  auto it = std::upper_bound(theta.begin(), theta.end(), t);
  const std::size_t hi = it == theta.end() ? 0 : std::size_t(it - theta.begin());
  const std::size_t lo = hi == 0 ? n - 1 : hi - 1;
  double t0 = theta[lo], t1 = theta[hi];
  if (t1 <= t0) t1 += 2 * pi;
  double tt = t;
  if (tt < t0) tt += 2 * pi;
  const double w = (tt - t0) / (t1 - t0);
  return (1 - w) * v[lo] + w * v[hi];
}

/// (b - a) / sqrt(err_a^2 + err_b^2); absent without either error or when their sum is 0.
std::optional<double> in_error_units(double a, double b, const std::optional<double>& se_a,
                                     const std::optional<double>& se_b) {
  if (!se_a && !se_b) return std::nullopt;
  const double se = std::hypot(se_a.value_or(0.0), se_b.value_or(0.0));
  if (!(se > 0)) return std::nullopt;
  return (b - a) / se;
}

/// Root mean square and max of |d| over the grid, divided by @p P.
void norms(const std::vector<double>& d, double P, double& l2, double& max) {
  double sum = 0;
  max = 0;
  for (double x : d) {
    sum += x * x;
    max = std::max(max, std::abs(x) / P);
  }
  l2 = std::sqrt(sum / double(d.size())) / P;
}

/// The norms of d and of its symmetric and antisymmetric parts (symmetry_split).
void split_norms(const std::vector<double>& d, double P, double& l2, double& max, double& sym_l2,
                 double& sym_max, double& anti_l2, double& anti_max) {
  std::vector<double> sym, anti;
  symmetry_split(d, sym, anti);
  norms(d, P, l2, max);
  norms(sym, P, sym_l2, sym_max);
  norms(anti, P, anti_l2, anti_max);
}

/// A result's error of @p name ("drag", "lift", "torque"): the standard error of its mean, else
/// the mesh-error estimate its /diagnostics carries.
std::optional<double> error_of(const RunResult& r, const std::string& name,
                               const std::optional<double>& stderr_of_mean) {
  if (stderr_of_mean) return stderr_of_mean;
  const auto it = r.diagnostics.values.find(name + "_mesh_error");
  if (it != r.diagnostics.values.end()) return it->second;
  return std::nullopt;
}

std::string error_kind(const RunResult& r) {
  if (r.means && (r.means->drag_stderr || r.means->lift_stderr)) return "standard error";
  if (r.diagnostics.values.count("drag_mesh_error")) return "mesh-error estimate";
  return "none";
}

}  // namespace

Comparison compare_results(const RunResult& a, const RunResult& b) {
  Comparison c;
  c.solver_a = a.meta.solver;
  c.solver_b = b.meta.solver;
  if (a.means && b.means) {
    c.have_means = true;
    c.drag_a = a.means->drag;
    c.drag_b = b.means->drag;
    c.lift_a = a.means->lift;
    c.lift_b = b.means->lift;
    c.torque_a = a.means->torque;
    c.torque_b = b.means->torque;
    c.drag_rel = relative(c.drag_a, c.drag_b);
    c.lift_rel = relative(c.lift_a, c.lift_b);
    c.torque_rel = relative(c.torque_a, c.torque_b);
    c.drag_err_a = error_of(a, "drag", a.means->drag_stderr);
    c.drag_err_b = error_of(b, "drag", b.means->drag_stderr);
    c.lift_err_a = error_of(a, "lift", a.means->lift_stderr);
    c.lift_err_b = error_of(b, "lift", b.means->lift_stderr);
    c.torque_err_a = error_of(a, "torque", a.means->torque_stderr);
    c.torque_err_b = error_of(b, "torque", b.means->torque_stderr);
    c.error_kind_a = error_kind(a);
    c.error_kind_b = error_kind(b);
    c.drag_z = in_error_units(c.drag_a, c.drag_b, c.drag_err_a, c.drag_err_b);
    c.lift_z = in_error_units(c.lift_a, c.lift_b, c.lift_err_a, c.lift_err_b);
    c.torque_z = in_error_units(c.torque_a, c.torque_b, c.torque_err_a, c.torque_err_b);
  }
  if (a.surface && b.surface && !a.surface->theta.empty() && !b.surface->theta.empty()) {
    c.have_surface = true;
    if (a.geometry.pressure_scale > 0) {
      c.pressure_scale = a.geometry.pressure_scale;
      c.pressure_scale_from = "A: geometry.pressure_scale";
    } else if (b.geometry.pressure_scale > 0) {
      c.pressure_scale = b.geometry.pressure_scale;
      c.pressure_scale_from = "B: geometry.pressure_scale";
    } else {
      for (double s : a.surface->sigma_n)
        c.pressure_scale = std::max(c.pressure_scale, std::abs(s));
      c.pressure_scale_from = "A: max |sigma_n|";
    }
    const double P = c.pressure_scale > 0 ? c.pressure_scale : 1.0;
    const auto& ta = a.surface->theta;
    std::vector<double> dn(ta.size()), dt(ta.size());
    for (std::size_t m = 0; m < ta.size(); ++m) {
      dn[m] = interpolate(b.surface->theta, b.surface->sigma_n, ta[m]) - a.surface->sigma_n[m];
      dt[m] = interpolate(b.surface->theta, b.surface->sigma_t, ta[m]) - a.surface->sigma_t[m];
    }
    split_norms(dn, P, c.sigma_n_l2, c.sigma_n_max, c.sigma_n_symmetric_l2,
                c.sigma_n_symmetric_max, c.sigma_n_antisymmetric_l2, c.sigma_n_antisymmetric_max);
    split_norms(dt, P, c.sigma_t_l2, c.sigma_t_max, c.sigma_t_symmetric_l2,
                c.sigma_t_symmetric_max, c.sigma_t_antisymmetric_l2, c.sigma_t_antisymmetric_max);
  }
  return c;
}

JsonObject comparison_object(const Comparison& c) {
  JsonObject o;
  o.add("solver_a", c.solver_a);
  o.add("solver_b", c.solver_b);
  if (c.have_means) {
    o.add("drag_a", c.drag_a);
    o.add("drag_b", c.drag_b);
    o.add("lift_a", c.lift_a);
    o.add("lift_b", c.lift_b);
    o.add("torque_a", c.torque_a);
    o.add("torque_b", c.torque_b);
    o.add("drag_rel", c.drag_rel);
    o.add("lift_rel", c.lift_rel);
    o.add("torque_rel", c.torque_rel);
    o.add("drag_z", c.drag_z);
    o.add("lift_z", c.lift_z);
    o.add("torque_z", c.torque_z);
    o.add("drag_err_a", c.drag_err_a);
    o.add("drag_err_b", c.drag_err_b);
    o.add("lift_err_a", c.lift_err_a);
    o.add("lift_err_b", c.lift_err_b);
    o.add("torque_err_a", c.torque_err_a);
    o.add("torque_err_b", c.torque_err_b);
    o.add("error_kind_a", c.error_kind_a);
    o.add("error_kind_b", c.error_kind_b);
  }
  if (c.have_surface) {
    o.add("pressure_scale", c.pressure_scale);
    o.add("pressure_scale_from", c.pressure_scale_from);
    o.add("sigma_n_l2", c.sigma_n_l2);
    o.add("sigma_n_max", c.sigma_n_max);
    o.add("sigma_t_l2", c.sigma_t_l2);
    o.add("sigma_t_max", c.sigma_t_max);
    o.add("sigma_n_symmetric_l2", c.sigma_n_symmetric_l2);
    o.add("sigma_n_symmetric_max", c.sigma_n_symmetric_max);
    o.add("sigma_n_antisymmetric_l2", c.sigma_n_antisymmetric_l2);
    o.add("sigma_n_antisymmetric_max", c.sigma_n_antisymmetric_max);
    o.add("sigma_t_symmetric_l2", c.sigma_t_symmetric_l2);
    o.add("sigma_t_symmetric_max", c.sigma_t_symmetric_max);
    o.add("sigma_t_antisymmetric_l2", c.sigma_t_antisymmetric_l2);
    o.add("sigma_t_antisymmetric_max", c.sigma_t_antisymmetric_max);
  }
  return o;
}

std::string comparison_json(const Comparison& c, int indent) {
  return comparison_object(c).str(indent);
}

std::string comparison_text(const Comparison& c) {
  auto rel = [](const std::optional<double>& r) {
    return r ? fmt::format("{:+.4f}", *r) : std::string("n/a (A = 0)");
  };
  auto z = [](const std::optional<double>& v) {
    return v ? fmt::format("  (B-A)/se {:+.3g}", *v) : std::string();
  };
  std::string s = fmt::format("A: {}   B: {}\n", c.solver_a, c.solver_b);
  if (c.have_means) {
    s += fmt::format("  drag    A {:.6g}  B {:.6g}  (B-A)/|A| {}{}\n", c.drag_a, c.drag_b,
                     rel(c.drag_rel), z(c.drag_z));
    s += fmt::format("  lift    A {:.6g}  B {:.6g}  (B-A)/|A| {}{}\n", c.lift_a, c.lift_b,
                     rel(c.lift_rel), z(c.lift_z));
    s += fmt::format("  torque  A {:.6g}  B {:.6g}  (B-A)/|A| {}{}\n", c.torque_a, c.torque_b,
                     rel(c.torque_rel), z(c.torque_z));
    if (c.drag_z || c.lift_z || c.torque_z)
      s += fmt::format("  (se: the combined error sqrt(err_A^2 + err_B^2); A: {}, B: {})\n",
                       c.error_kind_a, c.error_kind_b);
  } else {
    s += "  no mean forces in one of the files\n";
  }
  if (c.have_surface) {
    s += fmt::format("  pressure scale P = {:.6g} Pa ({})\n", c.pressure_scale,
                     c.pressure_scale_from);
    s += fmt::format("  sigma_n: L2 {:.4g} P, max {:.4g} P\n", c.sigma_n_l2, c.sigma_n_max);
    s += fmt::format("  sigma_t: L2 {:.4g} P, max {:.4g} P\n", c.sigma_t_l2, c.sigma_t_max);
    s += fmt::format("  sigma_n symmetric: L2 {:.4g} P, max {:.4g} P; antisymmetric: L2 {:.4g} "
                     "P, max {:.4g} P\n",
                     c.sigma_n_symmetric_l2, c.sigma_n_symmetric_max, c.sigma_n_antisymmetric_l2,
                     c.sigma_n_antisymmetric_max);
    s += fmt::format("  sigma_t symmetric: L2 {:.4g} P, max {:.4g} P; antisymmetric: L2 {:.4g} "
                     "P, max {:.4g} P\n",
                     c.sigma_t_symmetric_l2, c.sigma_t_symmetric_max, c.sigma_t_antisymmetric_l2,
                     c.sigma_t_antisymmetric_max);
  } else {
    s += "  no surface distribution in one of the files\n";
  }
  return s;
}

}  // namespace grainlift
