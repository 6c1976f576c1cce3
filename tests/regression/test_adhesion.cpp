// Issue 50 (SPEC §9): Frémond's adhesion against exact solutions. cases/adhesion-bar-1d.toml: a bar
// of stiffness K = E/l glued at its right end and pulled through its left end by δ: bar and bond are
// springs in series, s = Kδ/(K + γ_ν α²), and the bond weakens at b α̇ = −α γ_ν s² (ε_a = 0, s < L).
// The lagged scheme carries α over step n with s_{n−1} frozen, exactly: α_n = α_{n−1} e^{−γ_ν s_{n−1}² k/b},
// then solves the step with the bond γ_ν α_n²: the recursion below, to round-off, on both solvers; its
// limit is the ODE K² ln α + Kγ_ν α² + γ_ν² α⁴/4 = const − γ_ν K² δ² t/b (first order in k). Beyond the
// bond length the pull is γ_ν α² L and the recursion has a closed form, also with ε_a > 0.
// cases/peel-2d.toml: both solvers agree, a debonded surface is Signorini's, a resume is bitwise.
#include "friction_runs.hpp"
#include "io/checkpoint.hpp"
#include "scheme/step_failure.hpp"
#include "solvers/contact_capabilities.hpp"

#include <fmt/format.h>

#include <filesystem>

namespace vpc {
namespace {

namespace fs = std::filesystem;
using namespace friction_test;

constexpr double kK = 100.0, kGamma = 200.0, kDelta = 0.01, kB = 0.005;  // adhesion-bar-1d

Case bar(const std::vector<std::string>& sets = {}, const std::string& solver = "active-set") {
  Case c = case_of("adhesion-bar-1d", shipped_text("adhesion-bar-1d"), sets);
  c.solvers.contact = solver;
  return c;
}

Case peel(const std::vector<std::string>& sets = {}, const std::string& solver = "active-set") {
  std::vector<std::string> all = {"time.steps=40", "time.T=0.4"};
  all.insert(all.end(), sets.begin(), sets.end());
  Case c = case_of("peel-2d", shipped_text("peel-2d"), all);
  c.solvers.contact = solver;
  return c;
}

double field(const State& s, const std::string& name, Eigen::Index i = 0) {
  const SurfaceField* f = s.surface_field(name);
  if (!f) throw std::runtime_error("no surface field " + name);
  return f->values[i];
}

/// The bar's separation with the bond γ α²: the two springs in series.
double separation(double alpha) { return kK * kDelta / (kK + kGamma * alpha * alpha); }

TEST(AdhesionExact, TheLaggedBondingIsTheClosedFormRecursionToRoundOff) {
  for (const std::string solver : {"active-set", "primal-active-set"}) {
    SCOPED_TRACE(solver);
    double alpha = 1, s_before = 0, off_alpha = 0, off_s = 0, off_force = 0, off_released = 0, released = 0;
    int steps = 0;
    run_to_end(bar({}, solver), [&](const TimeStepper& t, const StepReport& r) {
      const double before = alpha;
      alpha *= std::exp(-kGamma * s_before * s_before * r.k / kB);
      released += kGamma * (before * before - alpha * alpha) * s_before * s_before / 2;
      const double s = separation(alpha);
      const State& st = t.state();
      off_alpha = std::max(off_alpha, std::abs(field(st, "bonding") - alpha));
      off_s = std::max(off_s, std::abs(field(st, "separation") - s) / s);
      // The bond's pull is the node's force (a tension: λ < 0) and the history's adhesive force.
      off_force = std::max(off_force, std::abs(-st.lambda[0] - kGamma * alpha * alpha * s) / (kGamma * s));
      off_force = std::max(off_force, std::abs(r.surface_integral[0] - kGamma * alpha * alpha * s) / (kGamma * s));
      off_released = std::max(off_released, std::abs(field(st, "debonding_energy") - released) / (kGamma * s * s));
      s_before = s;
      steps = r.n;
    });
    std::printf("  %s, %d steps: bonding against the recursion %.3g, separation %.3g, force %.3g, released energy "
                "%.3g; alpha(T) = %.6f\n",
                solver.c_str(), steps, off_alpha, off_s, off_force, off_released, alpha);
    EXPECT_EQ(steps, 20);
    EXPECT_LT(alpha, 0.9);  // it debonds noticeably
    EXPECT_LE(off_alpha, 1e-13);
    EXPECT_LE(off_s, 1e-12);
    EXPECT_LE(off_force, 1e-12);
    EXPECT_LE(off_released, 1e-12);
  }
}

/// The ODE's α(t): f(α) = f(1) − γ K² δ² t / b, f(α) = K² ln α + K γ α² + γ² α⁴/4 (f increasing: bisection).
double ode_bonding(double t) {
  const auto f = [](double a) { return kK * kK * std::log(a) + kK * kGamma * a * a + kGamma * kGamma * a * a * a * a / 4; };
  const double target = f(1.0) - kGamma * kK * kK * kDelta * kDelta * t / kB;
  double lo = 1e-12, hi = 1;
  for (int i = 0; i < 200; ++i) (f(0.5 * (lo + hi)) < target ? lo : hi) = 0.5 * (lo + hi);
  return 0.5 * (lo + hi);
}

TEST(AdhesionExact, ItConvergesToTheOdeAtFirstOrderInTheStep) {
  std::vector<double> errors;
  for (int steps : {20, 40, 80}) {
    const Case c = bar({fmt::format("time.steps={}", steps)});
    TimeStepper s(c.problem, c.solvers);
    while (!s.done()) ASSERT_TRUE(s.step().ok);
    errors.push_back(std::abs(field(s.state(), "bonding") - ode_bonding(1.0)));
  }
  const double rate1 = std::log2(errors[0] / errors[1]), rate2 = std::log2(errors[1] / errors[2]);
  std::printf("  bonding at t = 1 against the ODE (alpha = %.8f): %.4g, %.4g, %.4g at 20, 40, 80 steps: rates %.3f, %.3f\n",
              ode_bonding(1.0), errors[0], errors[1], errors[2], rate1, rate2);
  EXPECT_NEAR(rate1, 1.0, 0.1);
  EXPECT_NEAR(rate2, 1.0, 0.05);
}

TEST(AdhesionExact, ErrorControlledStepsFollowTheBonding) {
  // The elastic bar has no error of its own in z or β: the estimate is the bonding's lag alone
  // ((k/2)|α'(s_n) − α'(s_{n−1})|, SurfaceUpdate::rate_change). A tighter tolerance takes more steps
  // and lands nearer the ODE, about in proportion (first order).
  std::vector<double> errors;
  std::vector<int> steps;
  for (const char* tolerance : {"time.tolerance=1e-2", "time.tolerance=1e-3"}) {
    const Case c = bar({tolerance});
    ASSERT_TRUE(c.problem->step_control.has_value());
    int n = 0;
    double alpha = 0;
    run_to_end(c, [&](const TimeStepper& t, const StepReport&) {
      ++n;
      alpha = field(t.state(), "bonding");
    });
    errors.push_back(std::abs(alpha - ode_bonding(1.0)));
    steps.push_back(n);
  }
  std::printf("  error-controlled: %d and %d steps at tolerances 1e-2 and 1e-3, bonding at t = 1 off the ODE by %.3g "
              "and %.3g\n",
              steps[0], steps[1], errors[0], errors[1]);
  EXPECT_GT(steps[1], 4 * steps[0]);
  EXPECT_LT(errors[1], errors[0] / 4);
  EXPECT_LT(errors[0], 0.05);
}

TEST(AdhesionExact, BeyondTheBondLengthThePullIsConstantAndTheBondDecaysInClosedForm) {
  // L = 1e-3 below the separation: each step from the second on is pulled with γ α² L, and α follows
  // α_n = ε/c + (α_{n−1} − ε/c) e^{−c k/b}, c = γ L², from α_1 = 1 (the first step starts from s_0 = 0).
  const double L = 1e-3, c = kGamma * L * L, k = 0.05;
  for (const double energy : {0.0, 5e-5}) {
    for (const std::string solver : {"active-set", "primal-active-set"}) {
      SCOPED_TRACE(solver + fmt::format(", epsilon_a = {}", energy));
      double off = 0, off_force = 0, alpha = 1;
      run_to_end(bar({"contact.bond_length=1e-3", fmt::format("contact.adhesion_energy={}", energy)}, solver),
                 [&](const TimeStepper& t, const StepReport& r) {
                   if (r.n > 1 && c * alpha > energy) alpha = energy / c + (alpha - energy / c) * std::exp(-c * k / kB);
                   off = std::max(off, std::abs(field(t.state(), "bonding") - alpha));
                   off_force = std::max(off_force, std::abs(-t.state().lambda[0] - kGamma * alpha * alpha * L) / (kGamma * L));
                   EXPECT_GT(field(t.state(), "separation"), L);
                 });
      EXPECT_LE(off, 1e-14);
      EXPECT_LE(off_force, 1e-12);
      if (energy > 0) {
        EXPECT_GT(alpha, energy / c);  // toward its rest ε/c, never below
      }
    }
  }
}

// cases/pull-off-1d.toml (verification (a)): a bar held by its bond alone under an end force F. The
// bond carries F: γ α² s = F, and b α̇ = −α γ s² gives α⁴ = α_0⁴ − 4F²t/(bγ) until γ α² L = F (pull-off,
// t_pull = bγ(α_0⁴ − (F/(γL))²)/(4F²) = 0.75). Lagged: α_n = α_{n−1} e^{−γ s_{n−1}² k/b}, s_0 = 0, and
// step n has an equilibrium while γ α_n² L ≥ F.
constexpr double kF = 1.0, kGammaP = 200.0, kLengthP = 0.01, kBP = 0.02;
constexpr double kPullOff = kBP * kGammaP * (1 - (kF / (kGammaP * kLengthP)) * (kF / (kGammaP * kLengthP))) / (4 * kF * kF);

Case glued(int steps, double T = 1.0) {
  return case_of("pull-off-1d", shipped_text("pull-off-1d"),
                 {fmt::format("time.steps={}", steps), fmt::format("time.T={}", T)});
}

/// Runs the glued bar until it ends or fails: each accepted step to `each`, and the failed one's report.
StepReport run_glued(const Case& c, const std::function<void(const TimeStepper&, const StepReport&)>& each) {
  TimeStepper t(c.problem, c.solvers);
  EXPECT_EQ(t.contact_solver(), "primal-active-set");  // auto: K is singular without the bond
  while (!t.done()) {
    const StepReport r = t.step();
    if (!r.ok) return r;
    each(t, r);
  }
  return {};
}

TEST(AdhesionExact, AGluedEndUnderAForceFollowsTheRecursionToItsPullOff) {
  double alpha = 1, s_before = 0, off_alpha = 0, off_s = 0, off_force = 0;
  int held = 0;
  const double k = 0.05;
  const StepReport failed = run_glued(glued(20), [&](const TimeStepper& t, const StepReport& r) {
    alpha *= std::exp(-kGammaP * s_before * s_before * k / kBP);
    const double s = kF / (kGammaP * alpha * alpha);
    off_alpha = std::max(off_alpha, std::abs(field(t.state(), "bonding") - alpha));
    off_s = std::max(off_s, std::abs(field(t.state(), "separation") - s) / s);
    off_force = std::max(off_force, std::abs(-t.state().lambda[0] - kF) / kF);  // the bond carries F
    s_before = s;
    held = r.n;
  });
  // The step after the last held one: its α cannot hold F any more.
  const double next = alpha * std::exp(-kGammaP * s_before * s_before * k / kBP);
  std::printf("  held %d steps (alpha %.6f: pull %.4f >= F), pull-off at step %d (t = %.4g; exact %.4g): its alpha "
              "%.6f pulls %.4f < F; bonding against the recursion %.3g, separation %.3g, force %.3g\n",
              held, alpha, kGammaP * alpha * alpha * kLengthP, failed.n, failed.t, kPullOff, next,
              kGammaP * next * next * kLengthP, off_alpha, off_s, off_force);
  EXPECT_EQ(failed.n, held + 1);
  EXPECT_TRUE(failed.contact.pulled_off);
  EXPECT_FALSE(failed.ok);
  EXPECT_GE(kGammaP * alpha * alpha * kLengthP, kF);
  EXPECT_LT(kGammaP * next * next * kLengthP, kF);
  EXPECT_GT(failed.contact.pull_off_excess, 1e-3);
  EXPECT_LE(off_alpha, 1e-13);
  EXPECT_LE(off_s, 1e-12);
  EXPECT_LE(off_force, 1e-12);
  EXPECT_NE(step_failure(failed, 1e-8).find(fmt::format("pull-off at t = {:.6g}", failed.t)), std::string::npos);
  EXPECT_FALSE(halving_can_help(failed, 1e-8));
}

TEST(AdhesionExact, TheGluedEndsBondingAndPullOffTimeConvergeAtFirstOrder) {
  // α at t = 0.5 against α⁴ = 1 − 4F²t/(bγ); the pull-off step's time against t_pull.
  std::vector<double> errors, late;
  for (int steps : {20, 40, 80, 160}) {
    double alpha_half = 0;
    const StepReport failed = run_glued(glued(steps), [&](const TimeStepper& t, const StepReport& r) {
      if (std::abs(r.t - 0.5) < 1e-9) alpha_half = field(t.state(), "bonding");
    });
    ASSERT_TRUE(failed.contact.pulled_off) << steps;
    errors.push_back(std::abs(alpha_half - std::pow(1 - 4 * kF * kF * 0.5 / (kBP * kGammaP), 0.25)));
    late.push_back(failed.t - kPullOff);
    std::printf("  %3d steps: bonding at t = 0.5 off by %.4g; pull-off at t = %.6g (%.4g after the exact %.4g)\n",
                steps, errors.back(), failed.t, late.back(), kPullOff);
  }
  for (std::size_t i = 1; i < errors.size(); ++i) {
    EXPECT_NEAR(std::log2(errors[i - 1] / errors[i]), 1.0, 0.1);
    EXPECT_GT(late[i], 0);                         // the lag delays it ...
    EXPECT_LT(late[i], 0.6 * late[i - 1]);        // ... by O(k)
  }
}

TEST(AdhesionExact, ErrorControlledStepsFindTheGluedEndsPullOff) {
  // Rejected steps restart the primal from an extrapolated warm start whose set releases the bond (K
  // singular): the iteration puts it back on its spring. The pull-off lands near the exact 0.75.
  const Case c = case_of("pull-off-1d", shipped_text("pull-off-1d"), {"time.T=1", "time.tolerance=1e-3"});
  const StepReport failed = run_glued(c, [](const TimeStepper&, const StepReport&) {});
  std::printf("  error-controlled: pull-off at t = %.6f (exact %.4g) at step %d\n", failed.t, kPullOff, failed.n);
  EXPECT_TRUE(failed.contact.pulled_off);
  EXPECT_NEAR(failed.t, kPullOff, 5e-3);
}

TEST(AdhesionKeys, HeldByBondIsCheckedAndTheDualRefused) {
  // Without the key the bar is not held; with it, the dual (which needs K⁻¹) is refused.
  std::string text = shipped_text("pull-off-1d");
  const std::string key = "held_by_bond = true";
  text.replace(text.find(key), key.size(), "");
  try {
    (void)case_of("pull-off-1d", text);
    ADD_FAILURE() << "a bar held by nothing was accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("held_by_bond = true"), std::string::npos) << e.what();
  }
  Case c = glued(20);
  c.solvers.contact = "active-set";
  try {
    TimeStepper t(c.problem, c.solvers);
    ADD_FAILURE() << "the dual was not refused";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("'primal-active-set' solves it"), std::string::npos) << e.what();
  }
}

// SPEC §9's tangential bond: a block W × H bonded along its bottom and sheared by its top (u_x = δ, u_y = 0),
// its sides loaded with the complementary shear (0, ±τ): simple shear u_x = v + (δ − v) y/H, u_y = 0 is
// exact on any mesh, bond and block two springs in series, γ_τ α² v = τ = μ (δ − v)/H.
std::string sheared_block(double gamma_tau, double length, double viscosity, double tau, int dim = 2) {
  // The material, the bond and the steps, the same in 2D and 3D.
  const std::string rest = fmt::format(R"toml(
[viscoplasticity]
law = "elastic"
[damage]
source = "zero"
[contact]
gap = 0.0
adhesion = "fremond"
bond_stiffness = 1000.0
bond_shear_stiffness = {}
bond_length = {}
bond_viscosity = {}
[time]
T = 1.0
steps = 4
)toml",
                                       gamma_tau, length, viscosity);
  if (dim == 3)  // height along z, sheared along (cos 30°, sin 30°, 0): the bond's disc, not a box
    return fmt::format(R"toml(
[case]
name = "bond-shear-3d"
[mesh]
generator = "box"
lower = [0.0, 0.0, 0.0]
upper = [1.0, 0.5, 0.5]
cells = [4, 2, 2]
[boundary]
contact = ["bottom"]
[[boundary.displacement]]
parts = ["top"]
ux = "0.01 * cos(pi / 6)"
uy = "0.01 * sin(pi / 6)"
uz = "0"
[loads]
f2 = ["0", "0", "x < 1e-9 ? -{0} * cos(pi / 6) : x > 1 - 1e-9 ? {0} * cos(pi / 6) : y < 1e-9 ? -{0} * sin(pi / 6) : {0} * sin(pi / 6)"]
[elasticity]
kind = "isotropic"
E = 100.0
nu = 0.0
)toml",
                       tau) + rest;
  return fmt::format(R"toml(
[case]
name = "bond-shear"
[mesh]
generator = "rectangle"
lower = [0.0, 0.0]
upper = [1.0, 0.5]
cells = [8, 4]
[boundary]
contact = ["bottom"]
[[boundary.displacement]]
parts = ["top"]
ux = "0.01"
uy = "0"
[loads]
f2 = ["0", "x < 0.5 ? -{0} : {0}"]
[elasticity]
kind = "plane-strain"
E = 100.0
nu = 0.0
)toml",
                     tau) + rest;
}

TEST(AdhesionShear, ABondedBlockInSimpleShearIsTheSeriesSpringsExactly) {
  // μ = E/2 = 50, H = 0.5, γ_τ = 100, δ = 0.01: v = (μ/H) δ / (μ/H + γ_τ) = δ/2, τ = γ_τ v = 0.5 (α = 1: b huge).
  for (int dim : {2, 3}) {
    SCOPED_TRACE(dim);
    for (const std::string solver : {"active-set", "primal-active-set"}) {
    SCOPED_TRACE(solver);
    const double delta = 0.01, v = delta / 2, tau = 100 * v, H = 0.5;
    Case c = case_of("peel-2d", sheared_block(100, 1.0, 1e12, tau, dim));
    c.solvers.contact = solver;
    double off_u = 0, off_slip = 0, off_shear = 0, sum_tau = 0;
    run_to_end(c, [&](const TimeStepper& t, const StepReport& r) {
      const State& st = t.state();
      const Mesh& mesh = t.mesh();
      // u = (v + (δ − v) h/H) e along the shear e, h the height (y in 2D, z in 3D).
      const double e[3] = {dim == 3 ? std::cos(M_PI / 6) : 1.0, dim == 3 ? std::sin(M_PI / 6) : 0.0, 0.0};
      for (int i = 0; i < mesh.n_nodes(); ++i) {
        const double h = mesh.node(i)[dim - 1];
        for (int j = 0; j < dim; ++j)
          off_u = std::max(off_u, std::abs(st.u[i * dim + j] - (v + (delta - v) * h / H) * e[j]) / delta);
      }
      const SurfaceField* slip = st.surface_field("bond_slip");
      ASSERT_NE(slip, nullptr);
      sum_tau = 0;
      for (int k = 0; k < st.lambda.size() / st.contact_block; ++k) {
        off_slip = std::max(off_slip, std::abs(std::hypot(slip->values[2 * k], slip->values[2 * k + 1]) - v) / v);
        off_shear = std::max(off_shear, std::abs(field(st, "adhesive_shear", k) - tau) / tau);
        sum_tau += st.lambda.segment(k * st.contact_block + 1, st.contact_block - 1).norm();
      }
      EXPECT_LE(r.contact.residuals.max(), 1e-10);
    });
    const double area = dim == 3 ? 0.5 : 1.0;
    std::printf("  d = %d, %s: u against simple shear %.3g (of delta), bond slip %.3g, shear traction %.3g, sum "
                "|lambda_tau| %.15g (tau W = %g)\n",
                dim, solver.c_str(), off_u, off_slip, off_shear, sum_tau, tau * area);
    EXPECT_LE(off_u, 1e-12);
    EXPECT_LE(off_slip, 1e-12);
    EXPECT_LE(off_shear, 1e-12);
    EXPECT_NEAR(sum_tau, tau * area, 1e-12);
    }
  }
}

TEST(AdhesionShear, TheTangentialStretchWeakensTheBondAsTheLaggedRecursion) {
  // b = 0.05: the bond weakens under the stretch; each node's α follows α_n = α_{n−1} e^{−c k/b},
  // c = γ_ν R(s_{n−1})² + γ_τ R(|v_{n−1}|)², from its own state at t_{n−1}; its tangential force is
  // γ_τ α_n² |Γ3|_i P_L(v_n) (the traction γ_τ α_n² min(|v_n|, L)). Also past L (L = 0.002 < v).
  for (const std::string solver : {"active-set", "primal-active-set"})
  for (const double L : {1.0, 0.002}) {
    SCOPED_TRACE(solver + fmt::format(", L = {}", L));
    Case c = case_of("peel-2d", sheared_block(100, L, 0.05, 0.5));
    c.solvers.contact = solver;
    std::vector<double> alpha, s, v;
    double off_alpha = 0, off_traction = 0, least = 1;
    run_to_end(c, [&](const TimeStepper& t, const StepReport& r) {
      const State& st = t.state();
      const SurfaceField* slip = st.surface_field("bond_slip");
      const auto m = static_cast<std::size_t>(st.lambda.size() / st.contact_block);
      if (alpha.empty()) alpha.assign(m, 1.0), s.assign(m, 0.0), v.assign(m, 0.0);
      for (std::size_t k = 0; k < m; ++k) {
        const double R = std::min(s[k], L), R_tau = std::min(v[k], L);
        alpha[k] *= std::exp(-(1000 * R * R + 100 * R_tau * R_tau) * r.k / 0.05);
        off_alpha = std::max(off_alpha, std::abs(field(st, "bonding", static_cast<Eigen::Index>(k)) - alpha[k]));
        s[k] = field(st, "separation", static_cast<Eigen::Index>(k));
        v[k] = std::hypot(slip->values[2 * static_cast<Eigen::Index>(k)], slip->values[2 * static_cast<Eigen::Index>(k) + 1]);
        off_traction = std::max(off_traction, std::abs(field(st, "adhesive_shear", static_cast<Eigen::Index>(k)) -
                                                       100 * alpha[k] * alpha[k] * std::min(v[k], L)));
        least = std::min(least, alpha[k]);
      }
      // (the primal's tangential forces settle to its slip-force tolerance, 1e-9 of the force scale)
      EXPECT_LE(r.contact.residuals.max(), solver == "active-set" ? 1e-10 : 1e-9);
    });
    std::printf("  %s, L = %g: bonding against the recursion %.3g, shear traction %.3g; least alpha %.4f\n",
                solver.c_str(), L, off_alpha, off_traction, least);
    EXPECT_LE(off_alpha, 1e-13);
    EXPECT_LE(off_traction, 1e-12);
    EXPECT_LT(least, 0.99);
  }
}

TEST(AdhesionShear, TheTangentialBondIsRefusedWhereItCannotBeSolved) {
  const std::string text = sheared_block(100, 1.0, 1.0, 0.5);
  auto error_of = [&](const std::vector<std::string>& sets, const std::string& solver = "auto") {
    try {
      Case c = case_of("peel-2d", text, sets);
      c.solvers.contact = solver;
      TimeStepper t(c.problem, c.solvers);
      return std::string();
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
  };
  EXPECT_NE(error_of({"contact.friction=\"coulomb\"", "contact.mu=0.3"}).find("a tangential bond (bond_shear_stiffness) is "
                                                                             "solved on frictionless contact"),
            std::string::npos);
  EXPECT_NE(error_of({}, "penalty-duality").find("penalty-duality"), std::string::npos);
  // Held by its bonds (normal) and a roller on its left side: the tangential bond cannot join the pull-off test.
  std::string held = test::replaced(text, "parts = [\"top\"]\nux = \"0.01\"\nuy = \"0\"", "parts = [\"left\"]\nux = \"0\"");
  held = test::replaced(held, "[time]", "held_by_bond = true\n[time]");
  try {
    Case c = case_of("peel-2d", held);
    c.solvers.contact = "primal-active-set";
    TimeStepper t(c.problem, c.solvers);
    ADD_FAILURE() << "a tangential bond holding a body was not refused";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("a tangential bond"), std::string::npos) << e.what();
  }
  EXPECT_NE(error_of({"contact.bond_shear_stiffness=-1"}).find("bond_shear_stiffness"), std::string::npos);
  EXPECT_EQ(error_of({}), "");
}

/// The largest |x − y| / max|y| over the steps of two runs, of u and of λ.
std::pair<double, double> runs_apart(const Case& a, const Case& b) {
  std::vector<Vector> ua, la;
  run_to_end(a, [&](const TimeStepper& s, const StepReport&) {
    ua.push_back(s.state().u);
    la.push_back(s.state().lambda);
  });
  double du = 0, dl = 0;
  std::size_t n = 0;
  run_to_end(b, [&](const TimeStepper& s, const StepReport&) {
    du = std::max(du, (s.state().u - ua[n]).cwiseAbs().maxCoeff() / s.state().u.cwiseAbs().maxCoeff());
    dl = std::max(dl, (s.state().lambda - la[n]).cwiseAbs().maxCoeff() / std::max(s.state().lambda.cwiseAbs().maxCoeff(), 1e-300));
    ++n;
  });
  EXPECT_EQ(n, ua.size());
  return {du, dl};
}

TEST(AdhesionShear, TheTwoSolversAgreeOnTheLapJoint) {
  // lap-shear-2d over 40 steps: the dual's Tresca disc with the bond's compliance and the primal's two
  // tangential states (the bond's spring, its pull beyond L) give one answer while the front runs.
  std::vector<std::string> sets = {"time.steps=40", "time.T=0.4"};
  Case dual = case_of("lap-shear-2d", shipped_text("lap-shear-2d"), sets), primal = dual;
  dual.solvers.contact = "active-set";
  primal = case_of("lap-shear-2d", shipped_text("lap-shear-2d"), sets);
  primal.solvers.contact = "primal-active-set";
  const auto [du, dl] = runs_apart(dual, primal);
  std::printf("  lap-shear-2d, 40 steps: primal against dual, u %.3g, lambda %.3g (of their largest)\n", du, dl);
  EXPECT_LE(du, 1e-9);
  EXPECT_LE(dl, 1e-7);  // the primal's tangential forces to its slip-force tolerance (1e-9 of the force scale)
}

TEST(AdhesionRuns, TheTwoSolversAgreeOnThePeel) {
  const auto [du, dl] = runs_apart(peel({}, "active-set"), peel({}, "primal-active-set"));
  std::printf("  peel-2d, 40 steps, primal against dual: u %.3g, lambda %.3g\n", du, dl);
  // (The dual splits each bonded row's force into its pressing part and its pull, a box QP solved exactly; the
  // primal takes the bond's spring as a third state of its active set.)
  EXPECT_LE(du, 1e-10);
  EXPECT_LE(dl, 1e-10);
  // The front moves: part of the bottom debonds, and the bulk damages.
  const Case c = peel();
  TimeStepper s(c.problem, c.solvers);
  StepReport last;
  while (!s.done()) last = s.step();
  EXPECT_GT(last.surface_integral[1], 0.2);  // debonded_fraction
  EXPECT_LT(last.beta_min, 0.995);
}

TEST(AdhesionRuns, WithCoulombFrictionAPullingNodeSlidesFreelyAndTheSolversAgree) {
  // Coulomb's bound is μ max(λ_ν, 0): 0 where the bond pulls (λ_ν < 0), so such a node carries no
  // tangential force; the nodes the peel presses ahead of the front carry |λ_τ| ≤ μ λ_ν.
  const std::vector<std::string> coulomb = {"contact.friction=\"coulomb\"", "contact.mu=0.5"};
  std::vector<std::vector<double>> normal[2], tangential[2];
  int k = 0;
  double force_scale = 0;  // the residuals' (max of λ, F and Ku)
  for (const std::string solver : {"active-set", "primal-active-set"}) {
    SCOPED_TRACE(solver);
    int pulling = 0, pressing = 0;
    run_to_end(peel(coulomb, solver), [&](const TimeStepper& s, const StepReport& r) {
      std::vector<double> n, t;
      for (const NodeForces& f : node_forces(s)) {
        n.push_back(f.normal);
        t.push_back(f.tangential_norm());
        // The primal's slip forces are exact to its friction tolerance, 1e-9 of the residuals' force scale.
        const double slack = 1e-9 * r.contact.residuals.force_scale;
        force_scale = std::max(force_scale, r.contact.residuals.force_scale);
        if (f.normal < 0) {
          ++pulling;
          EXPECT_LE(f.tangential_norm(), slack);
        } else if (f.normal > 0) {
          ++pressing;
          EXPECT_LE(f.tangential_norm(), 0.5 * f.normal + slack);
        }
      }
      normal[k].push_back(n);
      tangential[k].push_back(t);
    });
    EXPECT_GT(pulling, 0);
    EXPECT_GT(pressing, 0);
    ++k;
  }
  double dn = 0, dt = 0, scale = 0;
  for (std::size_t n = 0; n < normal[0].size(); ++n)
    for (std::size_t i = 0; i < normal[0][n].size(); ++i) {
      dn = std::max(dn, std::abs(normal[0][n][i] - normal[1][n][i]));
      dt = std::max(dt, std::abs(tangential[0][n][i] - tangential[1][n][i]));
      scale = std::max(scale, std::abs(normal[0][n][i]));
    }
  std::printf("  peel-2d with Coulomb mu = 0.5, 40 steps, primal against dual: normal %.3g, tangential %.3g of the "
              "largest normal force %.3g (%.3g, %.3g of the residuals' force scale %.3g)\n",
              dn / scale, dt / scale, scale, dn / force_scale, dt / force_scale, force_scale);
  // The primal's frictional iteration stops at its slip-force tolerance, 1e-9 of the force scale: the two
  // agree to the steps' residual tolerance, 1e-8 of it.
  EXPECT_LE(dn, 1e-8 * force_scale);
  EXPECT_LE(dt, 1e-8 * force_scale);
}

TEST(AdhesionRuns, WithNormalComplianceTheBondPullsBelowTheLawsPressingBranch) {
  // The bar pushed into the foundation and pulled back off it (δ(t) = 0.01 cos 6t): a compliant node presses
  // with k d where it penetrates and the bond pulls with a min(s, L) where it separates; both solvers, and
  // the bar's exact answer: the node's force is the series springs' at each branch.
  const std::vector<std::string> sets = {"contact.law=\"normal-compliance\"", "contact.stiffness=1000",
                                         "boundary.displacement[0].ux=\"-0.01*cos(6*t)\""};
  for (const std::string solver : {"active-set", "primal-active-set"}) {
    SCOPED_TRACE(solver);
    double alpha = 1, s_before = 0, off = 0;
    int pressed = 0, pulled = 0;
    run_to_end(bar(sets, solver), [&](const TimeStepper& t, const StepReport& r) {
      const double delta = 0.01 * std::cos(6 * r.t);  // the left end's pull (a push where < 0)
      alpha *= std::exp(-kGamma * s_before * s_before * r.k / kB);
      // Springs in series with the bar K: pressing k = 1000 (δ < 0), the bond γ α² (δ > 0).
      const double spring = delta < 0 ? 1000.0 : kGamma * alpha * alpha;
      const double force = -kK * spring * delta / (kK + spring);  // λ: > 0 pressing, < 0 pulling
      off = std::max(off, std::abs(t.state().lambda[0] - force) / 0.7);
      s_before = delta > 0 ? kK * delta / (kK + spring) : 0.0;
      (delta < 0 ? pressed : pulled) += 1;
    });
    EXPECT_GT(pressed, 0);
    EXPECT_GT(pulled, 0);
    EXPECT_LE(off, 1e-13);
  }
}

TEST(AdhesionRuns, OnAPairTheSlaveSideBondsAndThePatchTestHolds) {
  // contact-patch-2d's blocks bonded across their pair and pulled apart (the upper top up by 0.01 t): each
  // block in uniaxial stress, E* = E/(1 − ν²) in plane strain, in series with the bond, so the separation
  // is uniform, s = δ/(1 + γ α² (H_l/E*_l + H_u/E*_u)), α is uniform and follows the recursion, and the
  // pair's force is γ α² s times the interface's length 1 (the dual mortar passes the patch test).
  const double gamma = 2e4, b = 0.01, nu = 0.3;
  const double compliance = 0.5 / (1000 / (1 - nu * nu)) + 0.5 / (3000 / (1 - nu * nu));
  const std::vector<std::string> sets = {"boundary.displacement[0].uy=\"0.01*t\"", "contact.pair[0].adhesion=\"fremond\"",
                                         fmt::format("contact.pair[0].bond_stiffness={}", gamma),
                                         "contact.pair[0].bond_length=1", fmt::format("contact.pair[0].bond_viscosity={}", b),
                                         "time.steps=10"};
  for (const std::string solver : {"active-set", "primal-active-set"}) {
    SCOPED_TRACE(solver);
    Case c = case_of("contact-patch-2d", shipped_text("contact-patch-2d"), sets);
    c.solvers.contact = solver;
    double alpha = 1, s_before = 0, off_alpha = 0, off_force = 0;
    run_to_end(c, [&](const TimeStepper& t, const StepReport& r) {
      alpha *= std::exp(-gamma * s_before * s_before * r.k / b);
      const double s = 0.01 * r.t / (1 + gamma * alpha * alpha * compliance);
      const Vector& a = t.state().surface_field("bonding")->values;
      off_alpha = std::max(off_alpha, (a.array() - alpha).abs().maxCoeff());
      off_force = std::max(off_force, std::abs(r.surface_integral[0] - gamma * alpha * alpha * s) / (gamma * s));
      s_before = s;
    });
    std::printf("  %s: the slave's bonding against the uniform recursion %.3g, adhesive force %.3g (alpha = %.4f)\n",
                solver.c_str(), off_alpha, off_force, alpha);
    EXPECT_LT(alpha, 0.95);
    EXPECT_LE(off_alpha, 1e-10);
    EXPECT_LE(off_force, 1e-10);
  }
}

TEST(AdhesionRuns, ADebondedSurfaceIsSignorinis) {
  for (const std::string solver : {"active-set", "primal-active-set"}) {
    SCOPED_TRACE(solver);
    // The strip pressed down at its end (Signorini's forces not all zero) with α_0 = 0, against no adhesion.
    const std::vector<std::string> down = {"boundary.displacement[0].uy=-0.02*t"};
    std::vector<std::string> debonded = down;
    debonded.push_back("contact.bonding=0");
    std::vector<std::string> none = down;
    none.push_back("contact.adhesion=\"none\"");
    const auto [du, dl] = runs_apart(peel(debonded, solver), peel(none, solver));
    // Exactly: every bond is 0, and both solvers then take the path of the law without adhesion (the
    // dual's box QP has no split rows, the primal no third state).
    EXPECT_EQ(du, 0.0);
    EXPECT_EQ(dl, 0.0);
  }
}

TEST(AdhesionRuns, AResumeMidDebondingIsTheUninterruptedRun) {
  const Case c = peel();
  TimeStepper a(c.problem, c.solvers), b(c.problem, c.solvers);
  for (int i = 0; i < 17; ++i) ASSERT_TRUE(a.step().ok);
  const fs::path dir = fs::temp_directory_path() / "vpc_adhesion_ckpt";
  fs::remove_all(dir);
  fs::create_directories(dir);
  write_checkpoint(a, dir, "peel-2d", {}, RunTotals{});
  ASSERT_TRUE(resume_from_checkpoint(b, dir).has_value());
  while (!a.done()) {
    a.step();
    b.step();
  }
  for (const char* name : {"bonding", "separation", "debonding_energy"})
    EXPECT_EQ(b.state().surface_field(name)->values, a.state().surface_field(name)->values) << name;
  EXPECT_EQ(b.state().u, a.state().u);
  EXPECT_EQ(b.state().lambda, a.state().lambda);
  fs::remove_all(dir);
}

TEST(AdhesionRuns, ErrorControlledStepsKeepTheBondingMonotone) {
  // The step controller's rejections restore the bonding field with the rest of the state: α never grows.
  // (The bonding's lag error at the front, where α falls from 1 to 0 in about 0.05, asks for steps of
  // 2e-4 at tolerance 1e-2 and 2e-5 at 1e-3: 0.1 keeps the test short, 216 steps.)
  const Case c = case_of("peel-2d", shipped_text("peel-2d"), {"time.T=0.4", "time.tolerance=0.1"});
  ASSERT_TRUE(c.problem->step_control.has_value());
  Vector before;
  int rejected = 0;
  run_to_end(c, [&](const TimeStepper& s, const StepReport& r) {
    const Vector& alpha = s.state().surface_field("bonding")->values;
    if (before.size()) {
      EXPECT_LE((alpha - before).maxCoeff(), 0.0) << "step " << r.n;
    }
    before = alpha;
    rejected += r.rejected;
  });
  std::printf("  peel-2d under error control: %d rejected steps\n", rejected);
  EXPECT_GT(rejected, 0);  // (so that a restore happened)
}

// The automatic choice counts a bonded node's pull as a dual unknown besides its force (the dual's box QP
// splits each bonded row): 1200 nodes are 2400 unknowns, past the dual's bound; with friction the dual
// keeps its m × d (the pull is in λ_ν's own projection there).
TEST(AdhesionKeys, AutomaticChoiceCountsTheBondedPulls) {
  ContactNeeds bonded;
  bonded.adhesion = true;
  EXPECT_EQ(pick_contact_solver("auto", 900, "cholmod", bonded, 1).name, "active-set");
  const ContactSolverPick p = pick_contact_solver("auto", 1200, "cholmod", bonded, 1);
  EXPECT_EQ(p.name, "primal-active-set");
  EXPECT_NE(p.why.find("2400 contact unknowns (1200 nodes, a bonded node's pull besides its force)"), std::string::npos)
      << p.why;
  EXPECT_EQ(pick_contact_solver("auto", 600, "cholmod", bonded, 3).name, "active-set");
}

TEST(AdhesionKeys, BadAdhesionInputsAreLocatedErrors) {
  const std::string text = shipped_text("peel-2d");
  const auto error_of = [&](const std::string& from, const std::string& to, const std::string& solver = "auto") -> std::string {
    try {
      Case c = case_of("peel-2d", replaced(text, from, to));
      c.solvers.contact = solver;
      TimeStepper s(c.problem, c.solvers);
    } catch (const Error& e) {
      return e.what();
    }
    return "(accepted)";
  };
  const std::string law = "adhesion = \"fremond\"\n";
  struct Bad {
    std::string from, to, expected, solver = "auto";
  } table[] = {
      {law, "", "contact.bond_stiffness: bond_stiffness needs adhesion = \"fremond\" in the same table"},
      {"bond_stiffness = 100.0", "bond_stiffness = -1.0", "contact.bond_stiffness: expected a bond stiffness gamma_nu"},
      {"bond_length = 0.02", "bond_length = 0.0", "contact.bond_length: expected a bond length L"},
      {"bond_viscosity = 0.0005", "", "peel-2d.toml:44:1: missing key bond_viscosity (a bond viscosity b"},
      {"adhesion_energy = 0.0", "adhesion_energy = -1.0", "contact.adhesion_energy: expected an adhesion energy"},
      {"adhesion_energy = 0.0", "adhesion_energy = 0.0\nbonding = 1.5", "contact.bonding: expected an initial bonding alpha_0 in [0, 1]"},
      {"adhesion_energy = 0.0", "adhesion_energy = 0.0\nbonding = \"x - 1\"",
       "contact.bonding: the initial bonding alpha_0 is -0.95 at contact node (0.05, 0, 0)"},
      {"gap = 0.0", "gap = \"0.001*x\"",
       "[contact]: the initial bonding alpha_0 is 1 at contact node (0.05, 0, 0), where the initial gap is 5e-05"},
      {law, "adhesion = \"none\"\n", "contact.bond_stiffness: bond_stiffness does not belong to adhesion = \"none\""},
      {law, law, "contact solver 'penalty-duality' solves the Signorini conditions only (a force >= 0); adhesion",
       "penalty-duality"},
      {law, law + "friction = \"coulomb\"\nmu = 0.3\nlaw = \"normal-compliance\"\nstiffness = 1e4\n",
       "adhesion together with friction is solved with Signorini's normal law"},
  };
  for (const Bad& b : table) {
    const std::string msg = error_of(b.from, b.to, b.solver);
    EXPECT_NE(msg.find(b.expected), std::string::npos) << b.to << "\n" << msg;
  }
  // A body that only the bond would hold (the strip's end on a roller: nothing else stops it moving up) is refused.
  EXPECT_NE(error_of("uy = \"0.2*t\"\n", "").find("adhesion holds it only where the case says so"), std::string::npos)
      << error_of("uy = \"0.2*t\"\n", "");
  // With α_0 = 0 where the gap opens, the case runs (bonding only where the surfaces touch).
  EXPECT_EQ(error_of("gap = 0.0", "gap = \"0.001*max(x - 2, 0)\"\nbonding = \"x <= 2 ? 1 : 0\""), "(accepted)");
}

}  // namespace
}  // namespace vpc
