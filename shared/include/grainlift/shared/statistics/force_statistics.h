// Drag and lift by the conventions of docs/conventions.md, shared by both solvers. Their block
// means and standard errors: statistics.h.
#pragma once

namespace grainlift {

/// Drag D = -F . V/|V| and lift L = F . (z x V/|V|) (docs/conventions.md). Forces per unit length.
struct DragLift {
  double drag = 0, lift = 0;
};
/// @param fx, fy force on the intruder (N/m); @param vx, vy intruder velocity (m/s, not zero).
DragLift project_drag_lift(double fx, double fy, double vx, double vy);

}  // namespace grainlift
