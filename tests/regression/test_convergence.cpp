// Small convergence studies (Theorem 3.5) that run in CI: observed rates of the
// scheme against manufactured solutions and against a finer reference, checked
// against what the theory predicts; deliberately broken schemes must fail the same
// checks; and the two solvers must agree while the active-set method's iteration
// count stays flat under refinement. docs/verification.md has the full studies.
//
// Tolerance: an observed rate must lie within 0.15 of the predicted one (0.2 in 3D,
// where the levels CI can afford are less asymptotic). On the levels used here the
// correct scheme is within 0.09 of the prediction in 1D and 2D and within 0.11 in 3D
// (the rates are printed to the log). A scheme with an O(1) inconsistency gives rates
// near or below 0; one with an O(k) inconsistency at fixed k gives an error floor and
// rates of 0.75 or less on the finest level; both are far outside the band
// (docs/verification.md §7).
#include "cases/builtin_cases.hpp"
#include "verification/convergence.hpp"
#include "verification/manufactured.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>
#include <optional>
#include <tuple>

namespace vpc {
namespace {

using Norm = double ErrorNorms::*;
struct Expected {
  Norm norm;
  const char* name;
  double rate;
};

/// Rates the theory predicts for P1/P0/P1 with the spatial error alone (h sequence,
/// or hk with the O(k) part made exact): 1 in the energy norm, L2(σ) and L2(0,T;H1)
/// of β; 2 in L2 for u and β.
const std::vector<Expected> kSpatialRates = {{&ErrorNorms::u_energy, "|u|_E", 1},
                                             {&ErrorNorms::u_l2, "|u|_L2", 2},
                                             {&ErrorNorms::sigma_l2, "|sigma|_L2", 1},
                                             {&ErrorNorms::beta_l2, "|beta|_L2", 2},
                                             {&ErrorNorms::beta_grad, "grad beta", 1}};
/// Every norm first order (O(h + k) with h and k halved together, or O(k)).
const std::vector<Expected> kFirstOrder = {{&ErrorNorms::u_energy, "|u|_E", 1},
                                           {&ErrorNorms::u_l2, "|u|_L2", 1},
                                           {&ErrorNorms::sigma_l2, "|sigma|_L2", 1},
                                           {&ErrorNorms::beta_l2, "|beta|_L2", 1},
                                           {&ErrorNorms::beta_grad, "grad beta", 1}};

/// The observed rate of the last level (of the differences of consecutive levels
/// when `differences`, whose last entry is level levels − 2).
double last_rate(const ConvergenceResult& r, Norm norm, bool differences) {
  const int l = static_cast<int>(r.levels.size()) - (differences && r.exact ? 2 : 1);
  return r.rate(l, [&](const LevelResult& x) { return (differences ? x.difference : x.error).*norm; });
}

/// Whether every expected rate is met within `tol`; a message lists the rates seen.
bool rates_ok(const ConvergenceResult& r, const std::vector<Expected>& expected, double tol, bool differences,
              std::string* report = nullptr) {
  bool ok = true;
  std::string s;
  for (const auto& e : expected) {
    const double p = last_rate(r, e.norm, differences);
    const bool good = std::isfinite(p) && std::abs(p - e.rate) <= tol;
    ok = ok && good;
    s += fmt::format("{} {:.3f} (expected {} +- {}){}; ", e.name, p, e.rate, tol, good ? "" : " FAIL");
  }
  if (report) *report = s;
  std::cout << "  rates: " << s << "\n";  // in the CI log, to see the margin
  return ok;
}

/// A law wrapper that breaks the scheme in a chosen way (the stepper itself is
/// untouched: the law is where G enters step 3, z_n = z_{n−1} + k G_{n−1}).
class BrokenLaw final : public ViscoplasticLaw {
 public:
  enum class Kind {
    DropK,            // z_n = z_{n−1} + G_{n−1}: the factor k forgotten
    LagAtNewTime,     // G's explicit time dependence taken at t_n instead of t_{n−1}
    NotAccumulated,   // z_n = k G_{n−1}: the history not carried over
  };
  BrokenLaw(std::shared_ptr<const ViscoplasticLaw> base, Kind kind, double k, Elasticity el)
      : base_(std::move(base)), kind_(kind), k_(k), el_(el) {}
  SymTensor rate(const PointState& s) const override {
    switch (kind_) {
      case Kind::DropK: return (1.0 / k_) * base_->rate(s);
      case Kind::LagAtNewTime: {
        PointState later = s;
        later.t += k_;
        return base_->rate(later);
      }
      default: {
        // z_{n−1} = σ_{n−1} − ℰε(u_{n−1}); returning G − z_{n−1}/k gives z_n = k G.
        const SymTensor z = s.sigma - el_.apply(s.eps);
        return base_->rate(s) - (1.0 / k_) * z;
      }
    }
  }
  std::string describe() const override { return "broken"; }
  Lipschitz lipschitz(double beta) const override { return base_->lipschitz(beta); }

 private:
  std::shared_ptr<const ViscoplasticLaw> base_;
  Kind kind_;
  double k_;
  Elasticity el_;
};

/// The damage source with the factor k of r = Mβ_{n−1} + k F_φ forgotten (3.8).
class SourceWithoutK final : public DamageSource {
 public:
  SourceWithoutK(std::shared_ptr<const DamageSource> base, double k) : base_(std::move(base)), k_(k) {}
  double rate(const PointState& s) const override { return base_->rate(s) / k_; }
  std::string describe() const override { return "broken"; }

 private:
  std::shared_ptr<const DamageSource> base_;
  double k_;
};

struct MmsStudy {
  ManufacturedOptions options;
  RefinementSequence sequence = RefinementSequence::HK;
  int levels = 4;
  std::optional<BrokenLaw::Kind> broken;
  bool source_without_k = false;
};

ConvergenceResult run_mms(const MmsStudy& s) {
  const ManufacturedOptions o = s.options;
  const auto broken = s.broken;
  const bool source_without_k = s.source_without_k;
  ProblemFactory factory = [o, broken, source_without_k](const Mesh& mesh, int n_steps) {
    ManufacturedCase mc = make_manufactured_case(o, mesh, n_steps);
    if (broken) mc.problem->law = std::make_shared<BrokenLaw>(mc.problem->law, *broken, mc.problem->step(),
                                                              mc.problem->elasticity);
    if (source_without_k) mc.problem->source = std::make_shared<SourceWithoutK>(mc.problem->source, mc.problem->step());
    return std::shared_ptr<const Problem>(mc.problem);
  };
  ConvergenceOptions co;
  co.sequence = s.sequence;
  co.levels = s.levels;
  co.base_steps = o.n_steps;
  const Mesh base = manufactured_base_mesh(o);
  return run_convergence("mms", base, factory, make_manufactured_case(o, base, o.n_steps).exact, co);
}

ManufacturedOptions mms(int dim, const std::string& law, ManufacturedForcing forcing, int cells, int steps) {
  ManufacturedOptions o;
  o.dim = dim;
  o.law = law;
  o.forcing = forcing;
  o.cells = cells;
  o.n_steps = steps;
  return o;
}

constexpr double kTol = 0.15;

// Issue 11 item 5: in plane strain the scheme carries σ33 and z33 (the laws' 33 rate
// is nonzero here), and keeps the spatial rates; dropping z33 would leave an O(1)
// error in L2(σ).
TEST(ConvergenceMms, PlaneStrainKeepsItsRates) {
  for (const char* law : {"perzyna-von-mises", "maxwell-damage"}) {
    ManufacturedOptions o = mms(2, law, ManufacturedForcing::Discrete, 2, 4);
    o.plane_strain = true;
    const auto r = run_mms({o, RefinementSequence::HK, 4, {}});
    std::string report;
    EXPECT_TRUE(rates_ok(r, kSpatialRates, kTol, false, &report)) << law << ": " << report;
  }
}

TEST(ConvergenceMms, SpatialRatesIn1D2D3D) {
  // Discrete forcing: the exact solution solves the time-discrete scheme, so the
  // fully discrete error is spatial: O(h) energy/L2(σ)/H1(β), O(h²) L2(u)/L2(β).
  struct Study {
    int dim, cells, levels;
    double tol;
  };
  for (const Study& c : {Study{1, 2, 5, kTol}, Study{2, 2, 4, kTol}}) {
    const auto r = run_mms({mms(c.dim, "maxwell-damage", ManufacturedForcing::Discrete, c.cells, 4),
                            RefinementSequence::HK, c.levels, {}});
    std::string report;
    EXPECT_TRUE(rates_ok(r, kSpatialRates, c.tol, false, &report)) << "d = " << c.dim << ": " << report;
  }
  // 3D: the levels CI can afford (48 to 3072 tetrahedra) are asymptotic for the
  // first-order norms but not yet for the second-order ones, which rise towards 2
  // (1.6 and 1.7 here; 1.9 and 2.0 two levels further, docs/verification.md).
  const auto r = run_mms({mms(3, "maxwell-damage", ManufacturedForcing::Discrete, 2, 4), RefinementSequence::HK, 3, {}});
  std::string report;
  EXPECT_TRUE(rates_ok(r, {kSpatialRates[0], kSpatialRates[2], kSpatialRates[4]}, 0.2, false, &report))
      << "d = 3: " << report;
  for (Norm n : {&ErrorNorms::u_l2, &ErrorNorms::beta_l2}) {
    EXPECT_GE(last_rate(r, n, false), 1.5) << "d = 3";
    EXPECT_GT(last_rate(r, n, false), r.rate(1, [&](const LevelResult& x) { return x.error.*n; })) << "d = 3";
  }
}

TEST(ConvergenceMms, ElasticAndPerzynaSpatialRates) {
  for (const char* law : {"elastic", "perzyna"}) {
    const auto r = run_mms({mms(2, law, ManufacturedForcing::Discrete, 2, 4), RefinementSequence::H, 4, {}});
    std::string report;
    EXPECT_TRUE(rates_ok(r, kSpatialRates, kTol, false, &report)) << law << ": " << report;
  }
}

TEST(ConvergenceMms, FirstOrderInTimeAndInHPlusK) {
  // Continuous forcing: O(h + k). h and k halved together: first order in the energy
  // norm and L2(σ) (the L2 norms of u and β are on their way from 2 down to 1).
  const auto hk = run_mms({mms(2, "maxwell-damage", ManufacturedForcing::Continuous, 2, 4), RefinementSequence::HK, 4, {}});
  std::string report;
  EXPECT_TRUE(rates_ok(hk, {kFirstOrder[0], kFirstOrder[2], kFirstOrder[4]}, kTol, false, &report)) << report;
  for (Norm n : {&ErrorNorms::u_l2, &ErrorNorms::beta_l2}) EXPECT_GE(last_rate(hk, n, false), 1 - kTol);
  // k alone on a fixed mesh: the differences of consecutive levels remove the fixed
  // spatial error and show backward Euler's (and the lagged sources') O(k).
  ManufacturedOptions o = mms(2, "maxwell-damage", ManufacturedForcing::Continuous, 4, 4);
  const auto k = run_mms({o, RefinementSequence::K, 5, {}});
  EXPECT_TRUE(rates_ok(k, kFirstOrder, kTol, true, &report)) << report;
}

TEST(ConvergenceMms, BrokenSchemesFailTheRateCheck) {
  // The k factor of z_n = z_{n−1} + k G_{n−1} dropped, or the history not carried
  // over: O(1) inconsistencies, caught by the h-and-k study.
  for (auto kind : {BrokenLaw::Kind::DropK, BrokenLaw::Kind::NotAccumulated}) {
    const auto r = run_mms(
        {mms(2, "maxwell-damage", ManufacturedForcing::Continuous, 2, 4), RefinementSequence::HK, 4, kind});
    std::string report;
    EXPECT_FALSE(rates_ok(r, {kFirstOrder[0], kFirstOrder[2]}, kTol, false, &report))
        << "broken scheme " << static_cast<int>(kind) << " passed: " << report;
  }
  // The k of the damage source forgotten: β's norms lose their rate.
  {
    MmsStudy st{mms(2, "maxwell-damage", ManufacturedForcing::Continuous, 2, 4), RefinementSequence::HK, 4, {}};
    st.source_without_k = true;
    const auto r = run_mms(st);
    std::string report;
    EXPECT_FALSE(rates_ok(r, {kFirstOrder[3], kFirstOrder[4]}, kTol, false, &report))
        << "damage source without k passed: " << report;
  }
  // G lagged at t_n instead of t_{n−1}: still O(k) consistent, so O(h + k) alone
  // cannot see it; the discrete forcing assumes the paper's lagging exactly, so an
  // h study at fixed k shows an error floor.
  const auto r = run_mms({mms(2, "maxwell-damage", ManufacturedForcing::Discrete, 2, 4), RefinementSequence::H, 4,
                          BrokenLaw::Kind::LagAtNewTime});
  std::string report;
  EXPECT_FALSE(rates_ok(r, kSpatialRates, kTol, false, &report)) << "lag at t_n passed: " << report;
}

Case small_case(const std::string& name, int n, int steps) { return load_case(name, {.steps = steps}, {.cells = n}); }

ConvergenceResult run_case(const Case& c, RefinementSequence seq, int levels) {
  ConvergenceOptions co;
  co.sequence = seq;
  co.levels = levels;
  co.base_steps = c.problem->n_steps;
  return run_convergence(c.name, c.problem->mesh, same_data_on(c.problem), nullptr, co);
}

TEST(ConvergenceContact, Paper1dIsFirstOrder) {
  // The rod: contact starts at t ≈ 0.5 and the damage source is smooth; the rates
  // of the differences of consecutive levels are those of O(h + k).
  const auto r = run_case(small_case("paper-1d", 10, 10), RefinementSequence::HK, 4);
  std::string report;
  EXPECT_TRUE(rates_ok(r, {kFirstOrder[0], kFirstOrder[2], kFirstOrder[3], kFirstOrder[4]}, kTol, true, &report))
      << report;
  EXPECT_GE(r.levels.back().max_active_contact, 1);  // the constraint is active in this study
}

TEST(ConvergenceContact, NonUniformStepsAreFirstOrder) {
  // Issue 15: a grid of 0.1 to t = 0.5 and 0.025 after it, each step split in two per
  // level (k = max k_n halves): the differences of consecutive levels are O(k).
  const Case c = load_case("paper-1d", {.sets = {"time.breakpoints=[0.5]", "time.dt=[0.1, 0.025]"}}, {.cells = 40});
  ASSERT_EQ(c.problem->n_steps, 25);
  const auto r = run_case(c, RefinementSequence::K, 4);
  EXPECT_EQ(r.levels[0].k, 0.1);
  EXPECT_EQ(r.levels.back().n_steps, 200);
  std::string report;
  EXPECT_TRUE(rates_ok(r, {kFirstOrder[0], kFirstOrder[3], kFirstOrder[4]}, kTol, true, &report)) << report;
}

TEST(ConvergenceContact, ErrorControlledStepsFollowTheirTolerance) {
  // Issue 15: the rod loaded in 0.1 s and held, its damage reaching β = 0 from t ≈ 0.86 on.
  // The error-controlled levels (tolerance halved per level) are compared with the uniform
  // ones at the base grid's times: β's error falls with the tolerance, and the level whose
  // β error is at most the finest uniform level's takes less than half its steps.
  const Case c = load_case("paper-1d", {.sets = {"loads.f0=[\"min(10*t, 1)\"]", "damage.c=4"}, .steps = 10});
  ConvergenceOptions co;
  co.sequence = RefinementSequence::K;
  co.levels = 5;
  co.reference_offset = 5;
  co.base_steps = 10;
  co.step_control = StepControl{};
  co.step_control->tolerance = 0.16;
  const auto r = run_convergence(c.name, c.problem->mesh, same_data_on(c.problem), nullptr, co);
  ASSERT_EQ(r.adaptive.size(), 5u);
  EXPECT_TRUE(r.at_base_times);
  for (std::size_t l = 1; l < r.adaptive.size(); ++l) {
    EXPECT_LT(r.adaptive[l].error.beta_l2, 0.85 * r.adaptive[l - 1].error.beta_l2) << "level " << l;
    EXPECT_GT(r.adaptive[l].n_steps, r.adaptive[l - 1].n_steps) << "level " << l;
  }
  // The steps the error control needs for the uniform N = 160's β error: interpolated
  // (log-log) between the two error-controlled levels around it.
  const LevelResult& finest = r.levels.back();
  const double target = finest.error.beta_l2;
  double needed = NAN;
  for (std::size_t l = 1; l < r.adaptive.size(); ++l) {
    const LevelResult &a = r.adaptive[l - 1], &b = r.adaptive[l];
    if (a.error.beta_l2 >= target && b.error.beta_l2 <= target)
      needed = std::exp(std::log(a.n_steps) + (std::log(target) - std::log(a.error.beta_l2)) *
                                                  (std::log(b.n_steps) - std::log(a.n_steps)) /
                                                  (std::log(b.error.beta_l2) - std::log(a.error.beta_l2)));
  }
  ASSERT_TRUE(std::isfinite(needed)) << "the error-controlled levels do not bracket the uniform N = 160's error";
  EXPECT_LE(2 * needed, finest.n_steps);
  std::cout << "  error-controlled steps for beta's error " << target << " of N = " << finest.n_steps << ": " << needed
            << "\n";
}

TEST(ConvergenceContact, Paper2dEnergyRateIsLimitedByTheContactEdgeSingularity) {
  // The flat contact zone of the paper's block ends abruptly: the contact pressure
  // behaves like r^{-1/2} there (a flat punch), u is only in H^{3/2−ε}, and the
  // energy norm and L2(σ) converge like h^{1/2}; L2 of u and β stay first order.
  const auto r = run_case(small_case("paper-2d", 5, 5), RefinementSequence::HK, 3);
  const double pu = last_rate(r, &ErrorNorms::u_energy, true), ps = last_rate(r, &ErrorNorms::sigma_l2, true);
  EXPECT_NEAR(pu, 0.5, 0.1);
  EXPECT_NEAR(ps, 0.5, 0.1);
  EXPECT_GE(last_rate(r, &ErrorNorms::u_l2, true), 0.85);
  EXPECT_GE(last_rate(r, &ErrorNorms::beta_l2, true), 0.85);
}

TEST(SolverAgreement, ActiveSetAndPenaltyDualityGiveTheSameSolution) {
  for (const auto& [name, n, levels] : {std::tuple{"paper-1d", 10, 3}, std::tuple{"paper-2d", 5, 3}}) {
    const Case c = small_case(name, n, 20);
    const auto s = compare_solvers(c.problem->mesh, same_data_on(c.problem), levels, 20, c.solvers);
    for (const auto& l : s) {
      EXPECT_LT(l.diff_u, 1e-8) << name << " level " << l.level;
      EXPECT_LT(l.diff_beta, 1e-8) << name << " level " << l.level;
      EXPECT_LT(l.diff_lambda, 1e-8) << name << " level " << l.level;
      EXPECT_EQ(l.failed_as + l.failed_pd, 0) << name << " level " << l.level;
      // Warm-started active-set iterations stay flat under refinement.
      EXPECT_LE(l.contact_as.max, s.front().contact_as.max + 1) << name << " level " << l.level;
      EXPECT_LE(l.damage_as.max, s.front().damage_as.max + 1) << name << " level " << l.level;
    }
  }
}

}  // namespace
}  // namespace vpc
