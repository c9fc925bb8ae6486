// Finite-element engine of the continuum solver (the class: flow_problem.h; the weak form:
// assembly.cc).
// The member functions of FlowProblem are defined in files named for what they hold:
//   flow_problem.cc      construction, vector layout, run(), make_state()
//   system_setup.cc      setup_system(), constraints, initial guess
//   assembly.cc          assemble_system() (residual, Jacobian or Picard matrix)
//   linear_solver.cc     solve() (FGMRES with block_preconditioner.h, or MUMPS:
//                        direct_solver.cc)
//   nonlinear_solver.cc  solve_nonlinear() (Picard then Newton with a line search)
//   postprocess/         boundary_forces.cc, surface_traces.cc, point_fields.cc,
//                        ill_posed_share.cc, error_norms.cc, vtu_output.cc
#include "flow_problem.h"
#include "fluidity/fluidity_viscosity.h"

#include <deal.II/base/mpi.h>
#include <deal.II/fe/fe_q.h>

#include <mpi.h>

#include <cstdlib>

namespace grainlift::continuum::internal {

using namespace dealii;

namespace {
/// Trilinos objects need MPI even on one process. When the program has not initialised MPI
/// (the tests, a serial run), do it here once and finalise at exit.
int ensure_mpi() {
  int initialised = 0;
  MPI_Initialized(&initialised);
  if (initialised) return 0;
  MPI_Init(nullptr, nullptr);
  std::atexit([] {
    int finalised = 0;
    MPI_Finalized(&finalised);
    if (finalised) return;
    // (the solvers' pools of Trilinos vectors are statics made after this handler was
    // registered: they are destroyed before it runs, while MPI is still up)
    MPI_Finalize();
  });
  return 0;
}
}  // namespace

FlowProblem::FlowProblem(Triangulation<dim>& tria, const ProblemSetup& setup)
    : mpi_ready_(ensure_mpi()), tria_(tria), comm_(tria.get_communicator()), setup_(setup),
      fe_(FE_Q<dim>(2), dim, FE_Q<dim>(1), 1), mapping_(2), dof_handler_(tria) {}

unsigned int FlowProblem::n_ranks() const { return Utilities::MPI::n_mpi_processes(comm_); }

VectorType FlowProblem::make_vector() const { return VectorType(owned_, comm_); }

VectorType FlowProblem::ghosted(const VectorType& v) const {
  VectorType g(owned_, relevant_, comm_);
  g = v;
  return g;
}
void FlowProblem::run() {
  setup_system();
  interpolate_initial_guess();
  report_ = NonlinearReport{};
  solve_nonlinear(setup_.nonlinear);
}
PointState FlowProblem::make_state(const SymmetricTensor<2, dim>& D, double p, const Vec2& u,
                                   const Triangulation<dim>::cell_iterator& cell,
                                   const Point2& unit) const {
  RheologyInputs in;
  in.resize(1);
  RheologyOutputs out;
  out.resize(1);
  in.strain_rate_sq[0] = 0.5 * (D * D);
  in.pressure[0] = p;
  if (const auto* field = dynamic_cast<const FieldViscosity*>(setup_.viscosity))
    field->fill_fields_at(cell, {unit}, in);
  setup_.viscosity->evaluate(in, out);
  PointState s;
  s.velocity = u;
  s.pressure = p;
  s.viscosity = out.viscosity[0];
  s.inertial_number = out.inertial_number[0];
  s.stress = -p * unit_symmetric_tensor<dim>() + 2 * s.viscosity * D;
  return s;
}

PointState FlowProblem::make_state(const SymmetricTensor<2, dim>& D, double p, const Vec2& u,
                                   const FEFaceValues<dim>& ffv, unsigned int q) const {
  // the point's reference coordinates only where a field is read there (an inverse mapping)
  if (!dynamic_cast<const FieldViscosity*>(setup_.viscosity))
    return make_state(D, p, u, ffv.get_cell(), Point2());
  const Point2 unit = mapping_.transform_real_to_unit_cell(ffv.get_cell(), ffv.quadrature_point(q));
  return make_state(D, p, u, ffv.get_cell(), GeometryInfo<dim>::project_to_unit_cell(unit));
}
}  // namespace grainlift::continuum::internal
