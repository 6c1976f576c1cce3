// The state's fields declared once (io/state_fields.hpp): every stored field has its
// place in the checkpoint format; λ as a block of contact_block numbers per contact node
// in the VTU files and the checkpoints (b > 1: friction, issue 28), a checkpoint of
// another block refused on resume; docs/cases.md lists the fields as the table does.
#include "cases/builtin_cases.hpp"
#include "io/checkpoint.hpp"
#include "io/checkpoint_file.hpp"
#include "io/state_fields.hpp"
#include "test_files.hpp"

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <fstream>
#include <set>
#include <sstream>

namespace vpc {
namespace {

namespace fs = std::filesystem;

fs::path fields_dir(const std::string& name) { return test::fresh_dir("vpc_fields_", name); }
std::string read_text(const fs::path& p) { return test::read_bytes(p); }

/// The state of a small run with λ made a block of b numbers per contact node (the
/// normal force first, then b − 1 numbers of its own), as a law with friction would.
State with_block(const TimeStepper& s, int b) {
  State st = s.state();
  const Eigen::Index m = s.state().lambda.size();
  st.contact_block = b;
  st.lambda.resize(m * b);
  for (Eigen::Index i = 0; i < m; ++i) {
    st.lambda[i * b] = s.state().lambda[i];
    for (int j = 1; j < b; ++j) st.lambda[i * b + j] = 0.5 * static_cast<double>(i) + j;
  }
  return st;
}

TEST(StateFields, EveryStoredFieldHasItsPlaceInTheCheckpoint) {
  std::set<int> arrays;
  for (const StateField& f : state_fields()) {
    if (!f.stored()) {
      EXPECT_NE(f.vtu_field, nullptr) << f.name << ": an output field is made for the VTU files";
      continue;
    }
    EXPECT_NE(f.assign, nullptr) << f.name;
    EXPECT_NO_THROW(arrays.insert(checkpoint_file::file_array(f.name))) << f.name;
  }
  EXPECT_EQ(arrays.size(), std::size(checkpoint_file::kFileArrays));
  EXPECT_EQ(OutputOptions::field_names(), vtu_field_names());
}

TEST(StateFields, LambdaBlockIsAPointFieldOfBComponents) {
  TimeStepper s(load_case("paper-2d", {.steps = 4}, {.cells = 10}).problem);
  s.step();
  s.step();
  ASSERT_GT(s.state().lambda.size(), 0);
  ASSERT_GT(s.state().lambda.maxCoeff(), 0);
  // b = 1 (every normal law): no λ field of its own; the force and pressure from λ.
  std::vector<VtuField> points, cells;
  make_vtu_fields({s.state(), s.part(), s.contact().nodes}, {}, points, cells);
  std::vector<std::string> names;
  for (const auto& f : points) names.push_back(f.name);
  EXPECT_EQ(names, (std::vector<std::string>{"displacement", "beta", "contact_force", "contact_pressure"}));
  const std::vector<double> pressure_1 = points[3].values, force_1 = points[2].values;
  // b = 3: a point field of 3 components, node after node (zero off Γ3); the force and
  // pressure from the normal force, as before.
  const State st = with_block(s, 3);
  points.clear();
  cells.clear();
  make_vtu_fields({st, s.part(), s.contact().nodes}, {}, points, cells);
  // (and friction's tangential force and traction, from λ's other numbers: test_friction_outputs.cpp)
  ASSERT_EQ(points.size(), 7u);
  EXPECT_EQ(points[5].name, "tangential_force");
  EXPECT_EQ(points[6].name, "tangential_traction");
  const VtuField& block = points[2];
  EXPECT_EQ(block.name, "contact_lambda");
  EXPECT_EQ(block.n_components, 3);
  ASSERT_EQ(block.values.size(), static_cast<std::size_t>(s.mesh().n_nodes()) * 3);
  for (const PartContactNode& c : s.contact().nodes)
    for (int j = 0; j < 3; ++j) EXPECT_EQ(block.values[c.local_node * 3 + j], st.lambda[c.row * 3 + j]);
  EXPECT_EQ(points[3].values, force_1);
  EXPECT_EQ(points[4].values, pressure_1);
  const fs::path file = fields_dir("vtu_block") / "s.vtu";
  write_vtu(file, s.mesh(), points, cells, {.compression = VtuCompression::none});
  EXPECT_NE(read_text(file).find("Name=\"contact_lambda\" NumberOfComponents=\"3\""), std::string::npos);
}

TEST(StateFields, CheckpointStoresTheBlockAndRefusesAnother) {
  TimeStepper s(load_case("paper-2d", {.steps = 4}, {.cells = 10}).problem);
  s.step();
  Checkpoint c = test::checkpoint_of(s);
  c.snapshot.state = with_block(s, 2);
  const fs::path dir = fields_dir("ckpt_block");
  const fs::path file = write_checkpoint(dir, c);
  const Checkpoint back = read_checkpoint(file);
  EXPECT_EQ(back.snapshot.state.contact_block, 2);
  EXPECT_EQ(back.snapshot.state.lambda, c.snapshot.state.lambda);
  EXPECT_EQ(back.snapshot.state.lambda.size(), 2 * s.state().lambda.size());
  EXPECT_EQ(back.snapshot.state.u, s.state().u);
  // A run whose law has one number per contact node does not resume it, and says why.
  TimeStepper other(load_case("paper-2d", {.steps = 4}, {.cells = 10}).problem);
  std::vector<std::string> skipped;
  EXPECT_FALSE(resume_from_checkpoint(other, dir, &skipped).has_value());
  ASSERT_EQ(skipped.size(), 1u);
  EXPECT_NE(skipped[0].find("2 contact unknowns per contact node, this problem has 1"), std::string::npos)
      << skipped[0];
  // b = 1 keeps the format of earlier versions: the header's second u32 is 0.
  c.snapshot = s.snapshot();
  const std::string bytes = read_text(write_checkpoint(dir, c));
  EXPECT_EQ(bytes.substr(12, 4), std::string(4, '\0'));
  EXPECT_EQ(read_checkpoint(dir / "checkpoint_00001.bin").snapshot.state.contact_block, 1);
}

TEST(StateFields, NormalForcesAreTheFirstOfEachBlock) {
  State s;
  s.contact_block = 2;
  s.lambda = Eigen::Vector4d(1, 9, 2, 8);
  EXPECT_EQ(normal_forces(s), Eigen::VectorXd(Eigen::Vector2d(1, 2)));
  s.contact_block = 1;
  EXPECT_EQ(normal_forces(s), s.lambda);
}

/// The lines of `text` between the marker comment `<!-- begin NAME -->` and `<!-- end NAME -->`.
std::string between(const std::string& text, const std::string& name) {
  const std::string begin = fmt::format("<!-- begin {} -->\n", name), end = fmt::format("<!-- end {} -->", name);
  const auto a = text.find(begin), b = text.find(end);
  if (a == std::string::npos || b == std::string::npos || b < a) return "(no markers " + name + ")";
  return text.substr(a + begin.size(), b - a - begin.size());
}

// docs/cases.md's table of the fields is this table's (paste the expected text there
// when a field is added).
TEST(StateFields, DocsListEveryField) {
  std::string expected = "| field | VTU array | Python | where | meaning |\n|---|---|---|---|---|\n";
  for (const StateField& f : state_fields())
    expected += fmt::format("| `{}` | {} | {} | {} | {} |\n", f.name, f.vtu.empty() ? "—" : fmt::format("`{}`", f.vtu),
                            f.python.empty() ? "—" : fmt::format("`{}`", f.python), location_name(f.location),
                            f.meaning);
  EXPECT_EQ(between(read_text(fs::path(VPC_TEST_DATA_DIR) / "../../docs/cases.md"), "state fields"), expected)
      << "docs/cases.md between the markers should read:\n"
      << expected;
}

}  // namespace
}  // namespace vpc
