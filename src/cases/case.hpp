#pragma once
// A case: a Problem plus how to run it (solvers) and what to write (output).
// Built-in cases and case files both produce one.
#include "io/run_output.hpp"
#include "scheme/problem.hpp"
#include "scheme/time_stepper.hpp"

#include <memory>
#include <string>

namespace vpc {

struct Case {
  std::string name;
  std::string description;
  std::shared_ptr<Problem> problem;
  OutputOptions output;  // an empty directory means output/<name>
  SolverChoice solvers;
};

}  // namespace vpc
