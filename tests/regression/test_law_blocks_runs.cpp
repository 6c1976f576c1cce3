// Issue 49: a friction law the solvers never heard of runs through them by its block alone. The
// test-only elliptic Coulomb law (tests/support/test_laws.hpp) on shear-3d (a block pressed onto a
// plane that then slides along (2, 1)): with equal axes it is Coulomb; with unequal axes the face's
// full slip lies on the ellipse, |λ_τ|_C = μ λ_ν, and slips along its outward normal; on the dual and
// on the primal.
#include "friction_runs.hpp"
#include "test_laws.hpp"

#include <fmt/format.h>

#include <cstdio>

namespace vpc {
namespace {

using namespace friction_test;

constexpr double kMu = 0.3;

Case elliptic_shear(double a1, double a2, const std::string& solver) {
  test::register_test_laws();
  Case c = case_of("shear-3d", replaced(shipped_text("shear-3d"), test::kShippedCoulomb,
                                        fmt::format("friction = \"elliptic-coulomb\"\nmu = {}\naxis_1 = {}\naxis_2 = {}",
                                                    kMu, a1, a2)));
  c.solvers.contact = solver;
  return c;
}

std::vector<std::pair<Vector, Vector>> history(const Case& c) {
  std::vector<std::pair<Vector, Vector>> out;
  run_to_end(c, [&](const TimeStepper& s, const StepReport&) { out.emplace_back(s.state().u, s.state().lambda); });
  return out;
}

/// Over the slipping nodes, 1 − cos of the angle between the slip increment and the ellipse's outward
/// normal at λ_τ (∇|λ_τ|_C's direction, (λ_1/a_1², λ_2/a_2²)).
double slip_off_normal(const TimeStepper& s, double a1, double a2) {
  const State& st = s.state();
  double off = 0;
  for (const PartContactNode& node : s.contact().nodes) {
    if (st.contact_status[node.row] != 2) continue;
    const double l0 = st.lambda[node.row * 3 + 1], l1 = st.lambda[node.row * 3 + 2];
    const double d0 = st.slip_step[node.row * 2], d1 = st.slip_step[node.row * 2 + 1];
    const double g0 = l0 / (a1 * a1), g1 = l1 / (a2 * a2);
    const double dn = std::hypot(d0, d1), gn = std::hypot(g0, g1);
    if (dn > 0) off = std::max(off, (dn * gn - (d0 * g0 + d1 * g1)) / (dn * gn));
  }
  return off;
}

TEST(LawBlocks, EllipticCoulombWithEqualAxesIsCoulombOnTheDual) {
  Case coulomb = case_of("shear-3d", shipped_text("shear-3d"));
  coulomb.solvers.contact = "active-set";
  const auto a = history(coulomb), b = history(elliptic_shear(1, 1, "active-set"));
  ASSERT_EQ(a.size(), b.size());
  double du = 0, dl = 0;
  for (std::size_t n = 0; n < a.size(); ++n) {
    du = std::max(du, relative_difference(b[n].first, a[n].first));
    dl = std::max(dl, relative_difference(b[n].second, a[n].second));
  }
  std::printf("  elliptic-coulomb with axes 1, 1 against coulomb, %zu steps: u %.3g, lambda %.3g\n", a.size(), du, dl);
  EXPECT_LE(du, 1e-12);
  EXPECT_LE(dl, 1e-12);
}

TEST(LawBlocks, EllipticCoulombFullSlipLiesOnTheEllipseAlongItsNormal) {
  const double a1 = 1.0, a2 = 0.5;
  const Case c = elliptic_shear(a1, a2, "active-set");
  const test::EllipticCoulomb law(kMu, a1, a2);
  double on_ellipse = 0, normality = 0, against_coulomb = 0;
  int sliding = 0;
  Case coulomb = case_of("shear-3d", shipped_text("shear-3d"));
  coulomb.solvers.contact = "active-set";
  const auto plain = history(coulomb);
  std::size_t n = 0;
  run_to_end(c, [&](const TimeStepper& s, const StepReport& r) {
    against_coulomb = relative_difference(s.state().u, plain[n++].first);
    if (!(r.contact.n_stick == 0 && r.contact.n_slip > 0)) return;
    ++sliding;
    for (const NodeForces& f : node_forces(s)) {
      if (f.status != 2) continue;
      on_ellipse = std::max(on_ellipse, std::abs(law.gauge(f.tangential.data(), 2) - kMu * f.normal) / (kMu * f.normal));
    }
    normality = std::max(normality, slip_off_normal(s, a1, a2));
  });
  std::printf("  elliptic-coulomb axes %g, %g: %d steps of full slip; | |lambda_t|_C / (mu lambda_n) - 1 | %.3g, "
              "slip off the ellipse's normal %.3g; u against coulomb at the end %.3g\n",
              a1, a2, sliding, on_ellipse, normality, against_coulomb);
  EXPECT_GE(sliding, 3);
  EXPECT_LE(on_ellipse, 1e-9);
  EXPECT_LE(normality, 1e-8);
  EXPECT_GT(against_coulomb, 1e-3);  // a law of its own, not the disc
}

}  // namespace
}  // namespace vpc

namespace vpc {
namespace {

/// The steps' u and λ of `c`, and its contact iterations summed over the steps.
struct Steps {
  std::vector<std::pair<Vector, Vector>> steps;
  int iterations = 0;
};
Steps run_of(const Case& c) {
  Steps out;
  run_to_end(c, [&](const TimeStepper& s, const StepReport& r) {
    out.steps.emplace_back(s.state().u, s.state().lambda);
    out.iterations += r.contact.iterations;
  });
  return out;
}

/// max over the steps of the relative differences of u and of λ.
std::pair<double, double> differences(const Steps& a, const Steps& b) {
  EXPECT_EQ(a.steps.size(), b.steps.size());
  double du = 0, dl = 0;
  for (std::size_t n = 0; n < std::min(a.steps.size(), b.steps.size()); ++n) {
    du = std::max(du, relative_difference(a.steps[n].first, b.steps[n].first));
    dl = std::max(dl, relative_difference(a.steps[n].second, b.steps[n].second));
  }
  return {du, dl};
}

/// The primal solver's Hüeber–Stadler–Wohlmuth step linearizes each node's law through its block
/// (solvers/primal_friction.hpp: n = (I − D)⁻¹ ∂P/∂s, springs γ c (I − D)⁻¹ D): with equal axes the
/// elliptic law's general path is Coulomb's disc path in other arithmetic.
TEST(LawBlocks, EllipticCoulombWithEqualAxesIsCoulombOnThePrimal) {
  Case coulomb = case_of("shear-3d", shipped_text("shear-3d"));
  coulomb.solvers.contact = "primal-active-set";
  const Steps a = run_of(coulomb), b = run_of(elliptic_shear(1, 1, "primal-active-set"));
  const auto [du, dl] = differences(b, a);
  std::printf("  primal: elliptic-coulomb with axes 1, 1 against coulomb, %zu steps: u %.3g, lambda %.3g; "
              "%d and %d contact iterations\n",
              a.steps.size(), du, dl, b.iterations, a.iterations);
  EXPECT_LE(du, 1e-12);
  EXPECT_LE(dl, 1e-12);
}

/// With axes 1 and 0.5 the primal's full slip lies on the ellipse and its answer is the dual's, both
/// solved to a residual tolerance of 1e-12. The primal's λ_τ is its reaction, whose slip forces s n settle
/// to a tenth of that tolerance of its force scale (friction_force_tolerance), so |λ_τ|_C = μ λ_ν holds
/// to 1e-12 of the face's largest normal force (a node with a small one: 2e-10 of its own).
TEST(LawBlocks, EllipticCoulombOnThePrimalLiesOnTheEllipseAndIsTheDuals) {
  const double a1 = 1.0, a2 = 0.5;
  const test::EllipticCoulomb law(kMu, a1, a2);
  Case primal = elliptic_shear(a1, a2, "primal-active-set"), dual = elliptic_shear(a1, a2, "active-set");
  primal.solvers.residual_tolerance = dual.solvers.residual_tolerance = 1e-12;
  double on_ellipse = 0, normality = 0;
  int sliding = 0;
  Steps p;
  run_to_end(primal, [&](const TimeStepper& s, const StepReport& r) {
    p.steps.emplace_back(s.state().u, s.state().lambda);
    p.iterations += r.contact.iterations;
    if (!(r.contact.n_stick == 0 && r.contact.n_slip > 0)) return;
    ++sliding;
    double off = 0, largest = 0;
    for (const NodeForces& f : node_forces(s)) {
      largest = std::max(largest, f.normal);
      if (f.status == 2) off = std::max(off, std::abs(law.gauge(f.tangential.data(), 2) - kMu * f.normal));
    }
    on_ellipse = std::max(on_ellipse, off / largest);
    normality = std::max(normality, slip_off_normal(s, a1, a2));
  });
  const Steps d = run_of(dual);
  const auto [du, dl] = differences(p, d);
  std::printf("  primal: elliptic-coulomb axes %g, %g: %d steps of full slip; | |lambda_t|_C - mu lambda_n | / max lambda_n "
              "%.3g, slip off the ellipse's normal %.3g; against the dual: u %.3g, lambda %.3g; %d contact iterations "
              "(the dual: %d)\n",
              a1, a2, sliding, on_ellipse, normality, du, dl, p.iterations, d.iterations);
  EXPECT_GE(sliding, 3);
  EXPECT_LE(on_ellipse, 1e-12);
  EXPECT_LE(normality, 1e-8);
  EXPECT_LE(du, 1e-10);
  EXPECT_LE(dl, 1e-10);
}

}  // namespace
}  // namespace vpc
