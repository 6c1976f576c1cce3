// Case files: a valid case, its built-in twins, expressions, overrides, and a
// table of bad case files with the message each must give.
#include "../../case_text.hpp"
#include "cases/builtin_cases.hpp"
#include "core/error.hpp"
#include "core/expression.hpp"
#include "io/case_file.hpp"
#include "io/state_fields.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace vpc {
namespace {

const char* kValid = R"(
[case]
name = "small"

[mesh]
generator = "rectangle"
lower = [0.0, 0.0]
upper = [2.0, 1.0]
cells = [10, 5]

[[mesh.part]]
name = "patch"
where = "abs(y) < 1e-9 && x > 0.6 && x < 1.4"

[boundary]
clamped = ["top"]
contact = ["patch"]

[elasticity]
kind = "plane-strain"
E = 100.0
nu = 0.25

[viscoplasticity]
law = "perzyna-von-mises"
lambda = 10.0
sigma_y = 0.5

[damage]
kappa = 0.5
phi = "-0.01*vm*beta"
beta0 = "1 - 0.1*x/2"

[loads]
f0 = ["0", "-5*t"]

[contact]
gap = "0.001*x"
direction = [0, -1]

[time]
T = 0.5
dt = 0.05

[output]
times = [0.1, 0.5]
probes = [[1.0, 0.0]]
fields = ["displacement", "damage"]
)";

std::string error_of(const std::string& text, const std::vector<std::string>& sets = {}) {
  return test::case_error(text, "bad.toml", sets);
}

/// Replaces the first occurrence of `from` in the valid case by `to`.
std::string variant(const std::string& from, const std::string& to) { return test::replaced(kValid, from, to); }

TEST(CaseFile, ValidCaseIsReadCompletely) {
  const Case c = parse_case(kValid, "ok.toml", ".");
  const Problem& p = *c.problem;
  EXPECT_EQ(c.name, "small");
  EXPECT_EQ(p.mesh.dim(), 2);
  EXPECT_EQ(p.mesh.n_cells(), 2 * 10 * 5);
  EXPECT_EQ(p.mesh.part_size("patch"), 4);
  EXPECT_EQ(p.elasticity.name(), "plane-strain");
  EXPECT_DOUBLE_EQ(p.elasticity.young(), 100.0);
  EXPECT_EQ(p.n_steps, 10);
  EXPECT_DOUBLE_EQ(p.kappa, 0.5);
  EXPECT_NEAR(p.f0({1, 2, 0}, 0.4)[1], -2.0, 1e-15);
  EXPECT_NEAR(p.contact.gap({1.5, 0, 0}, 0), 0.0015, 1e-15);
  EXPECT_NEAR(p.beta0({2, 0, 0}, 0), 0.9, 1e-15);
  ASSERT_TRUE(p.contact.direction.has_value());
  EXPECT_EQ((*p.contact.direction)[1], -1.0);
  EXPECT_EQ(c.output.times, (std::vector<double>{0.1, 0.5}));
  EXPECT_EQ(c.output.probes.size(), 1u);
  EXPECT_EQ(c.output.fields, (std::vector<std::string>{"displacement", "beta"}));  // damage: beta's old name
  EXPECT_EQ(c.output.encoding.compression, VtuCompression::zlib);
  // The φ formula sees the point state.
  PointState s;
  s.sigma = SymTensor{{3, -1, 0, 0, 0, 2}};  // |σ|_VM = 5
  s.beta = 0.5;
  EXPECT_NEAR(p.source->rate(s), -0.025, 1e-15);
  // Perzyna's E defaults to the elastic E.
  EXPECT_NE(p.law->describe().find("E = 100"), std::string::npos) << p.law->describe();
}

TEST(CaseFile, OverridesApplyBeforeValidation) {
  const Case c = parse_case(kValid, "ok.toml", ".", {.sets = {"damage.kappa=2", "mesh.cells=[20, 10]", "case.name=renamed"}});
  EXPECT_DOUBLE_EQ(c.problem->kappa, 2.0);
  EXPECT_EQ(c.problem->mesh.n_cells(), 2 * 20 * 10);
  EXPECT_EQ(c.name, "renamed");
  EXPECT_NE(error_of(kValid, {"damage.kappa"}).find("expected key=value"), std::string::npos);
  EXPECT_NE(error_of(kValid, {"damage.kappa=-1"}).find("--set damage.kappa=-1: kappa must be >= 0 (got -1)"),
            std::string::npos)
      << error_of(kValid, {"damage.kappa=-1"});
}

// Issue 11, item 11: a --set of a key that excludes one of the file's replaces it.
TEST(CaseFile, OverridesReplaceTheKeysTheyExclude) {
  // The file gives dt = 0.05 (10 steps) and output times.
  Case c = parse_case(kValid, "ok.toml", ".", {.sets = {"time.steps=20", "output.every=2"}});
  EXPECT_EQ(c.problem->n_steps, 20);
  EXPECT_EQ(c.output.every, 2);
  EXPECT_TRUE(c.output.times.empty());
  const std::string with_steps = variant("dt = 0.05", "steps = 10");
  const std::string with_every = variant("times = [0.1, 0.5]", "every = 3");
  c = parse_case(with_every, "ok.toml", ".", {.sets = {"time.dt=0.1", "output.times=[0.2]"}});
  EXPECT_EQ(c.problem->n_steps, 5);
  EXPECT_EQ(c.output.times, (std::vector<double>{0.2}));
  c = parse_case(with_steps, "ok.toml", ".", {.sets = {"time.dt=0.25"}});
  EXPECT_EQ(c.problem->n_steps, 2);
  // phi replaces a named source and its parameters; a source replaces phi.
  const std::string with_source = variant("phi = \"-0.01*vm*beta\"", "source = \"von-mises\"\nc = 0.5");
  c = parse_case(with_source, "ok.toml", ".", {.sets = {"damage.phi=-vm"}});
  EXPECT_NE(c.problem->source->describe().find("vm"), std::string::npos) << c.problem->source->describe();
  c = parse_case(kValid, "ok.toml", ".", {.sets = {"damage.source=zero"}});
  EXPECT_EQ(c.problem->source->describe().find("vm"), std::string::npos) << c.problem->source->describe();
  // Two overrides that exclude each other: an error naming both.
  EXPECT_NE(error_of(kValid, {"time.steps=10", "time.dt=0.1"}).find("--set time.dt=0.1: conflicts with --set time.steps=10"),
            std::string::npos)
      << error_of(kValid, {"time.steps=10", "time.dt=0.1"});
}

// Issue 26 item 18: an inline table merges into the section (it replaced the whole
// table: the damage source became zero); a line break in a value is refused (the rest
// was dropped); a new law drops the old law's parameters; [[obstacle]]-like arrays of
// tables are indexed.
TEST(CaseFile, SetMergesTablesAndIndexesArraysOfTables) {
  Case c = parse_case(kValid, "ok.toml", ".", {.sets = {"damage={kappa=0.25}"}});
  EXPECT_DOUBLE_EQ(c.problem->kappa, 0.25);
  EXPECT_NE(c.problem->source->describe().find("vm"), std::string::npos) << c.problem->source->describe();
  c = parse_case(kValid, "ok.toml", ".", {.sets = {"time={T=1.0, dt=0.25}"}});
  EXPECT_EQ(c.problem->n_steps, 4);
  EXPECT_EQ(error_of(kValid, {"damage.kappa=0.5\nphi = \"0\""}),
            "--set damage.kappa=0.5\\nphi = \"0\": the value holds a line break; give one value, on one line");
  // perzyna-von-mises (lambda, sigma_y) to elastic, and to maxwell-damage (its own parameter).
  c = parse_case(kValid, "ok.toml", ".", {.sets = {"viscoplasticity.law=elastic"}});
  EXPECT_NE(c.problem->law->describe().find("elastic"), std::string::npos) << c.problem->law->describe();
  c = parse_case(kValid, "ok.toml", ".", {.sets = {"viscoplasticity.law=perzyna"}});  // shares lambda and sigma_y
  EXPECT_NE(c.problem->law->describe().find("10"), std::string::npos) << c.problem->law->describe();
  EXPECT_NE(error_of(kValid, {"viscoplasticity.lambda=2", "viscoplasticity.law=elastic"})
                .find("--set viscoplasticity.law=elastic: conflicts with --set viscoplasticity.lambda=2"),
            std::string::npos);
  // The i-th table of [[mesh.part]] (and [[obstacle]], [[material]], ...).
  c = parse_case(kValid, "ok.toml", ".", {.sets = {"mesh.part[0].where=\"abs(y) < 1e-9\""}});
  EXPECT_EQ(c.problem->mesh.part_size("patch"), 10);
  EXPECT_EQ(error_of(kValid, {"mesh.part[1].name=x"}), "--set mesh.part[1].name=x: the case has 1 [[mesh.part]] table (part[0])");
  EXPECT_EQ(error_of(kValid, {"mesh.part[0].nme=x"}), "--set mesh.part[0].nme=x: unknown key 'nme' in [mesh.part[0]]; did you mean 'name'?");
  EXPECT_EQ(error_of(kValid, {"mesh.part[0]=1"}), "--set mesh.part[0]=1: give a key of the indexed table, e.g. mesh.part[0].radius");
  EXPECT_EQ(error_of(kValid, {"mesh.part[a].name=x"}),
            "--set mesh.part[a].name=x: expected a key part such as obstacle or obstacle[0], got 'part[a]'");
  EXPECT_EQ(error_of(kValid, {"damage[0].c=1"}),
            "--set damage[0].c=1: 'damage' is not an array of tables ([[damage]]) in the case file");
}

// Issue 26 item 16: case.name names output/<name>; "../../escaped" wrote outside output/.
TEST(CaseFile, CaseNameIsOneSafePathComponent) {
  for (const char* name : {"../../escaped", "/tmp/x", ".", "..", "a b", "x\x1b[31m"}) {
    const std::string set = std::string("case.name=\"") + name + "\"";
    EXPECT_NE(error_of(kValid, {set}).find(": expected a name of at most 100 letters, digits, '-', '_' and '.' (not '.' or "
                                           "'..'; it names the output directory output/<name>), got '"),
              std::string::npos)
        << error_of(kValid, {set});
    try {
      case_info(kValid, "ok.toml", {.sets = {set}});
      ADD_FAILURE() << "case_info took " << name;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("--set case.name="), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(error_of(variant("name = \"small\"", "name = \"../up\"")),
            "bad.toml:3:8: case.name: expected a name of at most 100 letters, digits, '-', '_' and '.' (not '.' or '..'; "
            "it names the output directory output/<name>), got '../up'");
  EXPECT_EQ(parse_case(kValid, "ok.toml", ".", {.sets = {"case.name=run-2_b.1"}}).name, "run-2_b.1");
}

// Issue 26 item 17: user text echoed in a message is bounded and has no control characters.
TEST(CaseFile, EchoedTextIsBoundedAndPrintable) {
  const std::string long_name(300000, 'x');
  std::string m = error_of(variant("kind = \"plane-strain\"", "kind = \"" + long_name + "\""));
  EXPECT_LT(m.size(), 400u) << m.size();
  EXPECT_NE(m.find("xxx…' (300000 characters); expected one of"), std::string::npos) << m.substr(0, 400);
  m = error_of(variant("f0 = [\"0\", \"-5*t\"]", "f0 = [\"0\", \"-5*t+" + std::string(1000000, '(') + "\"]"));
  EXPECT_LT(m.size(), 600u) << m.size();
  EXPECT_NE(m.find("(1000005 characters)"), std::string::npos) << m.substr(0, 600);
  m = error_of(variant("kind = \"plane-strain\"", "kind = \"plane\\u001b[2J\\u0007\""));
  EXPECT_EQ(m.find('\x1b'), std::string::npos);
  EXPECT_EQ(m.find('\x07'), std::string::npos);
  EXPECT_NE(m.find("unknown value 'plane\\x1b[2J\\x07'"), std::string::npos) << m;
  m = error_of(kValid, {"damage.kappa" + std::string(5000, 'k') + "=1"});
  EXPECT_LT(m.size(), 800u) << m.size();
}

// `--n` (MeshRequest::cells) on a case that reads a mesh file says so.
TEST(CaseFile, CellsOfTheCommandLineApplyToGeneratedMeshesOnly) {
  Case c = parse_case(kValid, "ok.toml", ".", {}, {.cells = 4});
  EXPECT_EQ(c.problem->mesh.n_cells(), 2 * 4 * 4);
  const std::string with_file = variant("generator = \"rectangle\"\nlower = [0.0, 0.0]\nupper = [2.0, 1.0]\ncells = [10, 5]",
                                        "file = \"plate.msh\"");
  try {
    parse_case(with_file, "plate.toml", ".", {}, {.cells = 4});
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("--n 4: --n sets the cells per edge of a generated mesh only; plate.toml reads "
                                         "its mesh from 'plate.msh'"),
              std::string::npos)
        << e.what();
  }
}

TEST(CaseFile, CaseInfoWithoutBuildingAnything) {
  const CaseInfo info = case_info(variant("[output]", "[output]\ndirectory = \"out/x\""), "dir/ok.toml", {.sets = {"case.name=n2"}});
  EXPECT_EQ(info.name, "n2");
  EXPECT_EQ(info.description, "case file dir/ok.toml");
  EXPECT_EQ(info.output_directory, "out/x");
  EXPECT_EQ(case_info("not [toml", "dir/bad.toml").name, "bad");
}

// A rank > 0 of a distributed run builds the case without its mesh (MeshRequest):
// the mesh file is not even opened, the rest is the same as rank 0's.
TEST(CaseFile, WithoutTheMeshForRanksThatReceiveTheirPart) {
  const std::string no_file = variant("generator = \"rectangle\"\nlower = [0.0, 0.0]\nupper = [2.0, 1.0]\ncells = [10, 5]",
                                      "file = \"no_such_mesh.msh\"");
  EXPECT_THROW(parse_case(no_file, "ok.toml", "."), Error);  // rank 0 reads it: the file is missing
  MeshRequest request;
  request.build = false;
  request.dim = 2;
  const Case c = parse_case(no_file, "ok.toml", ".", {}, request);
  const Case full = parse_case(kValid, "ok.toml", ".");
  EXPECT_EQ(c.problem->mesh.dim(), 2);
  EXPECT_EQ(c.problem->mesh.n_nodes(), 0);
  EXPECT_EQ(c.problem->contact.parts, full.problem->contact.parts);
  EXPECT_EQ(c.problem->clamped, full.problem->clamped);
  EXPECT_EQ(c.problem->n_steps, full.problem->n_steps);
  EXPECT_EQ(c.problem->law->describe(), full.problem->law->describe());
  EXPECT_NEAR(c.problem->contact.gap({1.5, 0, 0}, 0), 0.0015, 1e-15);
  // The built-in cases likewise.
  const Case b = load_case("paper-2d", {}, {.build = false, .dim = 2, .cells = 20});
  EXPECT_EQ(b.problem->mesh.dim(), 2);
  EXPECT_EQ(b.problem->mesh.n_cells(), 0);
}

TEST(CaseFile, ExpressionsEvaluateAndReportErrors) {
  const Expression e("sin(pi*x/2) + t^2 + (y > 0.5 ? 1 : 0)", Expression::Kind::SpaceTime, "here");
  EXPECT_NEAR(e({1, 1, 0}, 3), 1 + 9 + 1, 1e-14);
  EXPECT_NEAR(e({1, 0, 0}, 0), 1, 1e-14);
  try {
    Expression bad("2*w", Expression::Kind::Space, "case.toml:3:5: contact.gap");
    FAIL();
  } catch (const Error& err) {
    const std::string m = err.what();
    EXPECT_NE(m.find("case.toml:3:5: contact.gap: invalid expression \"2*w\""), std::string::npos) << m;
    EXPECT_NE(m.find("Available variables: x, y, z"), std::string::npos) << m;
  }
  EXPECT_TRUE(e.uses_position());
  EXPECT_FALSE(Expression("-10*t + pi", Expression::Kind::SpaceTime, "w").uses_position());
  EXPECT_TRUE(Expression("0*z", Expression::Kind::SpaceTime, "w").uses_position());
  EXPECT_THROW(Expression("x +* 2", Expression::Kind::Space, "w"), Error);
  EXPECT_THROW(Expression("t", Expression::Kind::Space, "w"), Error);  // no t in a space-only formula
  const Expression phi("-eps_eq + tr_sigma + tr_eps + beta", Expression::Kind::PointState, "w");
  SymTensor eps{{0.1, -0.1, 0, 0, 0, 0}};
  // eps_eq = sqrt(2/3 dev ε : dev ε) = sqrt(2/3 · 0.02) for this deviatoric ε
  EXPECT_NEAR(phi({0, 0, 0}, 0, SymTensor{{1, 1, 0, 0, 0, 0}}, eps, 0.5), -std::sqrt(2.0 / 3 * 0.02) + 2 + 0 + 0.5,
              1e-14);
}

struct BadCase {
  std::string from, to, message;
};

TEST(CaseFile, BadCaseFilesGiveTheirMessages) {
  const std::vector<BadCase> table = {
      {"kappa = 0.5", "kapa = 0.5", "bad.toml:30:1: unknown key 'kapa' in [damage]; did you mean 'kappa'?"},
      {"[damage]", "[damge]", "unknown key 'damge' (a section); did you mean 'damage'?"},
      {"kind = \"plane-strain\"", "kind = \"plane-strian\"",
       "bad.toml:20:8: elasticity.kind: unknown value 'plane-strian'; expected one of: 1d, plane-stress, "
       "plane-strain, isotropic; did you mean 'plane-strain'?"},
      {"E = 100.0", "E = \"hundred\"", "bad.toml:21:5: elasticity.E: expected a number, got a string"},
      {"E = 100.0", "E = -100.0", "Young's modulus E must be > 0"},
      {"cells = [10, 5]", "cells = [10]", "bad.toml:9:9: mesh.cells: expected an array of 2 numbers"},
      {"cells = [10, 5]", "cells = [10, 0]", "mesh.cells: expected between 1 and 100000 cells"},
      {"generator = \"rectangle\"", "generator = \"square\"", "mesh.generator: unknown value 'square'"},
      {"contact = [\"patch\"]", "contact = [\"botom\"]",
       "boundary.contact: boundary part 'botom' does not exist in the mesh (or has no facets); the mesh has: "},
      {"clamped = [\"top\"]\n", "", "missing key 'boundary.clamped'"},
      {"where = \"abs(y) < 1e-9 && x > 0.6 && x < 1.4\"", "where = \"abs(y) < 1e-9 && x > 5\"",
       "selects no boundary facet"},
      {"f0 = [\"0\", \"-5*t\"]", "f0 = [\"0\"]", "loads.f0: expected an array of 2 formulas (one per component), got 1"},
      {"f0 = [\"0\", \"-5*t\"]", "f0 = [\"0\", \"-5*T\"]",
       "bad.toml:35:12: loads.f0[1]: invalid expression \"-5*T\": Unexpected token \"T\""},
      {"gap = \"0.001*x\"", "gap = \"0.001*vm\"", "contact.gap: invalid expression"},
      {"gap = \"0.001*x\"", "gap = \"-0.001*x\"", "contact.gap: the gap g must be >= 0"},
      {"gap = \"0.001*x\"", "gap = \"sqrt(x - 10)\"", "contact.gap: the gap g is not finite"},
      {"direction = [0, -1]", "direction = [0, 0]", "contact.direction: expected a non-zero vector"},
      {"direction = [0, -1]", "direction = \"up\"", "contact.direction: unknown value 'up'; expected one of: normal"},
      {"dt = 0.05", "dt = 0.03", "bad.toml:43:6: time.dt: the time step 0.03 does not divide the final time T = 0.5 into whole steps"},
      {"dt = 0.05", "dt = -0.05", "time.dt: the time step must be > 0 (got -0.05)"},
      {"dt = 0.05", "steps = 0", "time.steps: the number of time steps must be >= 1 (got 0)"},
      {"dt = 0.05", "dt = 0.05\nsteps = 10", "give exactly one of steps, dt (a step size, a list or a formula in t) and tolerance"},
      {"T = 0.5", "T = 0", "time.T: the final time T must be > 0 (got 0)"},
      {"kappa = 0.5", "kappa = -0.5", "damage.kappa: kappa must be >= 0 (got -0.5)"},
      {"beta0 = \"1 - 0.1*x/2\"", "beta0 = \"1.5\"", "damage.beta0: initial damage beta0 must lie in [0, 1]; it is 1.5 at node 0"},
      {"phi = \"-0.01*vm*beta\"", "phi = \"-0.01*vm*beta\"\nsource = \"von-mises\"", "give either source"},
      {"law = \"perzyna-von-mises\"", "law = \"perzina\"", "did you mean 'perzyna'?"},
      {"lambda = 10.0", "lamda = 10.0", "viscoplasticity.lamda: unknown key or parameter of the viscoplastic law "
                                        "'perzyna-von-mises'; did you mean 'lambda'?; its parameters are: E, lambda, sigma_y"},
      {"lambda = 10.0", "lambda = -10.0", "viscosity lambda must be > 0"},
      {"times = [0.1, 0.5]", "times = [0.1, 0.9]", "output time 0.9 is outside [0, T = 0.5]"},
      {"fields = [\"displacement\", \"damage\"]", "fields = [\"displacment\"]", "did you mean 'displacement'?"},
      {"probes = [[1.0, 0.0]]", "probes = [[1.0]]", "expected each probe to be an array of 2 numbers"},
      {"[output]", "[output]\nevery = 2", "give either every or times"},
      {"[output]", "[output]\ncompression = \"gzip\"", "output.compression: unknown value 'gzip'; expected one of: zlib, none"},
      {"upper = [2.0, 1.0]", "upper = [2.0, 1.0", "bad.toml:9:1: invalid TOML: Error while parsing array"},
      {"[case]", "[case]\n[case]", "invalid TOML"},
      // Issue 48: a component prescribed twice names both tables (the later first), a pressure on a
      // contact part its table, a friction field on a frictionless case the key.
      {"clamped = [\"top\"]\ncontact = [\"patch\"]\n",
       "contact = [\"patch\"]\n\n[[boundary.displacement]]\nparts = [\"top\"]\nux = 0\nuy = \"-0.02*t\"\n\n"
       "[[boundary.displacement]]\nparts = [\"right\"]\nuy = 0\n",
       "bad.toml:23:1: boundary.displacement[1]: uy at node 65 (2, 1, 0) is prescribed twice with different values at "
       "t = 0.5: -0.01 by [[boundary.displacement]] 1 (parts top) at bad.toml:18:1: boundary.displacement[0], and 0 by "
       "[[boundary.displacement]] 2 (parts right) at bad.toml:23:1: boundary.displacement[1]; restrict one of the parts"},
      {"f0 = [\"0\", \"-5*t\"]", "f0 = [\"0\", \"-5*t\"]\n\n[[loads.pressure]]\nparts = [\"patch\"]\np = 1",
       "bad.toml:37:1: loads.pressure[0]: pressure part 'patch' is a contact part; a pressure acts on Γ2 only"},
      {"fields = [\"displacement\", \"damage\"]", "fields = [\"slip\"]",
       "bad.toml:48:10: output.fields: the field 'slip' is written only for frictional cases (a friction law or wear "
       "in [contact], a [[contact.part]] or a [[contact.pair]]); this case is frictionless"},
  };
  for (const auto& b : table) {
    const std::string msg = error_of(variant(b.from, b.to));
    EXPECT_NE(msg.find(b.message), std::string::npos) << "case: " << b.to << "\nexpected: " << b.message
                                                      << "\ngot:      " << msg;
  }
}

// Issue 48: [output] fields names only arrays the case's VTU files can hold (VTU files with no
// array were written for "slip" on a frictionless case): each friction field and contact_lambda
// are refused without friction, gap without pairs, each at the key; all are accepted with friction.
TEST(CaseFile, OutputFieldsTheFilesWouldNeverHoldAreRefused) {
  for (const StateField& f : state_fields()) {
    if (f.vtu.empty()) continue;
    const std::string fields = fmt::format("fields = [\"{}\"]", f.vtu);
    const std::string m = error_of(variant("fields = [\"displacement\", \"damage\"]", fields));
    const bool refused = f.friction || f.vtu == "contact_lambda" || f.vtu == "gap";
    if (!refused) {
      EXPECT_EQ(m, "(no error)") << f.vtu;
      continue;
    }
    EXPECT_TRUE(m.starts_with("bad.toml:48:10: output.fields: the field")) << m;
    EXPECT_NE(m.find(f.vtu == "gap" ? "only for cases with contact pairs" : "frictional cases"),
              std::string::npos)
        << m;
    // With friction (Coulomb on Γ3) all but gap are written, and accepted.
    const std::string frictional =
        test::replaced(variant("fields = [\"displacement\", \"damage\"]", fields), "direction = [0, -1]",
                       "direction = [0, -1]\nfriction = \"coulomb\"\nmu = 0.3");
    EXPECT_EQ(error_of(frictional) == "(no error)", f.vtu != "gap") << f.vtu << ": " << error_of(frictional);
  }
}

TEST(CaseFile, MeshFileErrorsNameThePath) {
  const std::string msg = error_of(variant("generator = \"rectangle\"\nlower = [0.0, 0.0]\nupper = [2.0, 1.0]\ncells = [10, 5]",
                                           "file = \"no/such/mesh.msh\""));
  EXPECT_NE(msg.find("mesh.file"), std::string::npos) << msg;
  EXPECT_NE(msg.find("no/such/mesh.msh"), std::string::npos) << msg;
}

/// The built-in cases are the shipped case files: the command-line options are
/// overrides of their keys, checked as the file's values, with the option named.
TEST(CaseFile, CommandLineOptionsAreKeyOverrides) {
  const Case a = load_case("paper-2d", {.kappa = 0.5, .steps = 20}, {.cells = 10});
  const Case b = load_case("paper-2d", {.sets = {"damage.kappa=0.5", "time.steps=20", "mesh.cells=10"}});
  EXPECT_EQ(a.problem->kappa, 0.5);
  EXPECT_EQ(a.problem->n_steps, 20);
  EXPECT_EQ(a.problem->mesh.n_cells(), 2 * 10 * 10);
  EXPECT_EQ(a.problem->mesh.nodes(), b.problem->mesh.nodes());
  EXPECT_EQ(a.output.every, 2);  // every tenth of the run, after the override
  EXPECT_EQ(load_case("paper-1d", {.time_step = 0.02}).problem->n_steps, 50);
  const auto message = [](const CaseOverrides& o, const MeshRequest& m = {}) {
    try {
      load_case("paper-2d", o, m);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  const std::vector<std::pair<std::string, std::string>> table = {
      {message({}, {.cells = 12}), "--n 12: the number of cells per edge n must be a multiple of 5 (so that x = 0.8 "
                                   "and 1.2 are nodes); got 12"},
      {message({.sets = {"mesh.cells=[20, 12]"}}), "--set mesh.cells=[20, 12]: the number of cells per edge n must be "
                                                   "a multiple of 5"},
      {message({.kappa = -1.0}), "--kappa -1: kappa must be >= 0 (got -1)"},
      {message({.steps = 0}), "--steps 0: the number of time steps must be >= 1 (got 0)"},
      {message({.time_step = -0.01}), "--dt -0.01: the time step must be > 0 (got -0.01)"},
      {message({.time_step = 0.03}), "--dt 0.03: the time step 0.03 does not divide the final time T = 1"},
      {message({.sets = {"time.dt=0.1"}, .steps = 5}), "--steps 5: conflicts with --set time.dt=0.1"},
      {message({}, {.cells = 100000}), "--n 100000: the mesh would have"},
      {message({}, {.cells = 0}), "--n 0: expected between 1 and 100000 cells per direction, got 0"},
      {message({}, {.cells = -3}), "--n -3: expected between 1 and 100000 cells per direction, got -3"},
      {message({.sets = {"mesh.file=x.msh"}}, {.cells = 10}), "--n 10: --n sets the cells per edge of a generated mesh only"},
  };
  for (const auto& [got, expected] : table) EXPECT_NE(got.find(expected), std::string::npos) << got;
}

}  // namespace
}  // namespace vpc
