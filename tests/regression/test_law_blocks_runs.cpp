// Issue 49: a friction law the solvers never heard of runs through them by its block alone. The
// test-only elliptic Coulomb law (tests/support/test_laws.hpp) on shear-3d (a block pressed onto a
// plane that then slides along (2, 1)): with equal axes it is Coulomb; with unequal axes the face's
// full slip lies on the ellipse, |λ_τ|_C = μ λ_ν, and slips along its outward normal.
#include "friction_runs.hpp"
#include "solvers/contact_capabilities.hpp"
#include "test_laws.hpp"

#include <fmt/format.h>

#include <cstdio>

namespace vpc {
namespace {

using namespace friction_test;

const std::string kCoulomb = "friction = \"coulomb\"\nmu = 0.3";
constexpr double kMu = 0.3;

Case elliptic_shear(double a1, double a2, const std::string& solver) {
  test::register_test_laws();
  Case c = case_of("shear-3d", replaced(shipped_text("shear-3d"), kCoulomb,
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
    const State& st = s.state();
    for (const NodeForces& f : node_forces(s)) {
      if (f.status != 2) continue;
      on_ellipse = std::max(on_ellipse, std::abs(law.gauge(f.tangential.data(), 2) - kMu * f.normal) / (kMu * f.normal));
    }
    for (const PartContactNode& node : s.part().contact) {
      if (st.contact_status[node.row] != 2) continue;
      const double l0 = st.lambda[node.row * 3 + 1], l1 = st.lambda[node.row * 3 + 2];
      const double d0 = st.slip_step[node.row * 2], d1 = st.slip_step[node.row * 2 + 1];
      const double g0 = l0 / (a1 * a1), g1 = l1 / (a2 * a2);  // ∇|λ_τ|_C's direction
      const double dn = std::hypot(d0, d1), gn = std::hypot(g0, g1);
      if (dn > 0) normality = std::max(normality, (dn * gn - (d0 * g0 + d1 * g1)) / (dn * gn));
    }
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

/// The capability table (solvers/contact_capabilities.hpp): the primal solver's friction is the
/// disc's (Hüeber–Stadler–Wohlmuth's slip springs), so it refuses another set by name, and auto
/// takes the dual for it even where its cost rule would take the primal.
TEST(LawBlocks, ThePrimalRefusesASetThatIsNotADiscAndAutoTakesTheDual) {
  const Case primal = elliptic_shear(1, 0.5, "primal-active-set");
  try {
    TimeStepper s(primal.problem, primal.solvers);
    ADD_FAILURE() << "the primal solver took an elliptic set";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("contact solver 'primal-active-set' solves friction laws whose set is a disc "
                                         "(coulomb, tresca); friction = \"elliptic-coulomb\" needs 'active-set'"),
              std::string::npos)
        << e.what();
  }
  ContactNeeds needs;
  needs.friction = true;
  needs.non_disc = "elliptic-coulomb";
  EXPECT_EQ(pick_contact_solver("auto", 100000, "cg-gamg", needs, 3).name, "active-set");
  EXPECT_EQ(cannot_solve("active-set", needs), "");
}

}  // namespace
}  // namespace vpc
