#pragma once
// Issue 28: what the frictional regression tests share: a shipped case's text (to vary with
// test::replaced), a run
// to its end with a look at every step, and a contact node's forces (λ holds contact_block
// numbers per node, λ_ν first, then λ_τ along the node's tangents).
#include "../case_text.hpp"
#include "cases/builtin_cases.hpp"
#include "cases/shipped_cases.hpp"
#include "io/case_file.hpp"
#include "scheme/time_stepper.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

namespace vpc::friction_test {

/// The compiled-in text of cases/NAME.toml.
inline std::string shipped_text(const std::string& name) { return case_source(name).text; }

using test::replaced;

/// The case `text` (a variant of the shipped case `name`, whose meshes it finds) with `sets`.
inline Case case_of(const std::string& name, const std::string& text, const std::vector<std::string>& sets = {}) {
  return parse_case(text, name + ".toml", case_source(name).base_dir, {.sets = sets});
}

/// Runs `c` to its end; `each` sees the stepper and the report after every step. Every step
/// must be accepted (solvers converged, residuals within the tolerance).
inline void run_to_end(const Case& c, const std::function<void(const TimeStepper&, const StepReport&)>& each = {}) {
  TimeStepper s(c.problem, c.solvers);
  while (!s.done()) {
    const StepReport r = s.step();
    ASSERT_TRUE(r.ok) << "step " << r.n << " (t = " << r.t << ")";
    EXPECT_LE(r.contact.residuals.max(), c.solvers.residual_tolerance) << "step " << r.n;
    if (each) each(s, r);
  }
}

/// A contact node's forces after a step: λ_ν and λ_τ (block − 1 numbers).
struct NodeForces {
  Point x{};
  double measure = 0, normal = 0;
  std::vector<double> tangential;
  int status = -1;  // State::contact_status (0 free, 1 stick, 2 slip), −1 where the state has none
  double tangential_norm() const {
    double s = 0;
    for (double v : tangential) s += v * v;
    return std::sqrt(s);
  }
};

inline std::vector<NodeForces> node_forces(const TimeStepper& s) {
  const State& st = s.state();
  const int b = st.contact_block;
  std::vector<NodeForces> out;
  for (const PartContactNode& node : s.contact().nodes) {
    NodeForces f;
    f.x = s.mesh().node(node.local_node);
    f.measure = node.measure;
    f.normal = st.lambda[node.row * b];
    for (int j = 1; j < b; ++j) f.tangential.push_back(st.lambda[node.row * b + j]);
    if (st.contact_status.size() > node.row) f.status = static_cast<int>(st.contact_status[node.row]);
    out.push_back(f);
  }
  return out;
}

/// max |a − b| / max |b|.
inline double relative_difference(const Vector& a, const Vector& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(b.cwiseAbs().maxCoeff(), 1e-300);
}

}  // namespace vpc::friction_test
