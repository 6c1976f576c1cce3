// Issue 29: punch-3d, a deformable punch pressed into the paper's damageable viscoplastic block and
// slid along it: two bodies through a contact pair with Coulomb friction (μ = 0.3) and large
// sliding (docs/verification.md §8g). Every step within its residuals; at the end the punch slides
// whole (Σ|λ_τ| = μ Σλ_ν), its top's reaction balances the pair's forces on it (the normal forces
// along the moved configuration's normals, the tangential ones), and the damage lies along the
// track, behind the punch and not ahead of it, in the block alone.
#include "friction_runs.hpp"

#include "io/state_fields.hpp"

#include <cstdio>

namespace vpc {
namespace {

using namespace friction_test;

TEST(Punch3d, PressedAndSlidOnTheDamageableBlock) {
  const Case c = load_case("punch-3d");
  StepReport last;
  double normal = 0, tangential = 0, balance = 0, scale = 0;
  std::vector<double> beta;
  Vector u;
  run_to_end(c, [&](const TimeStepper& s, const StepReport& r) {
    last = r;
    if (!s.done()) return;
    const State& st = s.state();
    for (Eigen::Index i = 0; i < st.lambda.size() / 3; ++i) {
      normal += st.lambda[3 * i];
      tangential += st.lambda.segment(3 * i + 1, 2).norm();
    }
    // The force on the punch: at each slave node −λ_ν ν (contact_force) and −λ_τ·t (tangential_force:
    // both the force on the body that owns the node); its top's reaction holds it.
    const std::vector<double> f = state_field("contact_force").vtu_field({st, s.part(), s.contact().nodes}).values;
    const std::vector<double> t = state_field("tangential_force").vtu_field({st, s.part(), s.contact().nodes}).values;
    double on_punch[3] = {0, 0, 0};
    for (const PartContactNode& node : s.contact().nodes)
      for (int i = 0; i < 3; ++i) on_punch[i] += f[3 * node.local_node + i] + t[3 * node.local_node + i];
    for (int i = 0; i < 3; ++i) {  // reaction: the block's bottom (3), then the punch's top (3)
      balance = std::max(balance, std::abs(on_punch[i] + r.reaction[static_cast<std::size_t>(3 + i)]));
      scale = std::max(scale, std::abs(r.reaction[static_cast<std::size_t>(3 + i)]));
    }
    beta.assign(st.beta.data(), st.beta.data() + st.beta.size());
  });
  std::printf("  punch-3d: P = %.6g, drag %.6g (Σ|λ_τ| / (μ Σλ_ν) − 1 = %.2e), punch balance %.2e of its reaction, "
              "min β %.4f\n", last.pair_force[0], last.pair_tangential_force[0], tangential / (0.3 * normal) - 1,
              balance / scale, last.contact.n_active ? *std::min_element(beta.begin(), beta.end()) : 1.0);
  EXPECT_EQ(last.contact.n_stick, 0);
  EXPECT_NEAR(tangential, 0.3 * normal, 1e-9 * normal);
  EXPECT_GT(last.pair_tangential_force[0], 0.25 * last.pair_force[0]);  // the block dragged along +x
  EXPECT_LT(balance, 1e-8 * scale);
  // β along the track on the block's top (y = 0.5): damaged under the punch's first place and
  // along its path, far less ahead of where it stopped (its centre moved 0.45 → 0.95: beyond
  // x = 1.4 only the drag's stress ahead of it and κ's diffusion reach); the punch, elastic with
  // no source, keeps β = 1.
  const Case probe = load_case("punch-3d");
  const Mesh& m = probe.problem->mesh;
  double behind = 1, ahead = 0, in_punch = 1;
  for (int n = 0; n < m.n_nodes(); ++n) {
    const Point& x = m.node(n);
    const double b = beta[static_cast<std::size_t>(n)];
    if (x[2] > 0.5 + 1e-9) in_punch = std::min(in_punch, b);
    if (std::abs(x[1] - 0.5) > 1e-9 || std::abs(x[2] - 0.5) > 1e-9) continue;
    if (x[0] > 0.4 && x[0] < 0.9) behind = std::min(behind, b);
    if (x[0] > 1.4) ahead = std::max(ahead, 1 - b);
  }
  std::printf("  punch-3d: on the track's line, least β behind the punch's end %.4f, most damage beyond x = 1.4 %.4f\n",
              behind, ahead);
  EXPECT_LT(behind, 0.8);
  EXPECT_LT(ahead, 0.2 * (1 - behind));
  EXPECT_EQ(in_punch, 1.0);
}

}  // namespace
}  // namespace vpc
