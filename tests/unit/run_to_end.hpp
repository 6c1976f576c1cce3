#pragma once
// A case run to its end in a test: every step must pass its checks (ok); `last` gets the last
// step's report.
#include "io/case.hpp"
#include "scheme/time_stepper.hpp"

#include <gtest/gtest.h>

#include <memory>

namespace vpc {

inline std::unique_ptr<TimeStepper> run_to_end(const Case& c, StepReport* last = nullptr) {
  auto s = std::make_unique<TimeStepper>(c.problem, c.solvers);
  while (!s->done()) {
    const StepReport r = s->step();
    EXPECT_TRUE(r.ok) << "step " << r.n << ": contact residual " << r.contact.residuals.max();
    if (last) *last = r;
  }
  return s;
}

}  // namespace vpc
