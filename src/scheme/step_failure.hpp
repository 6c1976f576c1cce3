#pragma once
// Why a step failed (StepReport::ok false), in words, and whether smaller steps can help:
// for the one-line error of a failed run and of a convergence study.
#include "scheme/time_stepper.hpp"

#include <string>

namespace vpc {

/// What failed, e.g. "the contact solver ended after 1 iteration with its complementarity
/// residual 1.00e+00 (...) above the tolerance 1.0e-08": each solver that failed (the residual
/// and its value against `tolerance`, or its iteration limit, or NaN/Inf), else the state.
std::string step_failure(const StepReport& r, double tolerance);

/// Whether redoing the step as smaller ones (--retry-halvings) can help: a damage solve (H =
/// M + kκA depends on k), a solver stopped at its iteration limit (the warm start is nearer),
/// NaN or Inf (the explicit source may have grown beyond what the step can carry), a surface law's
/// step limit passed (SurfaceLimits: an update per step that grows with the step). Not a
/// contact solve that converged with a residual above the tolerance: the step's contact
/// problem was solved to its round-off, which the step size does not change.
bool halving_can_help(const StepReport& r, double tolerance);

}  // namespace vpc
