// Issue 11 item 16: the paper's block is symmetric about x = 1; its solution is
// mirror-symmetric to round-off on a mesh that is ("crossed", "alternate" with an
// even number of cells), and not on the default "right" mesh (one diagonal).
#include "cases/shipped_cases.hpp"
#include "core/error.hpp"
#include "io/case_file.hpp"
#include "scheme/time_stepper.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <utility>

namespace vpc {
namespace {

/// max |u(mirror x) − mirror u(x)| and max |β(mirror x) − β(x)| over the nodes,
/// relative to max |u| and 1, after a few steps of the paper-2d case at n = 10.
std::pair<double, double> mirror_asymmetry(const std::string& diagonal) {
  const auto& shipped = shipped_cases();
  const auto it = std::find_if(shipped.begin(), shipped.end(), [](const auto& s) { return s.name == "paper-2d"; });
  EXPECT_NE(it, shipped.end());
  const Case c = parse_case(it->text, "paper-2d.toml", ".",
                            {.sets = {"mesh.cells=[10, 10]", "mesh.diagonal=\"" + diagonal + "\"", "time.steps=5"}});
  TimeStepper s(c.problem, c.solvers);
  while (!s.done()) EXPECT_TRUE(s.step().ok);
  const Mesh& m = s.mesh();
  std::map<std::pair<long long, long long>, int> node_at;
  auto key = [](const Point& x) { return std::make_pair(std::llround(x[0] * 1e9), std::llround(x[1] * 1e9)); };
  for (int i = 0; i < m.n_nodes(); ++i) node_at[key(m.node(i))] = i;
  const Vector& u = s.state().u;
  const Vector& beta = s.state().beta;
  double du = 0, db = 0;
  for (int i = 0; i < m.n_nodes(); ++i) {
    const auto j = node_at.find(key({2.0 - m.node(i)[0], m.node(i)[1], 0}));
    EXPECT_NE(j, node_at.end());
    du = std::max({du, std::abs(u[2 * j->second] + u[2 * i]), std::abs(u[2 * j->second + 1] - u[2 * i + 1])});
    db = std::max(db, std::abs(beta[j->second] - beta[i]));
  }
  std::printf("  %s: relative mirror asymmetry of u %.3g, of beta %.3g\n", diagonal.c_str(), du / u.cwiseAbs().maxCoeff(), db);
  return {du / u.cwiseAbs().maxCoeff(), db};
}

TEST(MeshSymmetry, CrossedAndAlternateGiveMirrorSymmetricSolution) {
  for (const char* d : {"crossed", "alternate"}) {
    const auto [du, db] = mirror_asymmetry(d);
    EXPECT_LT(du, 1e-10) << d;
    EXPECT_LT(db, 1e-12) << d;
  }
  const auto [du, db] = mirror_asymmetry("right");
  EXPECT_GT(du, 1e-3) << "the one-diagonal mesh is expected to break the symmetry";
  (void)db;
}

TEST(MeshSymmetry, UnknownDiagonalInCaseFileListsValues) {
  const auto& shipped = shipped_cases();
  const auto it = std::find_if(shipped.begin(), shipped.end(), [](const auto& s) { return s.name == "paper-2d"; });
  try {
    parse_case(it->text, "paper-2d.toml", ".", {.sets = {"mesh.diagonal=\"diagonal\""}});
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("--set mesh.diagonal=\"diagonal\": unknown value 'diagonal'; expected one of: right, left, "
                                         "alternate, crossed"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace vpc
