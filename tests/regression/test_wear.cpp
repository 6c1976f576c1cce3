// Issue 50 (SPEC §9): Archard's wear, against exact solutions. cases/wear-2d.toml: an elastic block in
// uniaxial strain (rollers at its sides) pushed down by δ onto a rigid plane sliding along x at speed 1,
// so that every node slides by ds = dt a step under the same pressure p_n = E'(δ − ω_{n−1})/H: the
// lagged wear is then exactly the recursion ω_n = δ(1 − (1 − a)^n), a = k_w E' ds / H, whose limit is
// the ODE's δ(1 − e^{−k_w E' s / H}). With Coulomb friction and the complementary shear on the sides
// (a uniform state) the wear is Archard's k_w p s whatever μ.
#include "friction_runs.hpp"
#include "io/checkpoint.hpp"

#include <fmt/format.h>

#include <filesystem>

namespace vpc {
namespace {

namespace fs = std::filesystem;
using namespace friction_test;

constexpr double kDelta = 0.01, kH = 1.0, kE = 1000.0, kNu = 0.3, kWear = 5e-4;

/// The constrained (P-wave) modulus λ + 2μ of plane strain: σ_yy / ε_yy in uniaxial strain.
double constrained_modulus() {
  const double lambda = kE * kNu / ((1 + kNu) * (1 - 2 * kNu)), mu = kE / (2 * (1 + kNu));
  return lambda + 2 * mu;
}

Case wear_case(const std::vector<std::string>& sets = {}, const std::string& solver = "active-set") {
  Case c = case_of("wear-2d", shipped_text("wear-2d"), sets);
  c.solvers.contact = solver;
  return c;
}

const Vector& wear_of(const State& s) {
  const SurfaceField* f = s.surface_field("wear");
  if (!f) throw std::runtime_error("no surface field wear");
  return f->values;
}

/// Runs `c` and returns the largest |ω_i − δ(1 − (1 − a)^n)| / δ over every node and step (ds: the slide
/// of a step), with the other exact relations of the block checked on the way: every bottom node sits
/// at u_y = −ω_{n−1} (the worn gap it was solved with) and worn_volume = Σ ω_i |Γ3|_i = ω (width 1).
double recursion_error(const Case& c, double ds, int* steps = nullptr) {
  const double a = kWear * constrained_modulus() * ds / kH;
  double off = 0, off_u = 0, off_volume = 0;
  Vector before;
  int n_steps = 0;
  run_to_end(c, [&](const TimeStepper& s, const StepReport& r) {
    const State& st = s.state();
    const Vector& w = wear_of(st);
    if (before.size() == 0) before = Vector::Zero(w.size());
    const double exact = kDelta * (1 - std::pow(1 - a, r.n));
    off = std::max(off, (w.array() - exact).abs().maxCoeff() / kDelta);
    for (const PartContactNode& node : s.contact().nodes)
      off_u = std::max(off_u, std::abs(st.u[node.local_node * 2 + 1] + before[node.row]) / kDelta);
    ASSERT_EQ(r.surface_integral.size(), 1u);
    off_volume = std::max(off_volume, std::abs(r.surface_integral[0] - exact) / kDelta);
    EXPECT_LE(r.surface.step_share, 1.0);
    before = w;
    n_steps = r.n;
  });
  std::printf("  %d steps of ds = %.4g (a = %.4g): wear against the recursion %.3g, u_y against -w_(n-1) %.3g, "
              "worn_volume %.3g (of delta)\n",
              n_steps, ds, a, off, off_u, off_volume);
  // The primal's frictional iteration (the slip's zero bounds) stops at its slip-force tolerance, a tenth of
  // the step's residual tolerance: 4e-10 of δ here; the dual meets an active row to round-off.
  const double tol = c.solvers.contact == "primal-active-set" ? 1e-9 : 1e-11;
  EXPECT_LE(off_u, tol);
  EXPECT_LE(off_volume, tol);
  if (steps) *steps = n_steps;
  return off;
}

TEST(WearExact, TheLaggedWearIsTheClosedFormRecursionToRoundOff) {
  for (const std::string solver : {"active-set", "primal-active-set"}) {
    SCOPED_TRACE(solver);
    int steps = 0;
    EXPECT_LE(recursion_error(wear_case({}, solver), 0.05, &steps), solver == "active-set" ? 1e-12 : 1e-10);
    EXPECT_EQ(steps, 20);
  }
}

TEST(WearExact, ItConvergesToTheArchardOdeAtFirstOrderInTheSlide) {
  // ω(s) = δ(1 − e^{−k_w E' s/H}) at s = T = 1, against the lagged scheme at ds = 1/20, 1/40, 1/80.
  const double exact = kDelta * (1 - std::exp(-kWear * constrained_modulus() * 1.0 / kH));
  std::vector<double> errors;
  for (int steps : {20, 40, 80}) {
    const Case c = wear_case({fmt::format("time.steps={}", steps), fmt::format("boundary.displacement[0].uy=-0.01*min(t*{}, 1)", steps)});
    TimeStepper s(c.problem, c.solvers);
    while (!s.done()) ASSERT_TRUE(s.step().ok);
    errors.push_back(std::abs(wear_of(s.state()).maxCoeff() - exact) / kDelta);
  }
  const double rate1 = std::log2(errors[0] / errors[1]), rate2 = std::log2(errors[1] / errors[2]);
  std::printf("  wear at s = 1 against the ODE: %.4g, %.4g, %.4g (of delta) at 20, 40, 80 steps: rates %.3f, %.3f\n",
              errors[0], errors[1], errors[2], rate1, rate2);
  EXPECT_NEAR(rate1, 1.0, 0.05);
  EXPECT_NEAR(rate2, 1.0, 0.03);
}

TEST(WearExact, AStepAboveTheCapIsRejectedAndHalvingRedoesItExactly) {
  // k_w 16 times larger: a = 0.54 a step of 0.05, above wear_cap = 0.5 of the nodes' elastic approach; the
  // approach δ full from t = 0.05/8 on, so that halved steps have it too.
  const std::vector<std::string> big = {"contact.wear_coefficient=8e-3", "boundary.displacement[0].uy=-0.01*min(t/0.00625, 1)"};
  {
    const Case c = wear_case(big);
    TimeStepper s(c.problem, c.solvers);
    const StepReport r = s.step();
    EXPECT_FALSE(r.ok);
    EXPECT_GT(r.surface.step_share, 1.0);
    std::printf("  the first step: %s\n", r.surface.step_text.c_str());
    EXPECT_NE(r.surface.step_text.find("wear_cap = 0.5"), std::string::npos) << r.surface.step_text;
    EXPECT_NE(r.surface.step_text.find("wear-2d.toml:45:1: [contact]: at contact node 0 (0, 0, 0)"), std::string::npos)
        << r.surface.step_text;
  }
  Case c = wear_case(big);
  c.solvers.max_halvings = 6;
  TimeStepper s(c.problem, c.solvers);
  const StepReport r = s.step();
  ASSERT_TRUE(r.ok);
  ASSERT_GT(r.substeps, 1);
  // After the first step the worn depth is the recursion's after `substeps` steps of ds = 0.05 / substeps.
  const double a = 8e-3 * constrained_modulus() * 0.05 / r.substeps / kH;
  const double exact = kDelta * (1 - std::pow(1 - a, r.substeps));
  const double off = (wear_of(s.state()).array() - exact).abs().maxCoeff() / kDelta;
  std::printf("  with --retry-halvings: %d substeps (a = %.3g each), wear against their recursion %.3g\n", r.substeps,
              a, off);
  EXPECT_LE(off, 1e-12);
}

TEST(WearExact, ErrorControlledStepsFollowTheCapWithoutRejections) {
  // An elastic block has no error of its own to control: the steps grow until the wear cap holds them
  // (its share grows with the slip of a step). The controller proposes each step within the cap, so the
  // steps are not attempted above it and rejected one after the other (121 rejections in 131 steps
  // before it did).
  const Case c = wear_case({"contact.wear_coefficient=8e-3", "time.tolerance=0.01"});
  ASSERT_TRUE(c.problem->step_control.has_value());
  int steps = 0, rejected = 0;
  double largest_share = 0;
  run_to_end(c, [&](const TimeStepper&, const StepReport& r) {
    ++steps;
    rejected += r.rejected;
    largest_share = std::max(largest_share, r.surface.step_share);
  });
  std::printf("  error-controlled steps under the wear cap: %d steps, %d rejected, largest share of the cap %.3f\n",
              steps, rejected, largest_share);
  EXPECT_LE(largest_share, 1.0);
  EXPECT_LE(rejected, 2);
  EXPECT_GT(largest_share, 0.5);  // the cap, not the controller's growth limit, sets the steps
}

TEST(WearExact, WithCoulombFrictionTheWearIsArchardsWhateverMu) {
  // The pressure held constant: the top is moved down with the lagged worn depth, u_y = −pH/E −
  // k_w p (t − k)₊ (k = 0.05), so that the compression is pH/E at every step; the sides carry the
  // complementary shear ±τ, τ = −μ p (the friction on the body drags it along the plane's motion), and
  // the top's u_x is simple shear's γH, γ = τ/G. With ν = 0 the face does not widen under p (ε_xx = 0): every
  // node of the face slides by exactly the plane's ds = 0.05 a step, from the first on. Then the state
  // is uniform and ω_n = k_w p s_n exactly.
  for (const double mu : {0.3, 0.6}) {
    const double p = 10.0, G = kE / 2;
    const double eps_yy = -p / kE, gamma = -mu * p / G;
    std::string text = shipped_text("wear-2d");
    text = replaced(text, "symmetry = [\"left\", \"right\"]  # rollers: u_x = 0\n", "");
    text = replaced(text, "nu = 0.3", "nu = 0.0");
    text = replaced(text, "uy = \"-0.01*min(t/0.05, 1)\"",
                    fmt::format("ux = \"{:.17g}\"\nuy = \"{:.17g} - {:.17g}*max(t - 0.05, 0)\"", gamma * kH, eps_yy * kH,
                                kWear * p));
    text = replaced(text, "[contact]\n", fmt::format("[contact]\nfriction = \"coulomb\"\nmu = {}\n", mu));
    text = replaced(text, "[elasticity]", fmt::format("[loads]\nf2 = [\"0\", \"{:.17g}*(2*x - 1)\"]\n\n[elasticity]", -mu * p));
    const Case c = case_of("wear-2d", text);
    double off = 0, off_p = 0;
    int slipping = 0;
    run_to_end(c, [&](const TimeStepper& s, const StepReport& r) {
      for (const NodeForces& f : node_forces(s)) {
        off_p = std::max(off_p, std::abs(f.normal / f.measure - p) / p);
        slipping += f.status == 2;
      }
      off = std::max(off, (wear_of(s.state()).array() - kWear * p * r.t).abs().maxCoeff() / (kWear * p));
    });
    std::printf("  Coulomb mu = %.2g: pressure against p %.3g, wear against k_w p s %.3g (of k_w p), %d slipping node-steps\n",
                mu, off_p, off, slipping);
    EXPECT_LE(off_p, 1e-10);
    EXPECT_LE(off, 1e-10);
    EXPECT_EQ(slipping, 5 * 20);  // every node slides at every step
  }
}

// A contact pair (SPEC §8): contact-patch-2d's upper block pressed onto the lower one and dragged along it
// (its left side freed), frictionless, with Archard wear on the pair: the worn depth is the slave side's,
// from the slave's pressure λ_ν/D_jj and its slip relative to the master side's mortar mean (friction's Δ),
// and it opens the pair's gap in the next step: an active slave row sits at N u − g = ω_{n−1}.
TEST(WearPair, TheSlaveWearsByItsPressureAndItsSlipRelativeToTheMaster) {
  const double k_w = 2e-3;
  const std::vector<std::string> sets = {"boundary.symmetry=[\"left\", \"bottom\"]", "boundary.displacement[0].ux=0.05*t",
                                         "contact.pair[0].wear=\"archard\"",
                                         fmt::format("contact.pair[0].wear_coefficient={}", k_w), "time.steps=10"};
  for (const std::string solver : {"active-set", "primal-active-set"}) {
    SCOPED_TRACE(solver);
    Case c = case_of("contact-patch-2d", shipped_text("contact-patch-2d"), sets);
    c.solvers.contact = solver;
    Vector worn;
    double off = 0, off_gap = 0, largest = 0;
    int active = 0;
    run_to_end(c, [&](const TimeStepper& s, const StepReport&) {
      const State& st = s.state();
      if (worn.size() == 0) worn = Vector::Zero(s.part().n_contact);
      const Vector before = worn;
      for (const PartContactNode& node : s.contact().nodes) {
        worn[node.row] += k_w * std::max(st.lambda[node.row * 2], 0.0) / node.measure * std::abs(st.slip_step[node.row]);
        if (st.lambda[node.row * 2] > 0) {  // s.gap = g + ω_n − N u: ω_n − ω_{n−1} where the row is closed
          ++active;
          off_gap = std::max(off_gap, std::abs(st.gap[node.row] - (worn[node.row] - before[node.row])));
        }
      }
      largest = worn.maxCoeff();
      off = std::max(off, (wear_of(st) - worn).cwiseAbs().maxCoeff());
    });
    std::printf("  pair wear (%s): worn depth up to %.4g, against k_w sum lambda/D |slip| %.3g, closed rows' gap "
                "against the step's wear %.3g over %d node-steps\n",
                solver.c_str(), largest, off / largest, off_gap / largest, active);
    EXPECT_GT(largest, 1e-5);
    EXPECT_GT(active, 40);
    EXPECT_LE(off / largest, 1e-12);
    EXPECT_LE(off_gap / largest, solver == "active-set" ? 1e-12 : 1e-8);
  }
}

TEST(WearExact, AResumeMidWearIsTheUninterruptedRun) {
  const Case c = wear_case();
  TimeStepper a(c.problem, c.solvers), b(c.problem, c.solvers);
  for (int i = 0; i < 9; ++i) a.step();
  const fs::path dir = fs::temp_directory_path() / "vpc_wear_ckpt";
  fs::remove_all(dir);
  fs::create_directories(dir);
  write_checkpoint(a, dir, "wear-2d", {}, RunTotals{});
  ASSERT_TRUE(resume_from_checkpoint(b, dir).has_value());
  EXPECT_EQ(wear_of(b.state()), wear_of(a.state()));
  while (!a.done()) {
    a.step();
    b.step();
  }
  EXPECT_EQ(wear_of(b.state()), wear_of(a.state()));
  EXPECT_EQ(b.state().u, a.state().u);
  fs::remove_all(dir);
}

TEST(WearKeys, BadWearInputsAreLocatedErrors) {
  const std::string text = shipped_text("wear-2d");
  const auto error_of = [&](const std::string& from, const std::string& to) -> std::string {
    try {
      const Case c = case_of("wear-2d", replaced(text, from, to));
      TimeStepper s(c.problem, c.solvers);  // a formula's values: at the contact nodes, at set-up
    } catch (const Error& e) {
      return e.what();
    }
    return "(accepted)";
  };
  const std::string law = "wear = \"archard\"\n";
  struct Bad {
    std::string from, to, expected;
  } table[] = {
      {law, "", "contact.wear_coefficient: wear_coefficient needs wear = \"archard\" in the same table"},
      {"wear_coefficient = 5e-4", "wear_coefficient = -1", "contact.wear_coefficient: expected a wear coefficient k_w"},
      {"wear_coefficient = 5e-4", "wear_coefficient = 5e-4\nwear_cap = 1.5", "contact.wear_cap: expected a share 0 < wear_cap <= 1"},
      {"wear_coefficient = 5e-4", "wear_coefficient = 5e-4\nwear_warning = 0", "contact.wear_warning: expected a share wear_warning > 0"},
      {law, "wear = \"none\"\n", "contact.wear_coefficient: wear_coefficient does not belong to wear = \"none\""},
      {law, "wear = \"archrd\"\n", "contact.wear"},
      {"wear_coefficient = 5e-4", "wear_coefficient = \"5e-4*(x - 0.5)\"",
       "wear-2d.toml:47:20: contact.wear_coefficient: the wear coefficient k_w is -0.00025 at contact node (0, 0, 0)"},
  };
  for (const Bad& b : table) {
    const std::string msg = error_of(b.from, b.to);
    EXPECT_NE(msg.find(b.expected), std::string::npos) << msg;
  }
  // A 1D bar has no tangential slip to wear with.
  try {
    (void)case_of("paper-1d", replaced(shipped_text("paper-1d"), "[contact]\n", "[contact]\nwear = \"archard\"\nwear_coefficient = 1\n"));
    ADD_FAILURE() << "wear on a 1D bar was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("contact.wear: wear needs a body of dimension 2 or 3"), std::string::npos) << e.what();
  }
  // The bounds themselves are accepted.
  EXPECT_NE(error_of("wear_coefficient = 5e-4", "wear_coefficient = 5e-4\nwear_cap = 1").find("(accepted)"),
            std::string::npos);
}

}  // namespace
}  // namespace vpc
