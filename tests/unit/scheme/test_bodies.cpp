// Issue 29, first part: several bodies in one case (SPEC §8, `[[body]]`): each its own mesh,
// materials, κ and β0, its parts named "<body>.<part>". Without a contact pair between them
// the bodies are independent problems, and a run of two must give each one's run alone.
#include "io/case_file.hpp"
#include "mesh/generators.hpp"
#include "scheme/time_stepper.hpp"

#include <gtest/gtest.h>

#include <string>

#include "../error_of.hpp"
#include "../run_to_end.hpp"

namespace vpc {
namespace {

TEST(Bodies, AppendKeepsTheMeshesApartAndNamesTheirParts) {
  Mesh a = make_rectangle({0, 0, 0}, {1, 1, 0}, 2, 2);
  a.tag_facets("bottom", [](const Point& x) { return x[1] < 1e-12; });
  Mesh b = make_rectangle({2, 0, 0}, {3, 1, 0}, 1, 3);
  b.tag_facets("bottom", [](const Point& x) { return x[1] < 1e-12; });
  b.tag_cells("core", [](const Point& x) { return x[1] < 0.5; });
  const int na = a.n_nodes(), ca = a.n_cells(), fa = a.n_facets();
  EXPECT_EQ(a.append(b, "punch"), 1);
  EXPECT_EQ(a.n_bodies(), 2);
  EXPECT_EQ(a.n_nodes(), na + b.n_nodes());
  EXPECT_EQ(a.n_cells(), ca + b.n_cells());
  EXPECT_EQ(a.n_facets(), fa + b.n_facets());
  for (int c = 0; c < a.n_cells(); ++c) EXPECT_EQ(a.cell_body(c), c < ca ? 0 : 1);
  EXPECT_EQ(a.part_size("bottom"), 2);
  EXPECT_EQ(a.part_size("punch.bottom"), 1);
  EXPECT_EQ(a.region_size("punch.core"), b.region_size("core"));
  for (int f = fa; f < a.n_facets(); ++f) {  // the appended facets keep their outward normals
    const Point n = a.facet_normal(f), m = b.facet_normal(f - fa);
    for (int j = 0; j < 3; ++j) EXPECT_DOUBLE_EQ(n[j], m[j]);
    EXPECT_GE(a.facet(f)[0], na);  // no node shared with the first body
  }
  EXPECT_NE(error_of([&] { a.append(Mesh(3), "bad"); }).find("dimension 3"), std::string::npos);
}

/// paper-2d's block on [x0, x0 + 2] × [0, 2] (n × n cells, 4 steps), pressed by its weight onto
/// the foundation along [x0 + 0.8, x0 + 1.2]; `extra` follows.
std::string block(double x0, int n, const std::string& data) {
  return fmt::format(R"toml(
[mesh]
generator = "rectangle"
lower = [{0}, 0.0]
upper = [{1}, 2.0]
cells = [{2}, {2}]
[[mesh.part]]
name = "contact"
where = "abs(y) < 1e-12 && x > {3} && x < {4}"
[boundary]
clamped = ["top"]
contact = ["contact"]
[elasticity]
kind = "plane-stress"
E = 1000.0
nu = 0.3
[viscoplasticity]
law = "maxwell-damage"
[loads]
f0 = ["0", "-200*t"]
[contact]
gap = 0.0
[time]
T = 1.0
steps = 4
{5}
)toml",
                     x0, x0 + 2, n, x0 + 0.8, x0 + 1.2, data);
}

const char* const kSecondBody = R"toml(
[viscoplasticity]
law = "perzyna"
lambda = 2000.0
sigma_y = 1.0
[damage]
kappa = 0.1
beta0 = "0.9 - 0.01*x"
source = "strain"
)toml";


/// `text` with its first `from` replaced by `to`.
void replace(std::string& text, const std::string& from, const std::string& to) {
  text.replace(text.find(from), from.size(), to);
}

/// A second body "b" (block's mesh on [3, 5] × [0, 2], 5 × 5 cells, its part "contact"), then
/// `material`: its [body.*] tables.
std::string second_body(const std::string& material) {
  return R"toml(
[[body]]
name = "b"
[body.mesh]
generator = "rectangle"
lower = [3.0, 0.0]
upper = [5.0, 2.0]
cells = [5, 5]
[[body.mesh.part]]
name = "contact"
where = "abs(y) < 1e-12 && x > 3.8 && x < 4.2"
)toml" + material;
}

TEST(Bodies, TwoBodiesWithoutAPairRunAsEachAlone) {
  const std::string first_damage = "[damage]\nkappa = 1.0\nsource = \"von-mises\"\nc = 0.01\n";
  // The second body: another E, G, κ, β0 and φ; its parts named "b.<part>".
  const std::string two = block(0.0, 6, first_damage + second_body(R"toml(
[body.elasticity]
E = 2000.0
[body.viscoplasticity]
law = "perzyna"
lambda = 2000.0
sigma_y = 1.0
[body.damage]
kappa = 0.1
beta0 = "0.9 - 0.01*x"
source = "strain"
)toml"));
  std::string both = two;
  replace(both, "clamped = [\"top\"]", "clamped = [\"top\", \"b.top\"]");
  replace(both, "contact = [\"contact\"]", "contact = [\"contact\", \"b.contact\"]");
  std::string second = block(3.0, 5, kSecondBody);
  replace(second, "E = 1000.0", "E = 2000.0");
  const std::string maxwell = "[viscoplasticity]\nlaw = \"maxwell-damage\"\n";
  second.erase(second.find(maxwell), maxwell.size());
  const auto together = run_to_end(parse_case(both, "two.toml", ".", {}));
  const auto a = run_to_end(parse_case(block(0.0, 6, first_damage), "a.toml", ".", {}));
  const auto b = run_to_end(parse_case(second, "b.toml", ".", {}));
  const State &s = together->state(), &sa = a->state(), &sb = b->state();
  const auto na = sa.beta.size(), nb = sb.beta.size();
  ASSERT_EQ(s.beta.size(), na + nb);
  ASSERT_EQ(s.u.size(), sa.u.size() + sb.u.size());
  EXPECT_LT((s.u.head(sa.u.size()) - sa.u).cwiseAbs().maxCoeff(), 1e-12 * sa.u.cwiseAbs().maxCoeff());
  EXPECT_LT((s.u.tail(sb.u.size()) - sb.u).cwiseAbs().maxCoeff(), 1e-12 * sb.u.cwiseAbs().maxCoeff());
  EXPECT_LT((s.beta.head(na) - sa.beta).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((s.beta.tail(nb) - sb.beta).cwiseAbs().maxCoeff(), 1e-12);
  // The bodies differ, so the comparison can fail: damage and displacement are not alike.
  EXPECT_GT((sa.beta.head(nb) - sb.beta).cwiseAbs().maxCoeff(), 1e-3);
  EXPECT_LT(sb.beta.minCoeff(), 0.9);  // its β0, not [damage]'s 1
  EXPECT_GT(sa.u.cwiseAbs().maxCoeff(), 1e-4);
}

// A body with φ ≡ 0 and a uniform β0 keeps β = β0 exactly (constant_damage_nodes: its nodes are
// held, not solved for, where round-off would flip β = 1's degenerate bound); with a β0 that
// varies, β diffuses and is solved for. Either way the other body is as if alone.
TEST(Bodies, ABodyWhoseDamageCannotChangeKeepsItExactly) {
  const std::string first_damage = "[damage]\nkappa = 1.0\nsource = \"von-mises\"\nc = 0.01\n";
  auto with_second = [&](const std::string& beta0, const std::string& damage_solver = "active-set") {
    std::string text = block(0.0, 6, first_damage + second_body(fmt::format(R"toml(
[body.damage]
kappa = 0.1
beta0 = "{}"
source = "zero"
)toml", beta0)));
    replace(text, "clamped = [\"top\"]", "clamped = [\"top\", \"b.top\"]");
    replace(text, "contact = [\"contact\"]", "contact = [\"contact\", \"b.contact\"]");
    text += fmt::format("[solver]\ndamage = \"{}\"\n", damage_solver);
    return run_to_end(parse_case(text, "two.toml", ".", {}));
  };
  const auto alone = run_to_end(parse_case(block(0.0, 6, first_damage), "a.toml", ".", {}));
  const Vector& beta_a = alone->state().beta;
  const auto na = beta_a.size();
  ASSERT_LT(beta_a.minCoeff(), 0.999);  // the first body damages: its β is solved for
  const auto held = with_second("0.8");
  const Vector& beta = held->state().beta;
  for (Eigen::Index i = na; i < beta.size(); ++i) ASSERT_EQ(beta[i], 0.8) << i;  // exactly, not to round-off
  EXPECT_LT((beta.head(na) - beta_a).cwiseAbs().maxCoeff(), 1e-12);
  const auto held_pd = with_second("0.8", "penalty-duality");  // the other damage solver holds them too
  const Vector& beta_pd = held_pd->state().beta;
  for (Eigen::Index i = na; i < beta_pd.size(); ++i) ASSERT_EQ(beta_pd[i], 0.8) << i;
  EXPECT_LT((beta_pd.head(na) - beta_a).cwiseAbs().maxCoeff(), 1e-9);  // to its tolerance
  const auto varying = with_second("0.9 - 0.01*x");
  const Vector& beta_v = varying->state().beta;
  double moved = 0;  // κ spreads β0's slope: β differs from β0 = 0.9 − 0.01x inside
  const Mesh& mesh = varying->problem().mesh;
  for (Eigen::Index i = na; i < beta_v.size(); ++i)
    moved = std::max(moved, std::abs(beta_v[i] - (0.9 - 0.01 * mesh.node(static_cast<int>(i))[0])));
  EXPECT_GT(moved, 1e-6);
  EXPECT_LT((beta_v.head(na) - beta_a).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Bodies, BadBodiesAreRefusedNamingTheKey) {
  const std::string base = block(0.0, 5, "");
  auto with = [&](const std::string& body) { return error_of([&] { parse_case(base + body, "c.toml", ".", {}); }); };
  const std::string mesh = "[body.mesh]\ngenerator = \"rectangle\"\nlower = [3.0, 0.0]\nupper = [4.0, 1.0]\ncells = 2\n";
  EXPECT_NE(with("[[body]]\nname = \"body\"\n" + mesh).find("expected a new body name"), std::string::npos);
  EXPECT_NE(with("[[body]]\nname = \"a.b\"\n" + mesh).find("letters, digits"), std::string::npos);
  EXPECT_NE(with("[[body]]\nname = \"p\"\n" + mesh + "[[body]]\nname = \"p\"\n" + mesh).find("'p' is taken"),
            std::string::npos);
  EXPECT_NE(with("[[body]]\nname = \"p\"\n").find("missing section [body.mesh]"), std::string::npos);
  EXPECT_NE(with("[[body]]\nname = \"p\"\ncolour = 1\n" + mesh).find("unknown key 'colour' in [body[0]]"),
            std::string::npos);
  EXPECT_NE(with("[[body]]\nname = \"p\"\n" + mesh + "[body.elasticity]\nkind = \"plane-strain\"\n").find("kind"),
            std::string::npos);
  EXPECT_NE(with("[[body]]\nname = \"p\"\n" + mesh + "[body.damage]\nkappa = -1\n").find("kappa must be >= 0"),
            std::string::npos);
  EXPECT_NE(with("[[body]]\nname = \"p\"\n" + mesh + "[body.damage]\nbeta0 = 2\n").find("beta0 must lie in [0, 1]"),
            std::string::npos);
  // A body that nothing holds: K would be singular.
  const std::string loose = with("[[body]]\nname = \"p\"\n" + mesh);
  EXPECT_NE(loose.find("body 'p' is not held"), std::string::npos) << loose;
}

}  // namespace
}  // namespace vpc
