#include "grainlift/shared/statistics/replica_pool.h"

#include "grainlift/shared/statistics/statistics.h"

#include <cmath>
#include <stdexcept>

namespace grainlift {
namespace {

/// Element-wise pooled mean (statistics.h's pooled_mean) over the replicas of one array; cells
/// that are not finite in a replica are left out of that cell's pool (NaN where no replica has
/// a value). With @p se, the pooled error of each cell (NaN with fewer than two values), its
/// within-bed part from @p errors (the replicas' own errors of the same cells) when given.
std::vector<double> mean_of(const std::vector<const std::vector<double>*>& arrays,
                            std::vector<double>* se = nullptr,
                            const std::vector<const std::vector<double>*>& errors = {}) {
  const std::size_t m = arrays.front()->size();
  for (const auto* a : arrays) {
    if (a->size() != m) throw std::invalid_argument("pool_replicas: replicas of different grids");
  }
  for (const auto* e : errors) {
    if (e->size() != m) throw std::invalid_argument("pool_replicas: errors of different grids");
  }
  std::vector<double> out(m), values, errs;
  if (se) se->assign(m, std::nan(""));
  for (std::size_t i = 0; i < m; ++i) {
    values.clear();
    errs.clear();
    for (std::size_t k = 0; k < arrays.size(); ++k) {
      if (!std::isfinite((*arrays[k])[i])) continue;
      values.push_back((*arrays[k])[i]);
      if (!errors.empty()) errs.push_back((*errors[k])[i]);
    }
    if (values.empty()) {
      out[i] = std::nan("");
      continue;
    }
    const PooledMean p = pooled_mean(values, errs);
    out[i] = p.mean;
    if (se && values.size() >= 2) (*se)[i] = p.error;
  }
  return out;
}

/// The optional field @p member of every replica's grid, pooled (absent if any lacks it).
template <class Member>
std::optional<std::vector<double>> pool_field(const std::vector<RunResult>& rs, Member member) {
  std::vector<const std::vector<double>*> arrays;
  for (const auto& r : rs) {
    const auto& f = (*r.fields).*member;
    if (!f) return std::nullopt;
    arrays.push_back(&*f);
  }
  return mean_of(arrays);
}

/// The pooled drag, lift and torque of the replicas' means into @p p (pooled_mean; each
/// replica's value kept in /diagnostics series).
void pool_means(const std::vector<RunResult>& rs, RunResult& p) {
  const std::size_t n = rs.size();
  std::vector<double> drag, lift, torque, contacts, drag_se, lift_se, torque_se;
  bool all_errors = true;
  std::int64_t samples = 0;
  for (const auto& r : rs) {
    drag.push_back(r.means->drag);
    lift.push_back(r.means->lift);
    torque.push_back(r.means->torque);
    if (r.means->contacts) contacts.push_back(*r.means->contacts);
    all_errors = all_errors && r.means->drag_stderr && r.means->lift_stderr &&
                 r.means->torque_stderr;
    if (all_errors) {
      drag_se.push_back(*r.means->drag_stderr);
      lift_se.push_back(*r.means->lift_stderr);
      torque_se.push_back(*r.means->torque_stderr);
    }
    samples += r.means->samples;
  }
  if (!all_errors) {  // pooled from the spread alone
    drag_se.clear();
    lift_se.clear();
    torque_se.clear();
  }
  if (n >= 2) {
    MeanForces& m = *p.means;
    const PooledMean d = pooled_mean(drag, drag_se), l = pooled_mean(lift, lift_se),
                     t = pooled_mean(torque, torque_se);
    m.drag = d.mean;
    m.lift = l.mean;
    m.torque = t.mean;
    m.drag_stderr = d.error;
    m.lift_stderr = l.error;
    m.torque_stderr = t.error;
    if (contacts.size() == n) m.contacts = pooled_mean(contacts).mean;
    m.samples = samples;
    m.blocks = std::int64_t(n);
  }
  p.diagnostics.series["replica_drag"] = drag;
  p.diagnostics.series["replica_lift"] = lift;
  p.diagnostics.series["replica_torque"] = torque;
}

/// The replicas' mean surface stresses and their pooled errors at each angle into @p p.
void pool_surface(const std::vector<RunResult>& rs, RunResult& p) {
  std::vector<const std::vector<double>*> sn, st, en, et;
  bool all_errors = true;
  for (const auto& r : rs) {
    sn.push_back(&r.surface->sigma_n);
    st.push_back(&r.surface->sigma_t);
    all_errors = all_errors && r.surface->sigma_n_stderr && r.surface->sigma_t_stderr;
    if (all_errors) {
      en.push_back(&*r.surface->sigma_n_stderr);
      et.push_back(&*r.surface->sigma_t_stderr);
    }
  }
  if (!all_errors) {
    en.clear();
    et.clear();
  }
  std::vector<double> se_n, se_t;
  p.surface->sigma_n = mean_of(sn, &se_n, en);
  p.surface->sigma_t = mean_of(st, &se_t, et);
  p.surface->sigma_n_stderr = std::move(se_n);
  p.surface->sigma_t_stderr = std::move(se_t);
}

}  // namespace

RunResult pool_replicas(const std::vector<RunResult>& rs) {
  if (rs.empty()) throw std::invalid_argument("pool_replicas: no replicas");
  RunResult p = rs.front();
  const std::size_t n = rs.size();
  bool all_means = true, all_surface = true, all_hist = true, all_fields = true;
  for (const auto& r : rs) {
    all_means = all_means && r.means.has_value();
    all_surface = all_surface && r.surface.has_value();
    all_hist = all_hist && r.histogram.has_value();
    all_fields = all_fields && r.fields.has_value();
  }
  if (all_means) pool_means(rs, p);
  p.diagnostics.counts["replicas"] = static_cast<long long>(n);
  if (n < 2) return p;
  if (all_surface) {
    pool_surface(rs, p);
  } else {
    p.surface.reset();
  }
  if (all_hist) {
    auto pool = [&](std::vector<double> SurfaceHistogram::*member) {
      std::vector<const std::vector<double>*> a;
      for (const auto& r : rs) a.push_back(&((*r.histogram).*member));
      (*p.histogram).*member = mean_of(a);
    };
    pool(&SurfaceHistogram::contact_count);
    pool(&SurfaceHistogram::normal_force);
    pool(&SurfaceHistogram::tangential_force);
    pool(&SurfaceHistogram::slip_fraction);
  } else {
    p.histogram.reset();
  }
  if (all_fields) {
    FieldGrid& g = *p.fields;
    g.velocity_x = pool_field(rs, &FieldGrid::velocity_x);
    g.velocity_y = pool_field(rs, &FieldGrid::velocity_y);
    g.pressure = pool_field(rs, &FieldGrid::pressure);
    g.stress_xx = pool_field(rs, &FieldGrid::stress_xx);
    g.stress_xy = pool_field(rs, &FieldGrid::stress_xy);
    g.stress_yy = pool_field(rs, &FieldGrid::stress_yy);
    g.area_fraction = pool_field(rs, &FieldGrid::area_fraction);
    g.granular_temperature = pool_field(rs, &FieldGrid::granular_temperature);
  } else {
    p.fields.reset();
  }
  return p;
}

}  // namespace grainlift
