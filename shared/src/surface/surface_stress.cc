#include "grainlift/shared/surface/surface_stress.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace grainlift {

namespace {
constexpr double pi = 3.14159265358979323846;
}

double wrap_angle(double theta) {
  theta = std::fmod(theta + pi, 2 * pi);
  if (theta <= 0) theta += 2 * pi;
  return theta - pi;
}

std::vector<double> surface_angle_grid(int M) {
  std::vector<double> t(M);
  for (int m = 0; m < M; ++m) t[m] = (m + 0.5) * 2 * pi / M;
  return t;
}

SurfaceStressEstimator::SurfaceStressEstimator(int M, double width_deg, double diameter)
    : M_(M), width_(width_deg * pi / 180), diameter_(diameter), theta_(surface_angle_grid(M)),
      fn_(M, 0.0), ft_(M, 0.0) {
  if (M < 1 || !(width_ > 0) || !(diameter > 0))
    throw std::invalid_argument("SurfaceStressEstimator: need M >= 1, width > 0, D > 0");
}

void SurfaceStressEstimator::add(double theta, double fn, double ft) {
  // Guillard eq. (A4); the angular distance is wrapped so the kernel is periodic.
  const double norm = std::sqrt(2 * pi) / (M_ * width_);
  const double inv2s2 = 1.0 / (2 * width_ * width_);
  for (int m = 0; m < M_; ++m) {
    const double d = wrap_angle(theta - theta_[m]);
    const double w = norm * std::exp(-d * d * inv2s2);
    fn_[m] += w * fn;
    ft_[m] += w * ft;
  }
}

SurfaceDistribution SurfaceStressEstimator::result() const {
  SurfaceDistribution s;
  s.theta = theta_;
  s.kernel_width_deg = width_ * 180 / pi;
  const double area = diameter_ * pi / M_;  // element area per unit length
  const double frames = frames_ > 0 ? double(frames_) : 1.0;
  s.sigma_n.resize(M_);
  s.sigma_t.resize(M_);
  for (int m = 0; m < M_; ++m) {
    s.sigma_n[m] = fn_[m] / (frames * area);
    s.sigma_t[m] = ft_[m] / (frames * area);
  }
  return s;
}

ContactHistogram::ContactHistogram(int bins)
    : bins_(bins),
      count_(bins, 0.0),
      fn_(bins, 0.0),
      ft_(bins, 0.0),
      slip_(bins, 0.0),
      vt_(bins, 0.0),
      vt_count_(bins, 0.0) {
  if (bins < 1) throw std::invalid_argument("ContactHistogram: need at least one bin");
}

void ContactHistogram::add(double theta, double fn, double ft, bool slipping, double vt) {
  const double w = 2 * pi / bins_;
  int b = int(std::floor((wrap_angle(theta) + pi) / w));
  b = std::min(std::max(b, 0), bins_ - 1);
  count_[b] += 1;
  fn_[b] += fn;
  ft_[b] += ft;
  slip_[b] += slipping ? 1 : 0;
  if (std::isfinite(vt)) {
    vt_[b] += vt;
    vt_count_[b] += 1;
  }
}

SurfaceHistogram ContactHistogram::result() const {
  SurfaceHistogram h;
  const double w = 2 * pi / bins_;
  const double frames = frames_ > 0 ? double(frames_) : 1.0;
  const bool with_vt =
      std::any_of(vt_count_.begin(), vt_count_.end(), [](double n) { return n > 0; });
  if (with_vt) h.slip_velocity.emplace();
  for (int b = 0; b < bins_; ++b) {
    h.theta_lo.push_back(-pi + b * w);
    h.theta_hi.push_back(-pi + (b + 1) * w);
    h.contact_count.push_back(count_[b] / frames);
    h.normal_force.push_back(fn_[b] / frames);
    h.tangential_force.push_back(ft_[b] / frames);
    h.slip_fraction.push_back(count_[b] > 0 ? slip_[b] / count_[b] : 0.0);
    if (with_vt) h.slip_velocity->push_back(vt_count_[b] > 0 ? vt_[b] / vt_count_[b] : 0.0);
  }
  return h;
}

std::pair<double, double> fourier_mode(const std::vector<double>& values, int k) {
  const int M = int(values.size());
  const auto theta = surface_angle_grid(M);
  double a = 0, b = 0;
  for (int m = 0; m < M; ++m) {
    a += values[m] * std::cos(k * theta[m]);
    b += values[m] * std::sin(k * theta[m]);
  }
  if (k == 0) return {a / M, 0.0};
  return {2 * a / M, 2 * b / M};
}

double kernel_attenuation(int k, double width_deg) {
  const double s = width_deg * pi / 180;
  return std::exp(-0.5 * k * k * s * s);
}

void symmetry_split(const std::vector<double>& values, std::vector<double>& symmetric,
                    std::vector<double>& antisymmetric) {
  // On theta_m = (m + 1/2) 2 pi / M the mirror image of theta_m is theta_{M-1-m}.
  const std::size_t M = values.size();
  symmetric.resize(M);
  antisymmetric.resize(M);
  for (std::size_t m = 0; m < M; ++m) {
    const double mirror = values[M - 1 - m];
    symmetric[m] = 0.5 * (values[m] + mirror);
    antisymmetric[m] = 0.5 * (values[m] - mirror);
  }
}

std::array<double, 3> integrate_surface(const SurfaceDistribution& s, double diameter) {
  const double R = 0.5 * diameter;
  const std::size_t M = s.theta.size();
  const double ds = 2 * pi * R / M;
  double fpar = 0, fperp = 0, torque = 0;
  for (std::size_t m = 0; m < M; ++m) {
    const double c = std::cos(s.theta[m]), sn = std::sin(s.theta[m]);
    // traction on the intruder: -sigma_n n + sigma_t t, n = (c, s) outward, t = (-s, c)
    fpar += (-s.sigma_n[m] * c - s.sigma_t[m] * sn) * ds;
    fperp += (-s.sigma_n[m] * sn + s.sigma_t[m] * c) * ds;
    torque += R * s.sigma_t[m] * ds;
  }
  return {fpar, fperp, torque};
}

}  // namespace grainlift
