// Issue 28: the shipped shear-2d and shear-3d cases (docs/verification.md "Shear of a block on a
// rigid plane"): an elastic block clamped on top, pressed by a rigid plane that then slides.
//   (a) once the whole face slides, Σ|λ_τ,i| = μ Σ λ_ν,i to the solver's tolerance, and the
//       top's reaction has |R_τ| = μ |R_ν| (in 3D once the forces have turned parallel);
//   (b) with μ large the face sticks and the solution is the bonded one (the face's tangential
//       displacement prescribed equal to the plane's) to round-off;
//   (c) a Tresca run whose bound is μ times the Coulomb run's nodal pressure is the Coulomb run.
#include "friction_runs.hpp"

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
const std::string kCoulomb = "friction = \"coulomb\"\nmu = 0.3";
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
/// frictionless run with the face's u_τ prescribed to the plane's motion.
void sticks_as_bonded(const ShearCase& sc) {
  const std::string slow_x = "0.002*max(t - 1, 0)", slow_y = "0.001*max(t - 1, 0)";
  const std::string point = sc.dim == 2 ? "point = [\"" + slow_x + "\", \"0.005*min(t, 1)\"]"
                                        : "point = [\"" + slow_x + "\", \"" + slow_y + "\", \"0.004*min(t, 1)\"]";
  const std::string text = replaced(shipped_text(sc.name), sc.point, point);
  const Case sticking = case_of(sc.name, replaced(text, kCoulomb, "friction = \"coulomb\"\nmu = 10.0"));
  std::string bonded_text = replaced(text, kCoulomb, "friction = \"none\"");
  bonded_text += "\n[[boundary.displacement]]\nparts = [\"bottom\"]\nux = \"" + slow_x + "\"\n";
  if (sc.dim == 3) bonded_text += "uy = \"" + slow_y + "\"\n";
  const Case bonded = case_of(sc.name, bonded_text);
  std::vector<Vector> u, lambda_nu;
  run_to_end(bonded, [&](const TimeStepper& s, const StepReport&) {
    u.push_back(s.state().u);
    Vector l(s.part().contact.size());
    for (std::size_t i = 0; i < s.part().contact.size(); ++i) l[i] = s.state().lambda[s.part().contact[i].row];
    EXPECT_GT(l.minCoeff(), 0) << "the bonded face must stay pressed everywhere";
    lambda_nu.push_back(l);
  });
  std::size_t n = 0;
  double du = 0, dl = 0;
  run_to_end(sticking, [&](const TimeStepper& s, const StepReport& r) {
    EXPECT_EQ(r.contact.n_slip, 0) << "step " << r.n;
    ASSERT_LT(n, u.size());
    Vector l(s.part().contact.size());
    const auto forces = node_forces(s);
    for (std::size_t i = 0; i < forces.size(); ++i) l[i] = forces[i].normal;
    du = std::max(du, relative_difference(s.state().u, u[n]));
    dl = std::max(dl, relative_difference(l, lambda_nu[n]));
    ++n;
  });
  std::printf("  %s, mu = 10: sticks; against the bonded run, max |u - u_bonded| / max |u_bonded| = %.3g, normal forces %.3g\n",
              sc.name.c_str(), du, dl);
  EXPECT_EQ(n, u.size());
  EXPECT_LE(du, 1e-10);
  EXPECT_LE(dl, 1e-9);
}

TEST(FrictionShear, LargeMuSticksAsTheBondedSolution2d) { sticks_as_bonded(kShear2d); }
TEST(FrictionShear, LargeMuSticksAsTheBondedSolution3d) { sticks_as_bonded(kShear3d); }

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
      case_of(sc.name, replaced(shipped_text(sc.name), kCoulomb, "friction = \"tresca\"\nfriction_bound = \"" + g.str() + "\""), sets);
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
