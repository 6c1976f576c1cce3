// Issue 28: the shipped shear-2d and shear-3d cases (docs/verification.md "Shear of a block on a
// rigid plane"): an elastic block clamped on top, pressed by a rigid plane that then slides.
//   (a) once the whole face slides, Σ|λ_τ,i| = μ Σ λ_ν,i to the solver's tolerance, and the
//       top's reaction has |R_τ| = μ |R_ν| (in 3D once the forces have turned parallel);
//   (b) with μ large the face sticks and the solution is the bonded one (the face's tangential
//       displacement prescribed equal to the plane's) to round-off;
//   (c) a Tresca run whose bound is μ times the Coulomb run's nodal pressure is the Coulomb run.
#include "friction_runs.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <sstream>

namespace vpc {
namespace {

using namespace friction_test;

/// The shipped cases' plane motion and friction lines, replaced by the variants below.
struct ShearCase {
  std::string name, point;
  int dim;
};
const ShearCase kShear2d{"shear-2d", "point = [\"0.02*max(t - 1, 0)\", \"0.005*min(t, 1)\"]", 2};
const ShearCase kShear3d{"shear-3d", "point = [\"0.02*max(t - 1, 0)\", \"0.01*max(t - 1, 0)\", \"0.004*min(t, 1)\"]",
                         3};
constexpr double kMu = 0.3;

void full_sliding(const ShearCase& sc) {
  const Case c = case_of(sc.name, shipped_text(sc.name));
  double err_nodes = 0, err_reaction = 0, err_reaction_last = 0;
  int sliding_steps = 0;
  run_to_end(c, [&](const TimeStepper& s, const StepReport& r) {
    double tau = 0, nu = 0;
    for (const NodeForces& f : node_forces(s)) {
      tau += f.tangential_norm();
      nu += f.normal;
    }
    // The top is the only Dirichlet part: its reaction, (R_x, R_y[, R_z]); ν is the last axis.
    const auto& R = r.reaction;
    double rt = 0;
    for (int k = 0; k + 1 < sc.dim; ++k) rt += R[k] * R[k];
    rt = std::sqrt(rt);
    const double rn = std::abs(R[sc.dim - 1]);
    std::printf("  %s t = %.2f: stick %3d slip %3d  sum|lambda_tau| / (mu sum lambda_nu) = %.12f  |R_tau| / (mu |R_nu|) = %.12f\n",
                sc.name.c_str(), r.t, r.contact.n_stick, r.contact.n_slip, tau / (kMu * nu), rt / (kMu * rn));
    EXPECT_LE(tau, kMu * nu * (1 + 1e-8));  // |λ_τ,i| ≤ μ λ_ν,i at every node
    if (r.contact.n_stick == 0 && r.contact.n_slip > 0) {
      ++sliding_steps;
      err_nodes = std::max(err_nodes, std::abs(tau / (kMu * nu) - 1));
      err_reaction = std::max(err_reaction, std::abs(rt / (kMu * rn) - 1));
      err_reaction_last = std::abs(rt / (kMu * rn) - 1);
    }
  });
  std::printf("  %s: %d steps of full sliding; largest relative error of the limit load: nodes %.3g, reaction %.3g "
              "(at the last step %.3g)\n",
              sc.name.c_str(), sliding_steps, err_nodes, err_reaction, err_reaction_last);
  EXPECT_GE(sliding_steps, 3) << "the face must slide whole in the last steps";
  EXPECT_LE(err_nodes, 1e-8);
  // In 2D every node slides along the one tangent: the reaction is μ|R_ν| exactly. In 3D the
  // tangential forces left by the pressing and the partial slip point elsewhere and turn towards
  // the plane's direction as the slip grows (|Σ λ_τ,i| < Σ |λ_τ,i| until they are parallel): the
  // reaction reaches μ|R_ν| as the block slides on (1 % short at the first sliding step, 1e-7 after
  // 0.1 of sliding).
  EXPECT_LE(sc.dim == 2 ? err_reaction : err_reaction_last, 1e-6);
}

TEST(FrictionShear, FullSlidingLimitLoadIsMuTimesNormalLoad2d) { full_sliding(kShear2d); }
TEST(FrictionShear, FullSlidingLimitLoadIsMuTimesNormalLoad3d) { full_sliding(kShear3d); }

/// (b): μ = 10 and a slide of a tenth (the face sticks and stays pressed everywhere), against the
/// frictionless run with the face's u_τ prescribed to the plane's motion; `friction` in place of
/// μ = 10 and `sets` (the contact solver) for the variants of issue 48.
void sticks_as_bonded(const ShearCase& sc, const std::string& friction = "friction = \"coulomb\"\nmu = 10.0",
                      const std::vector<std::string>& sets = {}) {
  const std::string slow_x = "0.002*max(t - 1, 0)", slow_y = "0.001*max(t - 1, 0)";
  const std::string point = sc.dim == 2 ? "point = [\"" + slow_x + "\", \"0.005*min(t, 1)\"]"
                                        : "point = [\"" + slow_x + "\", \"" + slow_y + "\", \"0.004*min(t, 1)\"]";
  const std::string text = replaced(shipped_text(sc.name), sc.point, point);
  const Case sticking = case_of(sc.name, replaced(text, test::kShippedCoulomb, friction), sets);
  std::string bonded_text = replaced(text, test::kShippedCoulomb, "friction = \"none\"");
  bonded_text += "\n[[boundary.displacement]]\nparts = [\"bottom\"]\nux = \"" + slow_x + "\"\n";
  if (sc.dim == 3) bonded_text += "uy = \"" + slow_y + "\"\n";
  const Case bonded = case_of(sc.name, bonded_text);
  std::vector<Vector> u, lambda_nu;
  run_to_end(bonded, [&](const TimeStepper& s, const StepReport&) {
    u.push_back(s.state().u);
    Vector l(s.contact().nodes.size());
    for (std::size_t i = 0; i < s.contact().nodes.size(); ++i) l[i] = s.state().lambda[s.contact().nodes[i].row];
    EXPECT_GT(l.minCoeff(), 0) << "the bonded face must stay pressed everywhere";
    lambda_nu.push_back(l);
  });
  std::size_t n = 0;
  double du = 0, dl = 0;
  run_to_end(sticking, [&](const TimeStepper& s, const StepReport& r) {
    EXPECT_EQ(r.contact.n_slip, 0) << "step " << r.n;
    ASSERT_LT(n, u.size());
    Vector l(s.contact().nodes.size());
    const auto forces = node_forces(s);
    for (std::size_t i = 0; i < forces.size(); ++i) l[i] = forces[i].normal;
    du = std::max(du, relative_difference(s.state().u, u[n]));
    dl = std::max(dl, relative_difference(l, lambda_nu[n]));
    ++n;
  });
  std::printf("  %s, %s%s: sticks; against the bonded run, max |u - u_bonded| / max |u_bonded| = %.3g, normal forces %.3g\n",
              sc.name.c_str(), replaced(friction, "\n", ", ").c_str(), sets.empty() ? "" : (", " + sets[0]).c_str(), du, dl);
  EXPECT_EQ(n, u.size());
  EXPECT_LE(du, 1e-10);
  EXPECT_LE(dl, 1e-9);
}

TEST(FrictionShear, LargeMuSticksAsTheBondedSolution2d) { sticks_as_bonded(kShear2d); }
TEST(FrictionShear, LargeMuSticksAsTheBondedSolution3d) { sticks_as_bonded(kShear3d); }

/// Issue 48: μ = 1e8 and a Tresca bound of 1e8 (the stick-slip residual scaled a sticking node's
/// round-off slip by the bound: refused at step 1) are the bonded solution too, on both solvers.
void huge_bounds_stick(const ShearCase& sc) {
  for (const std::string solver : {"active-set", "primal-active-set"})
    for (const std::string friction : {"friction = \"coulomb\"\nmu = 1e8", "friction = \"tresca\"\nfriction_bound = 1e8"}) {
      SCOPED_TRACE(solver + ", " + friction);
      sticks_as_bonded(sc, friction, {"solver.contact=" + solver});
    }
}

TEST(FrictionShear, HugeMuAndTrescaBoundStickAsTheBondedSolution2d) { huge_bounds_stick(kShear2d); }
TEST(FrictionShear, HugeMuAndTrescaBoundStickAsTheBondedSolution3d) { huge_bounds_stick(kShear3d); }

/// The reported case of issue 48: shear-2d with Coulomb's μ = `mu` (the plane sliding 0.02 a unit of
/// time) on `solver`.
Case reported_slide(const std::string& mu, const std::string& solver) {
  return case_of(kShear2d.name, replaced(shipped_text(kShear2d.name), test::kShippedCoulomb, "friction = \"coulomb\"\nmu = " + mu),
                 {"solver.contact=" + solver});
}

/// Issue 48: the reported case (shear-2d with μ = 1e5 and 1e8: refused at step 14 and step 1) runs on
/// both solvers up to μ = 1e300, no node slipping but one at the face's trailing end as it leaves
/// contact (steps 14 and 17). The primal solver failed it from μ = 100 on: that node, stuck and pulled
/// off by its own stick reaction, went free, pressed in again and stuck, for ever
/// (PrimalFriction::slip_before_leaving); from μ = 1e8 its bound μ λ_ν carried μ times K w's round-off
/// (law_determines). The dual solver failed it from μ = 1e10 on: the same node's slip state, z_ν in
/// (0, |z_τ|/μ), is too thin for the Newton steps between sticking and leaving to land in
/// (slip_before_leaving in friction_dual.cpp), and from there on μ times z_ν's round-off was more than
/// its bound (resolvable_radius). μ = 1e300 on both: its answer is μ = 1e8's to 1e-8.
TEST(FrictionShear, HugeMuRunsTheReportedSlide2d) {
  for (const std::string solver : {"active-set", "primal-active-set"}) {
    for (const std::string mu : {"100", "1e3", "1e5", "1e8", "1e10", "1e300"}) {
      SCOPED_TRACE(mu);
      SCOPED_TRACE(solver);
      int steps = 0, slipping = 0;
      run_to_end(reported_slide(mu, solver), [&](const TimeStepper&, const StepReport& r) {
        ++steps;
        EXPECT_LE(r.contact.n_slip, 1) << "step " << r.n;
        slipping += r.contact.n_slip;
      });
      EXPECT_EQ(steps, 20);
      EXPECT_EQ(slipping, 2);  // steps 14 and 17
    }
    std::vector<Vector> u;
    run_to_end(reported_slide("1e8", solver), [&](const TimeStepper& s, const StepReport&) { u.push_back(s.state().u); });
    std::size_t n = 0;
    double du = 0;
    run_to_end(reported_slide("1e300", solver), [&](const TimeStepper& s, const StepReport&) {
      ASSERT_LT(n, u.size());
      du = std::max(du, relative_difference(s.state().u, u[n++]));
    });
    std::printf("  reported slide, %s: mu = 1e300 against mu = 1e8, max |du| / max |u| = %.3g\n", solver.c_str(), du);
    EXPECT_EQ(n, u.size());
    EXPECT_LE(du, 1e-8);
  }
}

/// Issue 48: on the reported case the primal and the dual solver give the same answer step by step
/// (u and the contact forces to 1e-8 of their largest), for μ = 100, 1e8 and 1e10.
TEST(FrictionShear, HugeMuPrimalAndDualAgreeOnTheReportedSlide2d) {
  for (const std::string mu : {"100", "1e8", "1e10"}) {
    SCOPED_TRACE(mu);
    std::vector<Vector> u, lambda;
    run_to_end(reported_slide(mu, "active-set"), [&](const TimeStepper& s, const StepReport&) {
      u.push_back(s.state().u);
      lambda.push_back(s.state().lambda);
    });
    std::size_t n = 0;
    double du = 0, dl = 0;
    run_to_end(reported_slide(mu, "primal-active-set"), [&](const TimeStepper& s, const StepReport&) {
      ASSERT_LT(n, u.size());
      du = std::max(du, relative_difference(s.state().u, u[n]));
      dl = std::max(dl, relative_difference(s.state().lambda, lambda[n]));
      ++n;
    });
    std::printf("  reported slide, mu = %s: primal against dual, max |du| / max |u| = %.3g, forces %.3g\n", mu.c_str(), du, dl);
    EXPECT_EQ(n, u.size());
    EXPECT_LE(du, 1e-8);
    EXPECT_LE(dl, 1e-8);
  }
}

/// Issue 48: Coulomb with a shear limit τ_max (shear_limit): |λ_τ,i| ≤ min(μ λ_ν,i, τ_max |Γ3|_i).
/// (i) τ_max below μ p everywhere on the face: once it slides whole each node in contact carries
/// τ_max |Γ3|_i and the total is τ_max × the contact area; (ii) τ_max between the face's values of
/// μ p: each node min(μ λ_ν,i, τ_max |Γ3|_i), both kinds present; (iii) τ_max far above: the plain
/// Coulomb run to round-off. On both solvers, to 1e-8 of the force scale.
void shear_limit(const ShearCase& sc) {
  for (const std::string solver : {"active-set", "primal-active-set"}) {
    SCOPED_TRACE(solver);
    const double tol = 1e-8;
    const std::vector<std::string> sets = {"solver.contact=" + solver};
    std::vector<Vector> u, lambda;
    double low = INFINITY, high = 0;  // μ p over the face's nodes in contact, at the last step
    run_to_end(case_of(sc.name, shipped_text(sc.name), sets), [&](const TimeStepper& s, const StepReport&) {
      u.push_back(s.state().u);
      lambda.push_back(s.state().lambda);
      low = INFINITY, high = 0;
      for (const NodeForces& f : node_forces(s))
        if (f.normal > 0) low = std::min(low, kMu * f.normal / f.measure), high = std::max(high, kMu * f.normal / f.measure);
    });
    for (const double tau : {0.5 * low, 0.5 * (low + high), 1e6}) {
      SCOPED_TRACE(tau);
      const Case c = case_of(sc.name, replaced(shipped_text(sc.name), test::kShippedCoulomb, fmt::format("{}\nshear_limit = {}", test::kShippedCoulomb, tau)), sets);
      std::size_t n = 0;
      int sliding = 0, capped = 0, coulomb = 0;
      double du = 0, dl = 0, err = 0, err_total = 0;
      run_to_end(c, [&](const TimeStepper& s, const StepReport& r) {
        double total = 0, area = 0, scale = 0;
        for (const NodeForces& f : node_forces(s)) scale = std::max(scale, f.normal);
        for (const NodeForces& f : node_forces(s)) {
          const double limit = tau * f.measure, bound = std::min(kMu * std::max(f.normal, 0.0), limit);
          EXPECT_LE(f.tangential_norm(), bound + tol * scale) << "step " << r.n;
          if (r.contact.n_stick == 0 && r.contact.n_slip > 0) {
            err = std::max(err, std::abs(f.tangential_norm() - bound) / scale);
            if (f.normal > 0) (kMu * f.normal > limit ? capped : coulomb) += 1;
          }
          total += f.tangential_norm();
          if (f.normal > 0) area += f.measure;
        }
        if (r.contact.n_stick == 0 && r.contact.n_slip > 0) {
          ++sliding;
          if (tau < low) err_total = std::max(err_total, std::abs(total / (tau * area) - 1));
        }
        if (n < u.size()) {
          du = std::max(du, relative_difference(s.state().u, u[n]));
          dl = std::max(dl, relative_difference(s.state().lambda, lambda[n]));
        }
        ++n;
      });
      std::printf("  %s, %s, shear_limit %.4g (mu p in [%.4g, %.4g]): %d steps of full slip, nodes at the limit %d, "
                  "below %d; |lambda_t| - min(mu lambda_n, tau |G3|) %.3g, total / (tau area) - 1 %.3g; "
                  "against plain Coulomb u %.3g, lambda %.3g\n",
                  sc.name.c_str(), solver.c_str(), tau, low, high, sliding, capped, coulomb, err, err_total, du, dl);
      EXPECT_EQ(n, u.size());
      EXPECT_GE(sliding, 3);
      EXPECT_LE(err, tol);
      if (tau < low) {
        EXPECT_EQ(coulomb, 0);
        EXPECT_LE(err_total, tol);
        EXPECT_GT(du, 1e-3);  // not the Coulomb run
      } else if (tau < high) {
        EXPECT_GT(capped, 0);
        EXPECT_GT(coulomb, 0);
      } else {
        EXPECT_EQ(capped, 0);
        EXPECT_LE(du, 1e-10);
        EXPECT_LE(dl, 1e-10);
      }
    }
  }
}

TEST(FrictionShear, ShearLimitCapsCoulombsBound2d) { shear_limit(kShear2d); }
TEST(FrictionShear, ShearLimitCapsCoulombsBound3d) { shear_limit(kShear3d); }

/// Issue 48: the reported case: Tresca's bound acts on all of Γ3, so a plane 0.1 below the face
/// that slides drags it (the classical model, kept); those nodes are counted (n_open, status 3),
/// not taken for free (the dual solver; the primal solver does not converge on a Tresca bound out
/// of contact: not solved here). Coulomb with a shear limit in its place transmits nothing, on both.
TEST(FrictionShear, TrescaOutOfContactIsCountedAndTheShearLimitActsOnlyInContact) {
  const std::string point = "point = [\"0.02*max(t - 1, 0)\", \"-0.1\"]";
  const std::string text = replaced(shipped_text(kShear2d.name), kShear2d.point, point);
  for (const std::string solver : {"active-set", "primal-active-set"}) {
    SCOPED_TRACE(solver);
    const std::vector<std::string> sets = {"solver.contact=" + solver};
    int dragged = 0;
    if (solver == "active-set") run_to_end(case_of(kShear2d.name, replaced(text, test::kShippedCoulomb, "friction = \"tresca\"\nfriction_bound = 1.0"), sets),
               [&](const TimeStepper& s, const StepReport& r) {
                 EXPECT_EQ(r.contact.n_active, 0);
                 EXPECT_EQ(r.contact.n_stick + r.contact.n_slip, 0);
                 int open = 0;
                 for (const NodeForces& f : node_forces(s)) open += f.status == static_cast<int>(ContactStatus::Open);
                 EXPECT_EQ(open, r.contact.n_open);
                 if (r.t > 1.05) {
                   ++dragged;
                   EXPECT_NEAR(r.tangential_force[0], -2.0, 1e-9);  // the bound 1 over the face's length 2
                   EXPECT_EQ(r.contact.n_open, 21);
                 }
               });
    EXPECT_EQ(dragged, solver == "active-set" ? 10 : 0);
    run_to_end(case_of(kShear2d.name, replaced(text, test::kShippedCoulomb, test::kShippedCoulomb + "\nshear_limit = 1.0"), sets),
               [&](const TimeStepper&, const StepReport& r) {
                 EXPECT_EQ(r.tangential_force[0], 0.0);
                 EXPECT_EQ(r.contact.n_open, -1);  // no bound that acts out of contact: no column
               });
  }
}

/// (c): the Coulomb run's nodal pressures p_i(t_n) = λ_ν,i / |Γ3|_i, as a Tresca bound g(x, t) =
/// μ p_i(t_n) at node i and step n: per node an indicator of its cell of the face times the step's
/// value (t < t_1 + k/2 ? … : …), within muParser's 20,000 characters.
void tresca_is_coulomb(const ShearCase& sc) {
  const std::vector<std::string> sets = {"time.steps=4"};
  const Case coulomb = case_of(sc.name, shipped_text(sc.name), sets);
  const double h = sc.dim == 2 ? 0.1 : 0.125;  // the face's node spacing (shear-2d: 2/20, shear-3d: 1/8)
  std::vector<Vector> u, lambda;
  std::vector<double> times;
  std::vector<NodeForces> nodes;
  std::vector<std::vector<double>> bound;  // per node, per step
  run_to_end(coulomb, [&](const TimeStepper& s, const StepReport& r) {
    u.push_back(s.state().u);
    lambda.push_back(s.state().lambda);
    times.push_back(r.t);
    nodes = node_forces(s);
    bound.resize(nodes.size());
    for (std::size_t i = 0; i < nodes.size(); ++i) bound[i].push_back(kMu * nodes[i].normal / nodes[i].measure);
  });
  std::ostringstream g;
  g.precision(17);
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (*std::max_element(bound[i].begin(), bound[i].end()) <= 0) continue;
    g << (g.tellp() > 0 ? " + " : "") << "(abs(x - " << nodes[i].x[0] << ") < " << h / 2 << ")";
    if (sc.dim == 3) g << "*(abs(y - " << nodes[i].x[1] << ") < " << h / 2 << ")";
    g << "*(";
    for (std::size_t n = 0; n + 1 < times.size(); ++n) g << "t < " << 0.5 * (times[n] + times[n + 1]) << " ? " << bound[i][n] << " : ";
    g << bound[i].back() << ")";
  }
  const Case tresca =
      case_of(sc.name, replaced(shipped_text(sc.name), test::kShippedCoulomb, "friction = \"tresca\"\nfriction_bound = \"" + g.str() + "\""), sets);
  std::size_t n = 0;
  double du = 0, dl = 0;
  run_to_end(tresca, [&](const TimeStepper& s, const StepReport&) {
    ASSERT_LT(n, u.size());
    du = std::max(du, relative_difference(s.state().u, u[n]));
    dl = std::max(dl, relative_difference(s.state().lambda, lambda[n]));
    ++n;
  });
  std::printf("  %s: Tresca with g = mu p_Coulomb against Coulomb (%zu steps, a bound of %zu characters): "
              "max |u diff| / max |u| = %.3g, lambda %.3g\n",
              sc.name.c_str(), n, static_cast<std::size_t>(g.tellp()), du, dl);
  EXPECT_EQ(n, u.size());
  EXPECT_LE(du, 1e-8);
  EXPECT_LE(dl, 1e-8);
}

TEST(FrictionShear, TrescaWithMuTimesTheCoulombPressureIsTheCoulombSolution2d) { tresca_is_coulomb(kShear2d); }
TEST(FrictionShear, TrescaWithMuTimesTheCoulombPressureIsTheCoulombSolution3d) { tresca_is_coulomb(kShear3d); }

}  // namespace
}  // namespace vpc
