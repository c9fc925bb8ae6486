// Internal: the velocity and pressure extractors of the Taylor-Hood element and the rheology
// at the quadrature points of a cell, shared by the assembly and the post-processors.
// Includes deal.II: never include it from a public header.
#pragma once

#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/fe_values_extractors.h>

#include <vector>

#include "flow_problem.h"
#include "fluidity/fluidity_viscosity.h"

namespace grainlift::continuum::internal {

inline const dealii::FEValuesExtractors::Vector kVelocity(0);
inline const dealii::FEValuesExtractors::Scalar kPressure(dim);

/// D(u), p and the viscosity model's outputs at the quadrature points of one cell (the
/// rheology as the assembly, the post-processing and the output see it).
struct QuadratureRheology {
  std::vector<dealii::SymmetricTensor<2, dim>> sym;  ///< D(u)
  std::vector<double> pressure;
  RheologyInputs in;
  RheologyOutputs out;
  explicit QuadratureRheology(unsigned int nq) : sym(nq), pressure(nq) {
    in.resize(nq);
    out.resize(nq);
  }
  /// At the points of @p fev (reinitialised on a cell) for the ghosted @p state.
  void evaluate(const dealii::FEValues<dim>& fev, const VectorType& state,
                const ViscosityModel& model) {
    fev[kVelocity].get_function_symmetric_gradients(state, sym);
    fev[kPressure].get_function_values(state, pressure);
    for (unsigned int q = 0; q < sym.size(); ++q) {
      in.strain_rate_sq[q] = 0.5 * (sym[q] * sym[q]);  // |D|^2 = D:D/2
      in.pressure[q] = pressure[q];
    }
    if (const auto* field = dynamic_cast<const FieldViscosity*>(&model))
      field->fill_fields(fev, in);
    model.evaluate(in, out);
  }
};

}  // namespace grainlift::continuum::internal
