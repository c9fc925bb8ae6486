// Viscosity models of the continuum engine, as pure batch functions over quadrature points
// (ASPECT material-model style): no I/O, no allocation, no deal.II.
#pragma once

#include <cstddef>
#include <vector>

#include "grainlift/continuum/continuum_config.h"

namespace grainlift::continuum {

/// Inputs at n points. Both vectors have the same length.
struct RheologyInputs {
  std::vector<double> strain_rate_sq;  ///< |D|^2 = D:D / 2, 1/s^2 (D the strain-rate tensor)
  std::vector<double> pressure;        ///< Pa, mechanical pressure -tr(sigma)/2; may be negative
  /// 1/s, the nonlocal fluidity g at the points (empty for the local laws; filled by the
  /// nonlocal model itself)
  std::vector<double> fluidity;
  /// 1/s, g - g_loc of the previous flow at the points, where the nonlocal model has it (empty
  /// elsewhere): the flow step then takes g_loc at its own stress ratio (fluidity_viscosity.h)
  std::vector<double> fluidity_excess;
  void resize(std::size_t n) { strain_rate_sq.resize(n); pressure.resize(n); }
  std::size_t size() const { return pressure.size(); }
};

/// Outputs at the same n points; the caller sizes them (see resize()).
struct RheologyOutputs {
  std::vector<double> viscosity;        ///< Pa s, eta in sigma = -p I + 2 eta D
  std::vector<double> deta_dstrain_sq;  ///< Pa s^3, d eta / d |D|^2
  std::vector<double> deta_dpressure;   ///< s, d eta / d p
  std::vector<double> friction;         ///< mu(I) (0 for a Newtonian fluid)
  std::vector<double> inertial_number;  ///< I = 2 |D| d / sqrt(p / rho_s) (0 for a Newtonian fluid)
  /// dI / d|D|^2 (s^2) and dI / dp (1/Pa) where the law has I (0 elsewhere; the dilatant
  /// medium's Jacobian, DilatancyLaw)
  std::vector<double> dI_dstrain_sq, dI_dpressure;
  void resize(std::size_t n) {
    viscosity.resize(n); deta_dstrain_sq.resize(n); deta_dpressure.resize(n);
    friction.resize(n); inertial_number.resize(n);
    dI_dstrain_sq.assign(n, 0.0); dI_dpressure.assign(n, 0.0);
  }
};

/// @brief The cap and floor of the granular viscosities (MuIRheology's, the nonlocal flow
/// step's): eta <- eta_max tanh(eta / eta_max) (relative change (eta/eta_max)^2 / 3 well below
/// the cap; keeps Newton's Jacobian continuous; eta_max beyond 20 eta_max), then eta_min with
/// zero derivatives below it. @p deta_ds, @p deta_dp are scaled alike.
void cap_viscosity(const RheologyParams& params, double& eta, double& deta_ds,
                   double& deta_dp);

/// @brief Interface of a generalised-Newtonian viscosity eta(|D|^2, p).
class ViscosityModel {
 public:
  virtual ~ViscosityModel() = default;
  /// @brief Fill every output at every point of @p in (outputs must be sized like the inputs).
  virtual void evaluate(const RheologyInputs& in, RheologyOutputs& out) const = 0;
  /// @brief True when eta depends on the solution (the problem is then nonlinear).
  virtual bool is_nonlinear() const = 0;
  /// @brief barker_criterion() of the law at inertial number @p I where it is not regularised
  /// (< 0: well posed); a viscous fluid is well posed everywhere.
  virtual double well_posedness(double /*inertial_number*/) const { return -1; }
  /// @brief Strain rate (|D|, 1/s) below which the law's regularisation makes it well posed
  /// whatever I (0: none).
  virtual double regularised_strain_rate() const { return 0; }
};

/// @brief Constant viscosity (Newtonian verification cases).
class NewtonianViscosity final : public ViscosityModel {
 public:
  /// @param viscosity Pa s
  explicit NewtonianViscosity(double viscosity) : eta_(viscosity) {}
  void evaluate(const RheologyInputs& in, RheologyOutputs& out) const override;
  bool is_nonlinear() const override { return false; }

 private:
  double eta_;
};

/// @brief Well-posedness criterion of Barker, Schaeffer, Bohorquez & Gray (JFM 779, 2015) for
/// two-dimensional incompressible flow with a friction law mu(I): with nu = I mu'(I) / mu(I),
/// the equations are well posed where C = 4 nu^2 - 4 nu + mu^2 (1 - nu / 2)^2 < 0 and ill posed
/// (short waves grow without bound, so no mesh convergence) where C > 0.
double barker_criterion(double mu, double nu);

/// @brief Inertial numbers [low, high] between which Jop's unregularised mu(I) with the
/// parameters of @p params satisfies barker_criterion() (for mu_s 0.38, mu_2 0.64, I_0 0.279:
/// about [0.019, 0.86]); low = high = 0 when it holds nowhere.
struct InertialRange {
  double low = 0, high = 0;
  bool empty() const { return !(high > low); }
};
InertialRange well_posed_range(const RheologyParams& params);

/// @brief The mu(I) rheology of Jop, Forterre & Pouliquen (Nature 2006), regularised.
///
/// mu(I) = mu_s + (mu_2 - mu_s) / (I_0 / I + 1),  I = 2 |D| d / sqrt(p+ / rho_s),  p+ = max(p, 0)
/// (the pressure is clamped here, never in the solution).
///  - chauchat_medale: eta = mu(I) p+ / (2 sqrt(|D|^2 + delta^2))  (Chauchat & Medale, JCP 2014),
///    with the same regularised sqrt(|D|^2 + delta^2) in place of |D| in I (smooth at |D| = 0);
///  - barker_gray: mu(I) replaced by mu_BG = mu(I) for I >= I_N and sqrt(alpha / ln(A / I))
///    below (Barker & Gray, JFM 2017), alpha, A from C1 continuity at I_N; with I_N inside the
///    well-posed range of mu(I) the law is well posed for every I < high (barker_criterion()).
///    The strain rate is regularised as above when delta > 0 (eta = mu_BG p+ / (2 sqrt(|D|^2 +
///    delta^2))), and eta = mu_BG p+ / (2 |D|) with delta = 0.
/// Both are then capped smoothly, eta <- eta_max tanh(eta / eta_max) (relative change
/// (eta/eta_max)^2 / 3 well below the cap; keeps Newton's Jacobian continuous), and floored at
/// eta_min (derivatives zero below the floor).
class MuIRheology final : public ViscosityModel {
 public:
  explicit MuIRheology(const RheologyParams& params);
  void evaluate(const RheologyInputs& in, RheologyOutputs& out) const override;
  bool is_nonlinear() const override { return true; }

  /// @brief Friction coefficient mu(I) of the selected regularisation (dimensionless).
  double friction(double inertial_number) const;
  /// @brief d mu / d I.
  double dfriction_dI(double inertial_number) const;
  /// @brief Inverse of the unregularised mu(I) for mu_s < mu < mu_2 (used by tests).
  double inertial_number_for_friction(double mu) const;
  /// @brief barker_criterion() of the friction law in use at @p I (< 0: well posed there).
  double well_posedness(double inertial_number) const override;
  /// @brief 5 delta: the Chauchat-Medale form's rate sensitivity delta^2 / (|D|^2 + delta^2)
  /// keeps the law well posed roughly below it (docs/continuum-model.md; our estimate).
  double regularised_strain_rate() const override { return 5 * p_.delta; }
  /// @brief I_N in use: params().barker_gray_IN, or when that is 0 1.5 times the lower end of
  /// well_posed_range() (kept below the geometric mean of its ends).
  double barker_gray_IN() const { return bg_IN_; }
  const RheologyParams& params() const { return p_; }

 private:
  RheologyParams p_;
  double bg_IN_ = 0, bg_alpha_ = 0, bg_A_ = 0;  // Barker & Gray low-I branch
};

}  // namespace grainlift::continuum
