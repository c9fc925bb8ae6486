#include "grainlift/shared/replica_pool.h"

#include "grainlift/shared/force_statistics.h"

#include <cmath>
#include <stdexcept>

namespace grainlift {
namespace {

/// Element-wise mean over the replicas of one array; cells that are not finite in a replica
/// are left out of that cell's mean (NaN where no replica has a value). With @p se, the
/// element-wise SD / sqrt(N) of the finite values (NaN with fewer than two).
std::vector<double> mean_of(const std::vector<const std::vector<double>*>& arrays,
                            std::vector<double>* se = nullptr) {
  const std::size_t m = arrays.front()->size();
  for (const auto* a : arrays) {
    if (a->size() != m) throw std::invalid_argument("pool_replicas: replicas of different grids");
  }
  std::vector<double> out(m), values;
  if (se) se->assign(m, std::nan(""));
  for (std::size_t i = 0; i < m; ++i) {
    values.clear();
    for (const auto* a : arrays)
      if (std::isfinite((*a)[i])) values.push_back((*a)[i]);
    if (values.empty()) {
      out[i] = std::nan("");
      continue;
    }
    // blocks of one value each: the mean and SD / sqrt(N)
    const BlockMean s = block_mean(values, values.size());
    out[i] = s.mean;
    if (se && values.size() >= 2) (*se)[i] = s.stderr_;
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
  if (all_means) {
    std::vector<double> drag, lift, torque, contacts;
    std::int64_t samples = 0;
    for (const auto& r : rs) {
      drag.push_back(r.means->drag);
      lift.push_back(r.means->lift);
      torque.push_back(r.means->torque);
      if (r.means->contacts) contacts.push_back(*r.means->contacts);
      samples += r.means->samples;
    }
    if (n >= 2) {
      MeanForces& m = *p.means;
      const BlockMean d = block_mean(drag, n), l = block_mean(lift, n), t = block_mean(torque, n);
      m.drag = d.mean;
      m.lift = l.mean;
      m.torque = t.mean;
      m.drag_stderr = d.stderr_;
      m.lift_stderr = l.stderr_;
      m.torque_stderr = t.stderr_;
      if (contacts.size() == n) m.contacts = block_mean(contacts, n).mean;
      m.samples = samples;
      m.blocks = std::int64_t(n);
    }
    p.diagnostics.series["replica_drag"] = drag;
    p.diagnostics.series["replica_lift"] = lift;
    p.diagnostics.series["replica_torque"] = torque;
  }
  p.diagnostics.counts["replicas"] = static_cast<long long>(n);
  if (n < 2) return p;
  if (all_surface) {
    std::vector<const std::vector<double>*> sn, st;
    for (const auto& r : rs) {
      sn.push_back(&r.surface->sigma_n);
      st.push_back(&r.surface->sigma_t);
    }
    std::vector<double> se_n, se_t;
    p.surface->sigma_n = mean_of(sn, &se_n);
    p.surface->sigma_t = mean_of(st, &se_t);
    p.surface->sigma_n_stderr = std::move(se_n);
    p.surface->sigma_t_stderr = std::move(se_t);
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
