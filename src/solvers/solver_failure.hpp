#pragma once
// How an iterative solver of a step failed, in words, for the step's message
// (scheme/step_failure.hpp): the one wording of the contact and the damage solvers.
#include <fmt/format.h>

#include <string>

namespace vpc {

/// A solver whose residuals are not finite.
inline const char* const kSolverMetNonFinite = "met NaN or Inf in its data or solution";

/// "" when the solver converged with no residual above its tolerance; else "stopped at its
/// iteration limit after 3 iterations without converging[; <above>]" or "ended after 1 iteration
/// with its <above>". `above`: the residuals above the tolerance, with it ("" for none).
inline std::string solver_failure(bool converged, int iterations, const std::string& above) {
  const std::string its = fmt::format("{} iteration{}", iterations, iterations == 1 ? "" : "s");
  if (!converged)
    return fmt::format("stopped at its iteration limit after {} without converging{}", its,
                       above.empty() ? "" : "; " + above);
  return above.empty() ? "" : fmt::format("ended after {} with its {}", its, above);
}

}  // namespace vpc
