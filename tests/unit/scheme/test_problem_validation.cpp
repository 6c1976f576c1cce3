// Invalid problems give a clear vpc::Error naming what is wrong, never a crash.
#include "../error_of.hpp"
#include "cases/builtin_cases.hpp"
#include "core/error.hpp"
#include "scheme/time_stepper.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace vpc {
namespace {

std::shared_ptr<Problem> paper_2d() { return load_case("paper-2d", {}, {.cells = 5}).problem; }

TEST(ProblemValidation, EmptyContactPart) {
  auto p = paper_2d();
  p->contact.parts = {"nowhere"};
  EXPECT_NE(error_of([&] { TimeStepper s(p); }).find("contact part 'nowhere' has no boundary facets"),
            std::string::npos);
}

TEST(ProblemValidation, ContactPartEntirelyClamped) {
  auto p = paper_2d();
  p->contact.parts = {"top"};  // the clamped side: no free contact node remains
  const std::string m = error_of([&] { TimeStepper s(p); });
  EXPECT_NE(m.find("boundary.contact: the contact part has no free node: every displacement component of each of its "
                   "nodes is prescribed, by "),
            std::string::npos)
      << m;
  EXPECT_NE(m.find("boundary.clamped;"), std::string::npos) << m;
}

TEST(ProblemValidation, MissingClampedPart) {
  auto p = paper_2d();
  p->clamped = {};
  EXPECT_NE(error_of([&] { TimeStepper s(p); }).find("no clamped part"), std::string::npos);
  p->clamped = {"roof"};
  EXPECT_NE(error_of([&] { TimeStepper s(p); }).find("clamped part 'roof' has no boundary facets"),
            std::string::npos);
}

TEST(ProblemValidation, NegativeKappaAndTime) {
  auto p = paper_2d();
  p->kappa = -0.5;
  EXPECT_NE(error_of([&] { TimeStepper s(p); }).find("kappa"), std::string::npos);
  p = paper_2d();
  p->n_steps = 0;
  EXPECT_NE(error_of([&] { TimeStepper s(p); }).find("time steps must be >= 1"), std::string::npos);
  p = paper_2d();
  p->final_time = -1;
  EXPECT_NE(error_of([&] { TimeStepper s(p); }).find("final time T must be > 0"), std::string::npos);
}

TEST(ProblemValidation, InitialDamageOutsideUnitInterval) {
  auto p = paper_2d();
  p->beta0 = [](const Point& x, double) { return x[0] > 1 ? 1.2 : 1.0; };
  EXPECT_NE(error_of([&] { TimeStepper s(p); }).find("beta0 must lie in [0, 1]"), std::string::npos);
}

TEST(ProblemValidation, NegativeGapAndDimensionMismatch) {
  auto p = paper_2d();
  p->contact.gap = [](const Point&, double) { return -0.1; };
  EXPECT_NE(error_of([&] { TimeStepper s(p); }).find("gap g must be >= 0"), std::string::npos);
  p = paper_2d();
  p->elasticity = Elasticity(Elasticity::Kind::Isotropic, 1, 0.3);
  EXPECT_NE(error_of([&] { TimeStepper s(p); }).find("is for d = 3 but the mesh has d = 2"), std::string::npos);
}

// Issue 11 item 4: paper-2d's contact patch lies on the bottom side (outward normal
// (0, −1)); a direction (0, 1) points into the body and must be refused, naming the
// node, its coordinates, both vectors and the angle.
TEST(ProblemValidation, ContactDirectionIntoTheBodyIsRefused) {
  auto p = paper_2d();
  p->contact.direction = Point{0, 1, 0};
  const std::string m = error_of([&] { TimeStepper s(p); });
  EXPECT_NE(m.find("the contact direction (0, 1, 0) points into the body at contact node"), std::string::npos) << m;
  EXPECT_NE(m.find("outward normal (0, -1, 0)"), std::string::npos) << m;
  EXPECT_NE(m.find("is 180 degrees"), std::string::npos) << m;
  EXPECT_NE(m.find(", 0, 0)"), std::string::npos) << m;  // the node's coordinates (x, 0, 0)
  // Tangential (90°) is refused as well; a little beyond 90° too.
  p->contact.direction = Point{1, 0, 0};
  EXPECT_NE(error_of([&] { TimeStepper s(p); }).find("is 90 degrees"), std::string::npos);
  p->contact.direction = Point{1, 0.01, 0};
  EXPECT_NE(error_of([&] { TimeStepper s(p); }).find("points into the body"), std::string::npos);
}

TEST(ProblemValidation, ObliqueContactDirectionWithin90DegreesIsAccepted) {
  auto p = paper_2d();
  const double a = 60 * std::acos(-1.0) / 180;  // 60° from the outward normal (0, −1)
  p->contact.direction = Point{std::sin(a), -std::cos(a), 0};
  TimeStepper s(p);
  ASSERT_FALSE(s.contact().nodes.empty());
  for (const PartContactNode& c : s.contact().nodes) {
    EXPECT_NEAR(c.direction[0], std::sin(a), 1e-15);
    EXPECT_NEAR(c.direction[1], -std::cos(a), 1e-15);
  }
  EXPECT_TRUE(s.step().ok);
}

// Issue 11 item 12: a NaN or infinite gap is "not finite", not "negative".
TEST(ProblemValidation, NonFiniteGapIsCalledNotFinite) {
  for (double g : {std::nan(""), std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()}) {
    auto p = paper_2d();
    p->contact.gap = [g](const Point&, double) { return g; };
    const std::string m = error_of([&] { TimeStepper s(p); });
    EXPECT_NE(m.find("the gap g is not finite"), std::string::npos) << m;
    EXPECT_EQ(m.find(">= 0"), std::string::npos) << m;
  }
}

TEST(ProblemValidation, BuiltinOverrides) {
  EXPECT_NE(error_of([] { load_case("paper-2d", {}, {.cells = 7}); }).find("multiple of 5"),
            std::string::npos);
  EXPECT_NE(error_of([] { load_case("paper-1d", {.time_step = -0.01}); }).find("time step must be > 0"),
            std::string::npos);
  EXPECT_NE(error_of([] { load_case("paper-1d", {.kappa = -1.0}); }).find("kappa must be >= 0"),
            std::string::npos);
  EXPECT_NE(error_of([] { load_case("paper-3d"); }).find("unknown case 'paper-3d'"), std::string::npos);
}

TEST(ProblemValidation, SteppingPastTheEnd) {
  auto p = load_case("paper-1d", {.steps = 2}, {.cells = 10}).problem;
  TimeStepper s(p);
  s.step();
  s.step();
  EXPECT_TRUE(s.done());
  EXPECT_THROW(s.step(), Error);
}

}  // namespace
}  // namespace vpc

namespace vpc {
namespace {

// Loads that do not depend on x are assembled once (f(t) times ∫ψ_a) instead of
// by quadrature at every step; both must give the same run. The uniform path is
// checked against the quadrature path with f0 and f2 both present, in 2D and 3D.
TEST(UniformLoads, GiveTheSameRunAsQuadrature) {
  for (const char* name : {"paper-2d", "block-3d"}) {
    SCOPED_TRACE(name);
    auto quadrature = load_case(name, {.steps = 4}, {.cells = 5}).problem;
    const int d = quadrature->mesh.dim();
    quadrature->f2 = [d](const Point&, double t) { return Point{0.5 * t, d == 3 ? 0.25 : -0.25 * t, 0}; };
    quadrature->f0_uniform = quadrature->f2_uniform = false;
    auto uniform = std::make_shared<Problem>(*quadrature);
    uniform->f0_uniform = uniform->f2_uniform = true;
    TimeStepper a(quadrature), b(uniform);
    for (int n = 0; n < 4; ++n) {
      a.step();
      b.step();
    }
    const double scale = a.state().u.cwiseAbs().maxCoeff();
    ASSERT_GT(scale, 0);
    EXPECT_LE((a.state().u - b.state().u).cwiseAbs().maxCoeff(), 1e-12 * scale);
    EXPECT_LE((a.state().beta - b.state().beta).cwiseAbs().maxCoeff(), 1e-12);
  }
}

}  // namespace
}  // namespace vpc
