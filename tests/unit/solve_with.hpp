#pragma once
// x = A⁻¹b with a factor of A, for tests that solve with a la::LinearSolver.
#include "la/linear_solver.hpp"

namespace vpc {

inline Vector solve_with(const la::LinearSolver& f, const Vector& b) {
  Vector x;
  f.solve(b, x);
  return x;
}

}  // namespace vpc
