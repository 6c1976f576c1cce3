// Friction's outputs (issue 28) on a frictional state made by hand (λ a block of d numbers
// per contact node, the slip fields filled): the tangents of the contact solver's frame in
// global coordinates, the VTU fields (tangential force and traction, slip increment as
// vectors, accumulated slip and status), the checkpoint of the friction fields and totals
// bit for bit (a frictionless checkpoint as before), history.csv's friction columns
// (none without friction) and the step's tangential totals per obstacle.
#include "../../case_text.hpp"
#include "cases/builtin_cases.hpp"
#include "io/case_file.hpp"
#include "io/checkpoint.hpp"
#include "io/checkpoint_file.hpp"
#include "io/history_columns.hpp"
#include "io/state_fields.hpp"
#include "part/contact_tangents.hpp"
#include "scheme/step_checks.hpp"
#include "test_files.hpp"

#include <gtest/gtest.h>

#include <map>

namespace vpc {
namespace {

namespace fs = std::filesystem;

fs::path friction_out_dir(const std::string& name) { return test::fresh_dir("vpc_friction_out_", name); }
using test::read_bytes;

double dot(const Point& a, const Point& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// `s`'s state made frictional by hand: λ a block of b numbers per contact node (the normal
/// force, then tangential forces of its own), the slip fields filled, the statuses cycling.
State frictional(const State& s0, int b) {
  State s = s0;
  const Eigen::Index m = s0.lambda.size() / s0.contact_block;
  s.contact_block = b;
  s.lambda.resize(m * b);
  s.slip_step.resize(m * (b - 1));
  s.slip.resize(m);
  s.contact_status.resize(m);
  for (Eigen::Index i = 0; i < m; ++i) {
    s.lambda[i * b] = 1.0 + 0.25 * static_cast<double>(i);
    for (int j = 1; j < b; ++j) {
      s.lambda[i * b + j] = 0.1 * static_cast<double>(j) - 0.03 * static_cast<double>(i);
      s.slip_step[i * (b - 1) + j - 1] = 1e-3 * static_cast<double>(i + j) / 3.0;
    }
    s.slip[i] = 1e-2 * std::sqrt(static_cast<double>(i) + 0.5);
    s.contact_status[i] = static_cast<double>(i % 3);
  }
  return s;
}

TEST(ContactTangents, UnitAndOrthogonalToTheNormalInBothFrames) {
  const Case c = load_case("block-3d", {.steps = 2}, {.cells = 5});
  MeshPart part = whole_mesh_part(c.problem);
  ASSERT_GT(part.contact.size(), 3u);
  // The case's normals are the axis −z (identity frame): tangents e_x, e_y.
  std::vector<Point> t = contact_tangents(part.dofs, part.contact, 3);
  ASSERT_EQ(t.size(), 2 * part.contact.size());
  EXPECT_EQ(t[0], (Point{1, 0, 0}));
  EXPECT_EQ(t[1], (Point{0, 1, 0}));
  // Tilted normals: the Householder frame, orthonormal with ν.
  for (std::size_t k = 0; k < part.contact.size(); ++k) {
    const double a = 0.3 + 0.1 * static_cast<double>(k), b = 0.7 - 0.05 * static_cast<double>(k);
    Point nu{std::sin(a) * std::cos(b), std::sin(a) * std::sin(b), -std::cos(a)};
    part.contact[k].direction = nu;
  }
  t = contact_tangents(part.dofs, part.contact, 3);
  for (std::size_t k = 0; k < part.contact.size(); ++k) {
    const Point& nu = part.contact[k].direction;
    EXPECT_NEAR(dot(t[2 * k], t[2 * k]), 1.0, 1e-14);
    EXPECT_NEAR(dot(t[2 * k + 1], t[2 * k + 1]), 1.0, 1e-14);
    EXPECT_NEAR(dot(t[2 * k], t[2 * k + 1]), 0.0, 1e-14);
    EXPECT_NEAR(dot(t[2 * k], nu), 0.0, 1e-14);
    EXPECT_NEAR(dot(t[2 * k + 1], nu), 0.0, 1e-14);
  }
  // Σ_j x_j t_j.
  const double x[2] = {2.0, -0.5};
  const Point v = along_tangents(t, 1, 3, x);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_DOUBLE_EQ(v[i], 2.0 * t[2][i] - 0.5 * t[3][i]);
  EXPECT_TRUE(contact_tangents(part.dofs, part.contact, 1).empty());
}

// The outputs' tangents are the contact solver's: DiscreteSystem::T's rows (owned free dofs) by
// component, here for tilted contact directions (the Householder frame).
TEST(ContactTangents, AreTheRowsOfTheSystemsT) {
  const Case c = load_case((fs::path(VPC_TEST_DATA_DIR) / "friction-2d.toml").string());
  auto p = std::make_shared<Problem>(*c.problem);
  const double n = std::hypot(0.3, 1.0);
  p->contact.direction = Point{0.3 / n, -1.0 / n, 0.0};
  const DiscreteSystem sys(p, whole_mesh_part(p), la::serial_backend(), SolverChoice{});
  const MeshPart& part = sys.part;
  ASSERT_EQ(sys.contact->friction.T.rows(), static_cast<Eigen::Index>(sys.contact->nodes.size()));
  const std::vector<Point> t = contact_tangents(part.dofs, sys.contact->nodes, 2);
  const SparseMatrix Tt = sys.contact->friction.T.transpose();
  Eigen::Index row = 0;
  for (std::size_t k = 0; k < sys.contact->nodes.size(); ++k) {
    const PartContactNode& node = sys.contact->nodes[k];
    ASSERT_TRUE(node.owned);
    EXPECT_NE(t[k][0], 0.0);  // tilted: not an axis
    Point from_T{0, 0, 0};
    for (SparseMatrix::InnerIterator it(Tt, row); it; ++it)
      for (int i = 0; i < 2; ++i)
        if (part.dofs.free_index(part.dofs.full_index(node.local_node, i)) == it.row()) from_T[i] = it.value();
    EXPECT_EQ(t[k], from_T) << "contact node " << k;
    ++row;
  }
}

TEST(FrictionOutputs, VtuFieldsAreTheTangentialVectorsSlipAndStatus) {
  TimeStepper s(load_case("paper-2d", {.steps = 4}, {.cells = 10}).problem);
  s.step();
  const State st = frictional(s.state(), 2);
  const MeshPart& part = s.part();
  const std::vector<Point> t = contact_tangents(part.dofs, s.contact().nodes, 2);
  std::vector<VtuField> points, cells;
  make_vtu_fields({st, part, s.contact().nodes}, {}, points, cells);
  std::map<std::string, const VtuField*> by_name;
  for (const VtuField& f : points) by_name[f.name] = &f;
  for (const char* name : {"tangential_force", "tangential_traction", "slip_increment", "slip", "contact_status"})
    ASSERT_TRUE(by_name.count(name)) << name;
  EXPECT_EQ(by_name["tangential_force"]->n_components, 3);
  EXPECT_EQ(by_name["slip"]->n_components, 1);
  std::vector<char> on_contact(static_cast<std::size_t>(s.mesh().n_nodes()), 0);
  for (std::size_t k = 0; k < s.contact().nodes.size(); ++k) {
    const PartContactNode& n = s.contact().nodes[k];
    on_contact[static_cast<std::size_t>(n.local_node)] = 1;
    const double lt = st.lambda[n.row * 2 + 1], dt = st.slip_step[n.row];
    for (std::size_t i = 0; i < 3; ++i) {
      // the force on the body: λ_τ's opposite (λ_τ is the force on the obstacle), as contact_force −λ ν
      EXPECT_EQ(by_name["tangential_force"]->values[n.local_node * 3 + i], -lt * t[k][i]);
      EXPECT_EQ(by_name["tangential_traction"]->values[n.local_node * 3 + i], -lt * t[k][i] / n.measure);
      EXPECT_EQ(by_name["slip_increment"]->values[n.local_node * 3 + i], dt * t[k][i]);
    }
    EXPECT_EQ(by_name["slip"]->values[n.local_node], st.slip[n.row]);
    EXPECT_EQ(by_name["contact_status"]->values[n.local_node], st.contact_status[n.row]);
  }
  for (std::size_t i = 0; i < on_contact.size(); ++i)
    if (!on_contact[i]) {
      EXPECT_EQ(by_name["slip"]->values[i], 0.0);
      EXPECT_EQ(by_name["tangential_force"]->values[i * 3], 0.0);
    }
  // [output] fields selects them; a frictionless state has none of them.
  points.clear();
  make_vtu_fields({st, part, s.contact().nodes}, {"slip", "beta"}, points, cells);
  ASSERT_EQ(points.size(), 2u);
  EXPECT_EQ(points[0].name, "beta");
  EXPECT_EQ(points[1].name, "slip");
  points.clear();
  make_vtu_fields({s.state(), part, s.contact().nodes}, {"slip", "tangential_force", "contact_status"}, points, cells);
  EXPECT_TRUE(points.empty());
}

TEST(FrictionOutputs, CheckpointKeepsTheFrictionStateBitForBit) {
  TimeStepper s(load_case("paper-2d", {.steps = 4}, {.cells = 10}).problem);
  s.step();
  Checkpoint c = test::checkpoint_of(s);
  RunTotals friction_totals;
  friction_totals.max_friction_bound = 1.5e-12;
  friction_totals.max_stick_slip = 2.5e-11;
  friction_totals.max_slip_direction = 3.0e-13;
  friction_totals.dissipation = 0.1 / 3;
  c.totals = friction_totals;
  // Without friction the file is that of before: its friction totals are not written.
  const fs::path plain = write_checkpoint(friction_out_dir("plain"), c);
  const Checkpoint plain_back = read_checkpoint(plain);
  EXPECT_EQ(plain_back.totals.dissipation, 0.0);
  EXPECT_EQ(plain_back.snapshot.state.slip.size(), 0);
  c.totals = {};
  const std::string before = read_bytes(write_checkpoint(friction_out_dir("plain2"), c));
  EXPECT_EQ(read_bytes(plain), before);
  // With friction: the fields and totals back bit for bit.
  c.snapshot.state = frictional(s.state(), 2);
  c.totals = friction_totals;
  const fs::path file = write_checkpoint(friction_out_dir("friction"), c);
  const Checkpoint back = read_checkpoint(file);
  const State& a = c.snapshot.state;
  const State& b = back.snapshot.state;
  EXPECT_EQ(b.contact_block, 2);
  EXPECT_EQ(b.lambda, a.lambda);
  EXPECT_EQ(b.slip_step, a.slip_step);
  EXPECT_EQ(b.slip, a.slip);
  EXPECT_EQ(b.contact_status, a.contact_status);
  EXPECT_EQ(b.u, a.u);
  EXPECT_EQ(back.totals.max_friction_bound, c.totals.max_friction_bound);
  EXPECT_EQ(back.totals.max_stick_slip, c.totals.max_stick_slip);
  EXPECT_EQ(back.totals.max_slip_direction, c.totals.max_slip_direction);
  EXPECT_EQ(back.totals.dissipation, c.totals.dissipation);
  // Exactly the friction arrays and totals more than the frictionless file of the same λ.
  const std::string bytes = read_bytes(file);
  const std::size_t m = static_cast<std::size_t>(a.slip.size());
  EXPECT_EQ(bytes.size(), before.size() + 8 * m /* λ_τ */ + 3 * 8 + 8 * (m + m + m) + 4 * 8);
  // A damaged friction array count is refused with the file's name.
  Checkpoint bad = c;
  bad.snapshot.state.slip.resize(m - 1);
  const fs::path bad_file = write_checkpoint(friction_out_dir("bad"), bad);
  try {
    read_checkpoint(bad_file);
    ADD_FAILURE() << "a checkpoint whose slip does not fit its λ was read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(bad_file.string()), std::string::npos) << e.what();
  }
}

// A rejected step is redone from the snapshot before it (step control, halving, resume): the
// slip it accumulated must go with it, so the redone step ends bit for bit where it did.
TEST(FrictionOutputs, RestoringASnapshotUndoesTheSlipOfTheStep) {
  const Case c = load_case((fs::path(VPC_TEST_DATA_DIR) / "friction-2d.toml").string());
  TimeStepper s(c.problem, c.solvers);
  for (int n = 0; n < 7; ++n) s.step();  // sliding from step 6 on
  const Snapshot before = s.snapshot();
  s.step();
  const State once = s.state();
  ASSERT_GT((once.slip - before.state.slip).maxCoeff(), 0.0);
  s.restore(before);
  EXPECT_EQ(s.state().slip, before.state.slip);
  EXPECT_EQ(s.state().slip_step, before.state.slip_step);
  EXPECT_EQ(s.state().contact_status, before.state.contact_status);
  s.step();
  EXPECT_EQ(s.state().slip, once.slip);
  EXPECT_EQ(s.state().slip_step, once.slip_step);
  EXPECT_EQ(s.state().contact_status, once.contact_status);
  EXPECT_EQ(s.state().lambda, once.lambda);
}

TEST(FrictionOutputs, HistoryHasFrictionColumnsOnlyWithFriction) {
  const Case plain = load_case("hertz-2d", {.steps = 1}, {.cells = 20});
  const MeshPart part = whole_mesh_part(plain.problem);
  const std::vector<std::string> before = history_column_names(*plain.problem, part);
  for (const std::string& n : before) EXPECT_EQ(n.find("tangential"), std::string::npos) << n;
  auto p = std::make_shared<Problem>(*plain.problem);
  p->contact.friction = std::make_shared<CoulombFriction>(0.3);
  const std::vector<std::string> names = history_column_names(*p, part);
  ASSERT_EQ(names.size(), before.size() + friction_columns().size() + 2 + 2);
  EXPECT_TRUE(std::equal(before.begin(), before.end(), names.begin()));  // a prefix: the old columns in place
  const std::vector<std::string> tail(names.begin() + static_cast<std::ptrdiff_t>(before.size()), names.end());
  EXPECT_EQ(tail, (std::vector<std::string>{"n_stick", "n_slip", "dissipation", "friction_bound", "friction_stick_slip",
                                            "friction_slip_direction", "tangential_force_x", "tangential_force_y",
                                            "tangential_force_cylinder_x", "tangential_force_cylinder_y"}));
  StepReport r;
  r.obstacle_force = {2.0};
  r.reaction.assign(before.size() - history_columns().size() - 1, 0.0);
  EXPECT_EQ(history_values(r).size(), before.size());  // no tangential force: no friction columns
  r.contact.n_stick = 3;
  r.contact.n_slip = 4;
  r.contact.dissipation = 0.125;
  r.contact.residuals.friction_bound = 1e-12;
  r.contact.residuals.stick_slip = 2e-12;
  r.contact.residuals.slip_direction = 3e-12;
  r.tangential_force = {0.5, -0.25};
  r.obstacle_tangential_force = {0.5, -0.25};
  r.contact.n_open = -1;  // no bound that acts out of contact (contact_totals): no n_tresca_open
  const std::vector<HistoryValue> row = history_values(r);
  ASSERT_EQ(row.size(), names.size());
  std::vector<std::string> text;
  for (std::size_t i = before.size(); i < row.size(); ++i) text.push_back(row[i].text());
  EXPECT_EQ(text, (std::vector<std::string>{"3", "4", "0.125", "1.000e-12", "2.000e-12", "3.000e-12", "0.5", "-0.25",
                                            "0.5", "-0.25"}));
}

TEST(FrictionOutputs, StepTotalsSumTheTangentialForcesPerObstacle) {
  const Case c = load_case("hertz-2d", {.steps = 1}, {.cells = 20});
  const DiscreteSystem sys(c.problem, whole_mesh_part(c.problem), la::serial_backend(), SolverChoice{});
  State s;
  s.contact_block = 1;
  s.lambda = Vector::Zero(sys.part.n_contact);
  StepReport plain;
  plain.t = 1;
  contact_totals(sys, frictional(s, 2), plain);  // the normal totals as without friction
  StepReport normal_only;
  normal_only.t = 1;
  State lambda_nu = frictional(s, 2);
  const State nu_only = [&] {
    State x = s;
    x.lambda = normal_forces(lambda_nu);
    return x;
  }();
  contact_totals(sys, nu_only, normal_only);
  EXPECT_EQ(plain.obstacle_force, normal_only.obstacle_force);
  EXPECT_EQ(plain.contact_area, normal_only.contact_area);
  EXPECT_TRUE(normal_only.tangential_force.empty());
  EXPECT_TRUE(normal_only.obstacle_tangential_force.empty());
  // The tangential force: Σ_i λ_τ,i t_i, all of it on the one obstacle.
  const std::vector<Point> t = contact_tangents(sys.part.dofs, sys.contact->nodes, 2);
  double x = 0, y = 0;
  for (std::size_t k = 0; k < sys.contact->nodes.size(); ++k) {
    const double l = lambda_nu.lambda[sys.contact->nodes[k].row * 2 + 1];
    x += l * t[k][0];
    y += l * t[k][1];
  }
  ASSERT_EQ(plain.tangential_force.size(), 2u);
  EXPECT_NEAR(plain.tangential_force[0], x, 1e-12 * (1 + std::abs(x)));
  EXPECT_NEAR(plain.tangential_force[1], y, 1e-12 * (1 + std::abs(y)));
  EXPECT_NE(plain.tangential_force[0], 0.0);
  EXPECT_EQ(plain.obstacle_tangential_force, plain.tangential_force);
}

// Two contact parts with their own friction: history.csv's columns per law entry, whose
// forces add up to the totals.
TEST(FrictionOutputs, ForcesPerContactPartAddUpToTheTotals) {
  // tests/data/friction-2d.toml's block with its bottom in two contact parts, the right one's mu its own.
  std::string text = read_bytes(fs::path(VPC_TEST_DATA_DIR) / "friction-2d.toml");
  text = test::replaced(text, "cells = [8, 4]\n", R"(cells = [8, 4]
[[mesh.part]]
name = "lhalf"
where = "abs(y) < 1e-12 && x < 0.45"
[[mesh.part]]
name = "rhalf"
where = "abs(y) < 1e-12 && x > 0.55"
)");
  text = test::replaced(text, "contact = [\"bottom\"]", "contact = [\"lhalf\", \"rhalf\"]");
  text = test::replaced(text, "mu = 0.3\n", R"(mu = 0.3
[[contact.part]]
parts = ["rhalf"]
friction = "coulomb"
mu = 0.5
)");
  const Case c = parse_case(text, "parts.toml", ".", {});
  const DiscreteSystem sys(c.problem, whole_mesh_part(c.problem), la::serial_backend(), SolverChoice{});
  const std::vector<std::string> names = history_column_names(*c.problem, sys.part);
  const std::vector<std::string> tail(names.end() - 6, names.end());
  EXPECT_EQ(tail, (std::vector<std::string>{"force_part_lhalf", "tangential_force_part_lhalf_x",
                                            "tangential_force_part_lhalf_y", "force_part_rhalf",
                                            "tangential_force_part_rhalf_x", "tangential_force_part_rhalf_y"}));
  State s;
  s.contact_block = 1;
  s.lambda = Vector::Zero(sys.part.n_contact);
  const State st = frictional(s, 2);
  StepReport r;
  r.t = 1;
  contact_totals(sys, st, r);
  ASSERT_EQ(r.part_force.size(), 2u);
  ASSERT_EQ(r.part_tangential_force.size(), 4u);
  EXPECT_GT(r.part_force[0], 0.0);
  EXPECT_GT(r.part_force[1], 0.0);
  EXPECT_NEAR(r.part_force[0] + r.part_force[1], normal_forces(st).sum(), 1e-12 * normal_forces(st).sum());
  for (std::size_t i = 0; i < 2; ++i)
    EXPECT_NEAR(r.part_tangential_force[i] + r.part_tangential_force[2 + i], r.tangential_force[i], 1e-12);
  const std::vector<HistoryValue> row = history_values(r);
  EXPECT_EQ(row.back().value, r.part_tangential_force[3]);
  EXPECT_EQ(row[row.size() - 3].value, r.part_force[1]);
}

}  // namespace
}  // namespace vpc
