// Issue 51: mesh adaptivity during a run (adapt/). The state is carried over a refinement exactly (u and
// β at the old nodes bit for bit, ε of the carried u equal to the inherited ε, ∫σ and Σλ kept), a
// refinement undone by coarsening gives the state back, marking is Dörfler's, the indicator vanishes on
// what P1/P0 represent exactly, and an adaptive run (a cylinder rolled along a block) refines ahead of it
// and coarsens behind it, every step within the tolerances, its files saying so.
#include "adapt/indicator.hpp"
#include "adapt/marking.hpp"
#include "adapt/mesh_adaptivity.hpp"
#include "adapt/state_transfer.hpp"
#include "cases/builtin_cases.hpp"
#include "fem/assembly.hpp"
#include "fem/cell_geometry.hpp"
#include "mesh/generators.hpp"
#include "run/run_case.hpp"
#include "test_laws.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>
#include <sstream>

namespace vpc {
namespace {

namespace fs = std::filesystem;

/// paper-2d on a 10 × 10 mesh after `steps` steps (of 20): stress, history z and damage all non-zero.
std::unique_ptr<TimeStepper> paper_after(int steps) {
  const Case c = load_case("paper-2d", {.steps = 20}, {.cells = 10});
  auto s = std::make_unique<TimeStepper>(c.problem, c.solvers);
  for (int n = 0; n < steps; ++n) EXPECT_TRUE(s->step().ok);
  return s;
}

double max_abs(const std::vector<SymTensor>& t) {
  double m = 0;
  for (const SymTensor& x : t)
    for (double v : x.c) m = std::max(m, std::abs(v));
  return m;
}

SymTensor integral(const Mesh& mesh, const std::vector<SymTensor>& t) {
  const std::vector<CellGeometry> geo = compute_geometry(mesh);
  SymTensor sum;
  for (int c = 0; c < mesh.n_cells(); ++c) sum += geo[static_cast<std::size_t>(c)].volume * t[static_cast<std::size_t>(c)];
  return sum;
}

/// ironing-3d (the paper's damaging material, Coulomb friction) on a 12 × 6 × 3 box after `steps` steps (of
/// 50): pressed in and dragged, with stress, z, damage, contact forces and slip.
std::unique_ptr<TimeStepper> ironing_3d_after(int steps) {
  const Case c = load_case("ironing-3d", {.sets = {"mesh.cells=[12, 6, 3]"}, .steps = 50});
  auto s = std::make_unique<TimeStepper>(c.problem, c.solvers);
  for (int n = 0; n < steps; ++n) EXPECT_TRUE(s->step().ok);
  return s;
}

/// What one refinement (and four more, until Γ3's facets are bisected) of `s` carries: exactly (2D and 3D).
void expect_refinement_carries_the_state_exactly(const std::unique_ptr<TimeStepper>& s) {
  AdaptSpec spec;
  spec.coarsen_fraction = 0;
  spec.where = "test: [adapt]";
  MeshAdaptivity a(std::make_shared<Problem>(s->problem()), s->solvers(), spec);
  const State& old = s->state();
  auto next = a.adapt(*s, 0, old, s->times(), s->step_control_state());
  ASSERT_TRUE(next);
  const State& now = next->state();
  ASSERT_GT(next->mesh().n_cells(), s->mesh().n_cells());
  EXPECT_EQ(now.n, old.n);
  EXPECT_EQ(now.t, old.t);
  // The coarse nodes keep their numbers: u and β there bit for bit.
  EXPECT_EQ(now.u.head(old.u.size()), old.u);
  EXPECT_EQ(now.beta.head(old.beta.size()), old.beta);
  // ε of the carried u on the new cells is the inherited ε (the parent's), σ = ℰε + z on every cell.
  std::vector<SymTensor> eps(static_cast<std::size_t>(next->mesh().n_cells()));
  compute_strain(next->mesh(), compute_geometry(next->mesh()), now.u, eps);
  const double scale = max_abs(now.eps);
  ASSERT_GT(scale, 0);
  for (std::size_t c = 0; c < eps.size(); ++c)
    for (int i = 0; i < 6; ++i) EXPECT_NEAR(eps[c][i], now.eps[c][i], 1e-12 * scale) << "cell " << c;
  const Elasticity& e = next->problem().elasticity;
  for (std::size_t c = 0; c < eps.size(); ++c)
    for (int i = 0; i < 6; ++i)
      EXPECT_NEAR((e.apply(now.eps[c]) + now.z[c])[i], now.sigma[c][i], 1e-12 * max_abs(now.sigma));
  // ∫σ, ∫z and the total contact force kept.
  const SymTensor s0 = integral(s->mesh(), old.sigma), s1 = integral(next->mesh(), now.sigma);
  const SymTensor z0 = integral(s->mesh(), old.z), z1 = integral(next->mesh(), now.z);
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(s0[i], s1[i], 1e-13 * max_abs(old.sigma) * 4);
    EXPECT_NEAR(z0[i], z1[i], 1e-13 * max_abs(old.z) * 4);
  }
  ASSERT_GT(old.lambda.sum(), 0);
  EXPECT_NEAR(now.lambda.sum(), old.lambda.sum(), 1e-13 * old.lambda.sum());
  ASSERT_EQ(a.log().size(), 1u);
  EXPECT_EQ(a.log()[0].cells_after, next->mesh().n_cells());
  // the generator's right triangles, bisected (2D), and its cubes' six tetrahedra (3D: dihedral angles)
  EXPECT_NEAR(a.log()[0].min_angle_degrees, 45, 1e-9);
  // Again, until Γ3's facets are bisected (a boundary facet is a refinement edge every other level): the
  // new contact nodes take the pressure of their facet, the total force kept.
  std::unique_ptr<TimeStepper> last = std::move(next);
  for (int k = 0; k < 4 && last->contact().nodes.size() == s->contact().nodes.size(); ++k) {
    auto again = a.adapt(*last, 0, last->state(), last->times(), last->step_control_state());
    ASSERT_TRUE(again);
    EXPECT_NEAR(again->state().lambda.sum(), old.lambda.sum(), 1e-13 * old.lambda.sum());
    last = std::move(again);
  }
  EXPECT_GT(last->contact().nodes.size(), s->contact().nodes.size());
  // The run goes on from it, within its tolerances.
  EXPECT_TRUE(last->step().ok);
}

TEST(Adapt, RefinementCarriesTheStateExactly) { expect_refinement_carries_the_state_exactly(paper_after(5)); }

TEST(Adapt, RefinementCarriesTheStateExactlyIn3D) {
  const auto s = ironing_3d_after(14);
  ASSERT_GT(s->state().lambda.sum(), 0);
  expect_refinement_carries_the_state_exactly(s);
}

/// A refinement of `s` (every cell twice) undone by coarsening gives its state back (2D and 3D).
void expect_coarsening_gives_the_state_back(const std::unique_ptr<TimeStepper>& s) {
  const Problem& p = s->problem();
  const auto d = static_cast<std::size_t>(p.mesh.dim());
  BisectionForest forest(p.mesh);
  const ForestState before = gather_state(forest, *s, s->state());
  ForestState fs = before;
  for (int level = 0; level < 2; ++level) {  // every cell bisected twice (and what the closure adds)
    forest.refine(forest.leaves());
    carry_through_refinement(forest, fs);
  }
  ASSERT_GT(fs.leaves.size(), 3 * before.leaves.size());
  const std::vector<Material> materials = p.material_list();
  std::vector<const Elasticity*> elasticity(static_cast<std::size_t>(p.mesh.n_cells()));
  for (int c = 0; c < p.mesh.n_cells(); ++c)
    elasticity[static_cast<std::size_t>(c)] = &materials[static_cast<std::size_t>(s->part().cell_material[static_cast<std::size_t>(c)])].elasticity;
  for (int round = 0; round < 4 && forest.coarsen(forest.leaves()) > 0; ++round)
    carry_through_coarsening(forest, elasticity, fs);
  ASSERT_EQ(fs.leaves, before.leaves);  // back to the coarse mesh
  const std::size_t nodes = before.beta.size();
  for (std::size_t i = 0; i < nodes; ++i) {
    EXPECT_EQ(fs.beta[i], before.beta[i]);
    for (std::size_t j = 0; j < d; ++j) EXPECT_EQ(fs.u[d * i + j], before.u[d * i + j]);
  }
  auto expect_near = [](const std::vector<double>& x, const std::vector<double>& y, const char* what) {
    ASSERT_EQ(x.size(), y.size()) << what;
    double scale = 0;
    for (double v : y) scale = std::max(scale, std::abs(v));
    for (std::size_t k = 0; k < x.size(); ++k) EXPECT_NEAR(x[k], y[k], 1e-12 * scale) << what << " entry " << k;
  };
  expect_near(fs.z, before.z, "z");
  expect_near(fs.eps, before.eps, "eps");
  expect_near(fs.sigma, before.sigma, "sigma");
  // The contact fields: the coarse rows' pressure back.
  for (std::size_t k = 0; k < before.contact.size(); ++k)
    if (!std::isnan(before.contact[k])) {
      EXPECT_EQ(fs.contact[k], before.contact[k]);
    }
}

TEST(Adapt, CoarseningUndoesARefinementAndGivesTheStateBack) { expect_coarsening_gives_the_state_back(paper_after(5)); }

TEST(Adapt, CoarseningUndoesARefinementAndGivesTheStateBackIn3D) {
  expect_coarsening_gives_the_state_back(ironing_3d_after(14));
}

TEST(Adapt, BulkMarkingTakesTheFewestLargestCells) {
  EXPECT_EQ(bulk_marking({1, 4, 2, 3}, 0.5), (std::vector<int>{1, 3}));  // 4 + 3 ≥ 5
  EXPECT_EQ(bulk_marking({1, 4, 2, 3}, 1.0), (std::vector<int>{1, 3, 2, 0}));
  // Cells tied with the last one marked are marked too (to 1e-9: round-off orders equal values by engine).
  EXPECT_EQ(bulk_marking({2, 2, 2, 2}, 0.5), (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(bulk_marking({3, 2, 2 + 1e-12, 1}, 0.5), (std::vector<int>{0, 2, 1}));
  EXPECT_EQ(bulk_marking({3, 2, 2 + 1e-6, 1}, 0.5), (std::vector<int>{0, 2}));
  const std::vector<double> stress{9, 1, 0, 0}, contact{0, 0, 1, 5};
  EXPECT_EQ(bulk_marking_each({&stress, &contact}, 0.5),
            (std::vector<int>{0, 3}));  // each part's own bulk
  EXPECT_TRUE(bulk_marking({0, 0, 0}, 0.5).empty());
  EXPECT_EQ(smallest_share({1, 4, 2, 3}, 0.3), (std::vector<int>{0, 2}));  // 1 + 2 ≤ 3
  EXPECT_TRUE(smallest_share({1, 4, 2, 3}, 0.05).empty());
}

TEST(Adapt, TheIndicatorSeesSurfacesAboutToTouch) {
  // Γ3 with no pressure yet: the contact part is zero, unless the forecast puts a node within h_F of its
  // obstacle at the next step; then the cells of that node's Γ3 facets, and only they.
  const Mesh mesh = make_rectangle({0, 0, 0}, {2, 1, 0}, 10, 5);
  std::vector<double> pressure(static_cast<std::size_t>(mesh.n_nodes()), NAN), approach = pressure;
  for (int i : mesh.nodes_of_parts({"bottom"})) pressure[static_cast<std::size_t>(i)] = 0;
  const std::vector<SymTensor> sigma(static_cast<std::size_t>(mesh.n_cells()));
  const Eigen::VectorXd beta = Eigen::VectorXd::Ones(mesh.n_nodes());
  AdaptSpec spec;
  CellIndicators ind = cell_indicators(mesh, sigma, beta, pressure, spec);
  for (double v : ind.contact) EXPECT_EQ(v, 0);
  for (int i : mesh.nodes_of_parts({"bottom"})) {
    const double x = mesh.node(i)[0];
    approach[static_cast<std::size_t>(i)] = x == 1.0 ? 0.01 : 0.5;  // the node at x = 1 only (h_F = 0.2)
  }
  ind = cell_indicators(mesh, sigma, beta, pressure, spec, approach);
  int flagged = 0;
  for (int f : mesh.facets_of_parts({"bottom"})) {
    const double x = mesh.facet_centroid(f)[0];
    const double eta = ind.contact[static_cast<std::size_t>(mesh.facet_cell(f))];
    if (std::abs(x - 1) < 0.15) {
      EXPECT_NEAR(eta, 0.2 * 0.2, 1e-15);  // h_F |F| p_ref², p_ref = 1 before any contact
      ++flagged;
    } else {
      EXPECT_EQ(eta, 0);
    }
  }
  EXPECT_EQ(flagged, 2);
}

TEST(Adapt, TheForecastLooksAheadToTheNextAdaptation) {
  // ironing-3d 2 steps into its drag: the sphere moves +x by half a cell a step. Adapting every 6 steps,
  // the facets the sphere comes within h_F of before the next adaptation are marked, not only the next
  // step's: more cells, every added one ahead of the sphere.
  const auto s = ironing_3d_after(12);
  AdaptSpec spec;
  spec.stress_weight = spec.damage_weight = 0;  // the contact part alone
  spec.where = "test: [adapt]";
  auto flagged = [&](int every) {
    spec.every = every;
    const MeshAdaptivity a(std::make_shared<Problem>(s->problem()), s->solvers(), spec);
    const std::vector<double> eta = a.indicator(*s);
    std::vector<int> cells;
    for (int c = 0; c < s->mesh().n_cells(); ++c)
      if (eta[static_cast<std::size_t>(c)] > 0) cells.push_back(c);
    return cells;
  };
  const std::vector<int> next = flagged(1), ahead = flagged(6);
  EXPECT_GT(next.size(), 0u);
  EXPECT_GT(ahead.size(), next.size());
  const double centre = -0.5 + 1.25 * (s->state().t - 0.2);  // the sphere's x now
  for (int c : ahead) {
    if (std::ranges::binary_search(next, c)) continue;
    EXPECT_GT(s->mesh().cell_centroid(c)[0], centre) << "cell " << c;
  }
}

TEST(Adapt, TheForecastZoneReachesItsFinalLevelInOneAdaptation) {
  // ironing-3d before its first step (nothing in contact, the sphere about to press): one adaptation takes
  // every cell of a Γ3 facet about to touch to max_level, marking the forest again as it refines (several
  // markings, one new stepper), and leaves a mesh the next adaptation keeps: coarsening does not take back
  // what the forecast would refine again.
  const auto s = ironing_3d_after(0);
  AdaptSpec spec;
  spec.max_level = 4;
  spec.where = "test: [adapt]";
  MeshAdaptivity a(std::make_shared<Problem>(s->problem()), s->solvers(), spec);
  auto next = a.adapt(*s, 0, s->state(), s->times(), s->step_control_state());
  ASSERT_TRUE(next);
  ASSERT_EQ(a.log().size(), 1u);
  EXPECT_GE(a.log()[0].forecast_passes, 2);
  EXPECT_EQ(a.log()[0].max_level, 4);
  // Before any contact the indicator is the forecast's alone: each of its cells at the final level.
  const std::vector<double> eta = a.indicator(*next);
  const std::vector<int> level = a.levels(*next);
  int forecast = 0;
  for (std::size_t c = 0; c < eta.size(); ++c) {
    if (eta[c] == 0) continue;
    ++forecast;
    EXPECT_EQ(level[c], 4) << "cell " << c;
  }
  EXPECT_GT(forecast, 0);
  EXPECT_FALSE(a.adapt(*next, 0, next->state(), next->times(), next->step_control_state()));
  // The run goes on from it, and its first step's contact is on the refined zone.
  EXPECT_TRUE(next->step().ok);
  EXPECT_GT(next->state().lambda.sum(), 0);
}

TEST(Adapt, TheIndicatorVanishesWhereP1AndP0AreExact) {
  const auto s = paper_after(1);
  Snapshot snap = s->snapshot();
  const Mesh& mesh = s->mesh();
  SymTensor uniform;
  uniform[0] = 3, uniform[1] = -2, uniform[5] = 1;
  for (SymTensor& x : snap.state.sigma) x = uniform;
  for (int i = 0; i < mesh.n_nodes(); ++i) snap.state.beta[i] = 0.9 - 0.1 * mesh.node(i)[0];  // linear
  AdaptSpec spec;
  const std::vector<double> off_contact(static_cast<std::size_t>(mesh.n_nodes()), NAN);
  CellIndicators ind = cell_indicators(mesh, snap.state.sigma, snap.state.beta, off_contact, spec);
  for (double v : ind.stress) EXPECT_LT(v, 1e-24);
  for (double v : ind.damage) EXPECT_LT(v, 1e-28);
  // A stress that jumps across x = 1: the cells beside the line, and only they.
  for (int c = 0; c < mesh.n_cells(); ++c)
    snap.state.sigma[static_cast<std::size_t>(c)] = mesh.cell_centroid(c)[0] < 1 ? uniform : 2.0 * uniform;
  ind = cell_indicators(mesh, snap.state.sigma, snap.state.beta, off_contact, spec);
  for (int c = 0; c < mesh.n_cells(); ++c) {
    bool touches = false;
    for (int a = 0; a < 3; ++a) touches = touches || std::abs(mesh.node(mesh.cell(c)[a])[0] - 1) < 1e-12;
    const double x = mesh.cell_centroid(c)[0];
    const bool beside = touches && std::abs(x - 1) < 0.1;  // an edge on the line (h = 0.2)
    if (!touches) {
      EXPECT_EQ(ind.stress[static_cast<std::size_t>(c)], 0) << "cell " << c;
    }
    if (beside && ind.stress[static_cast<std::size_t>(c)] == 0) {
      // a cell touching the line at a vertex only has no edge on it
      int on_line = 0;
      for (int a = 0; a < 3; ++a) on_line += std::abs(mesh.node(mesh.cell(c)[a])[0] - 1) < 1e-12;
      EXPECT_LT(on_line, 2) << "cell " << c;
    }
  }
  EXPECT_GT(ind.stress_relative, 0);
}

/// Runs the case `make` gives (quiet) into the fresh directory `out`, or with `resume` continues the run in
/// it from its newest good checkpoint; `checkpoint_every`: RunOptions's (−1: by wall time).
RunResult run_into(const fs::path& out, const std::function<Case(const MeshRequest&)>& make, bool resume = false,
                   int checkpoint_every = -1) {
  if (!resume) fs::remove_all(out);
  RunOptions o;
  o.quiet = true;
  o.output_directory = out;
  o.checkpoint_every = checkpoint_every;
  if (resume) o.resume = out;
  return run_case(
      [&](const MeshRequest& m) {
        Case c = make(m);
        c.output.directory = out;
        return c;
      },
      o);
}

/// The shipped ironing-2d (a cylinder pressed into a block and dragged along it, each step redone twice on
/// the mesh adapted from its solution) in 12 steps with `sets`, into a fresh directory; its summary.json.
nlohmann::json run_rolling(const fs::path& dir, std::vector<std::string> sets) {
  fs::remove_all(dir);
  fs::create_directories(dir);
  sets.push_back("adapt.max_level=5");
  const RunResult r = run_into(dir / "out", [&](const MeshRequest& m) {
    return load_case("ironing-2d", {.sets = sets, .steps = 12, .every = 4}, m);
  });
  EXPECT_EQ(r.steps, 12);
  std::ifstream in(dir / "out" / "summary.json");
  return nlohmann::json::parse(in);
}

TEST(Adapt, AStepThatFailsOnTheAdaptedMeshUndoesTheAdaptation) {
  // A friction law valid for contact nodes of |Γ3|_i >= 0.15 only (tests/support: a step ending with a
  // smaller node in contact is rejected whatever its length): ironing-2d's coarse Γ3 (h = 0.2) suits it, a
  // bisected contact facet does not. Every adaptation that refines the contact makes the next step (or the
  // redo pass) fail at its smallest step; the run undoes it and goes on with the mesh before, to the end.
  test::register_test_laws();
  const std::vector<std::string> sized = {"contact.friction=\"sized-coulomb\"", "contact.mu=0", "contact.min_measure=0.15"};
  for (const char* resolve : {"adapt.resolve=2", "adapt.resolve=0"}) {
    std::vector<std::string> sets = sized;
    sets.emplace_back(resolve);
    const fs::path dir = fs::temp_directory_path() / "vpc-adapt-undo";
    testing::internal::CaptureStderr();
    run_rolling(dir, sets);  // 12 steps, all accepted (asserted there)
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_NE(err.find("the adaptation is undone and the run goes on with the mesh before it"), std::string::npos) << resolve;
    if (std::string(resolve) == "adapt.resolve=0") continue;  // (its last adaptation, after the last step, stays)
    // With redo passes, the mesh the run ends on (made again from its last checkpoint's refinement history):
    // its contact facets never bisected (0.2 each).
    const Case c = load_case("ironing-2d", {.sets = sets});
    MeshAdaptivity a(c.problem, c.solvers, *c.adapt);
    std::ifstream in(dir / "out" / "checkpoint_00012.adaptations.bin");
    std::stringstream history;
    history << in.rdbuf();
    a.replay(history.str());
    const auto end = a.make_stepper();
    EXPECT_GE(end->mesh().n_cells(), c.problem->mesh.n_cells()) << resolve;
    double measure = INFINITY;
    for (int f : end->mesh().facets_of_parts({"bottom"})) measure = std::min(measure, end->mesh().facet_measure(f));
    EXPECT_NEAR(measure, 0.2, 1e-12) << resolve;
  }
}

TEST(Adapt, AStepRejectedRightAfterAnAdaptationIsRetriedOnTheAdaptedMesh) {
  // paper-2d (n = 10) with error-controlled steps, adapted every 2 steps: the step after an adaptation is
  // often rejected by the error control (the new mesh's first estimate) and redone shorter, on the adapted
  // mesh (its cells are the adaptation's), and the run reaches T with every step accepted.
  const fs::path dir = fs::temp_directory_path() / "vpc-adapt-rejected";
  const RunResult r = run_into(dir, [](const MeshRequest& m) {
    MeshRequest coarse = m;
    coarse.cells = 10;
    return load_case("paper-2d", {.sets = {"time.tolerance=1e-3", "adapt.every=2", "adapt.max_level=4"}}, coarse);
  });
  EXPECT_GT(r.steps, 20);
  std::ifstream in(dir / "history.csv");
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  for (std::stringstream ss(line); std::getline(ss, line, ',');) names.push_back(line);
  auto column = [&](const char* name) {
    return static_cast<std::size_t>(std::find(names.begin(), names.end(), name) - names.begin());
  };
  const std::size_t rejected = column("rejected"), adaptations = column("adaptations"), cells = column("cells"),
                    ok = column("ok");
  ASSERT_LT(std::max({rejected, adaptations, cells, ok}), names.size());
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    std::vector<double> row;
    for (std::stringstream ss(line); std::getline(ss, line, ',');) row.push_back(std::stod(line));
    rows.push_back(row);
  }
  int after_adaptation = 0;
  for (std::size_t n = 1; n < rows.size(); ++n) {
    EXPECT_EQ(rows[n][ok], 1) << "step " << n + 1;
    const bool adapted_before = rows[n - 1][adaptations] > (n >= 2 ? rows[n - 2][adaptations] : 0);
    if (rows[n][rejected] > 0 && adapted_before) {
      ++after_adaptation;
      EXPECT_EQ(rows[n][cells], rows[n - 1][cells]) << "step " << n + 1;  // on the adapted mesh
    }
  }
  std::printf("  %zu steps, %d rejected right after an adaptation\n", rows.size(), after_adaptation);
  EXPECT_GT(after_adaptation, 0);
}

TEST(Adapt, ARunRefinesAheadOfTheIndenterAndCoarsensBehindIt) {
  const fs::path dir = fs::temp_directory_path() / "vpc-adapt-rolling";
  const auto j = run_rolling(dir, {});
  const auto& log = j.at("adaptations");
  ASSERT_EQ(log.size(), 24u);  // two passes a step
  long long removed = 0;
  int deepest = 0;
  for (const auto& a : log) {
    removed += a.at("removed_nodes").get<long long>();
    deepest = std::max(deepest, a.at("max_level").get<int>());
    EXPECT_NEAR(a.at("min_angle_degrees").get<double>(), 45, 1e-9);
    for (const char* k : {"z", "sigma", "beta"}) EXPECT_LE(a.at("coarsening_change").at(k).get<double>(), 0.05 + 1e-12);
  }
  EXPECT_GT(removed, 0);
  EXPECT_GE(deepest, 3);
  // The fine zone moves with the cylinder rather than growing along its track: the mesh at the end is
  // hardly larger than the largest one before (the zone coarsened behind as it was refined ahead).
  long long peak = 0;
  for (const auto& a : log) peak = std::max(peak, a.at("cells_after").get<long long>());
  const long long last = log.back().at("cells_after").get<long long>();
  std::printf("  rolling: %lld nodes removed, deepest level %d, cells %lld at the end, %lld at most\n", removed, deepest,
              last, peak);
  // Without coarsening the refined cells pile up along the track.
  const auto kept = run_rolling(dir / "kept", {"adapt.coarsen_fraction=0"});
  const long long piled = kept.at("adaptations").back().at("cells_after").get<long long>();
  std::printf("  without coarsening: %lld cells at the end\n", piled);
  EXPECT_GT(last, 3200);
  EXPECT_LT(last - 3200, (piled - 3200) / 2);
  EXPECT_TRUE(j.at("checks").at("all_steps_ok").get<bool>()) << j.at("checks").dump();
  // history.csv ends with the mesh's columns; the VTU files carry the level and the indicator.
  std::ifstream h(dir / "out" / "history.csv");
  std::string header;
  std::getline(h, header);
  EXPECT_TRUE(header.ends_with(",cells,unknowns,adaptations")) << header;
  std::stringstream vtu;
  vtu << std::ifstream(dir / "out" / "solution_00012.vtu").rdbuf();
  EXPECT_NE(vtu.str().find("Name=\"level\""), std::string::npos);
  EXPECT_NE(vtu.str().find("Name=\"indicator\""), std::string::npos);
  fs::remove_all(dir);
}


std::string file_text(const fs::path& p) {
  std::stringstream text;
  text << std::ifstream(p, std::ios::binary).rdbuf();
  return text.str();
}

/// ironing-2d in 12 steps into `dir` (T = 0.5 and 6 steps where `half`), resumed from it where `resume`.
void run_ironing(const fs::path& dir, bool half, bool resume) {
  std::vector<std::string> sets = {"adapt.max_level=5"};
  if (half) sets.insert(sets.end(), {"time.T=0.5", "time.steps=6"});
  run_into(
      dir,
      [&](const MeshRequest& m) {
        return load_case("ironing-2d", {.sets = sets, .steps = half ? std::optional<int>() : 12, .every = 4}, m);
      },
      resume);
}

TEST(Adapt, AResumeAcrossAdaptationsIsByteIdentical) {
  const fs::path dir = fs::temp_directory_path() / "vpc-adapt-resume";
  fs::remove_all(dir);
  run_ironing(dir / "whole", false, false);
  // Stopped at step 6 (on a mesh adapted 12 times), then continued to step 12: the checkpoint's
  // refinement history makes its mesh again, and every later file is the uninterrupted run's, byte for byte.
  run_ironing(dir / "resumed", true, false);
  ASSERT_TRUE(fs::exists(dir / "resumed" / "checkpoint_00006.adaptations.bin"));
  run_ironing(dir / "resumed", false, true);
  for (const char* f : {"history.csv", "probes.csv", "solution_00008.vtu", "solution_00012.vtu"})
    EXPECT_EQ(file_text(dir / "whole" / f), file_text(dir / "resumed" / f)) << f;
  auto log = [](const fs::path& d) {
    auto j = nlohmann::json::parse(std::ifstream(d / "summary.json")).at("adaptations");
    for (auto& a : j) a.erase("seconds_adapt"), a.erase("seconds_rebuild"), a.erase("resident_bytes");  // measured
    return j;
  };
  EXPECT_EQ(log(dir / "whole"), log(dir / "resumed"));
  EXPECT_EQ(log(dir / "resumed").size(), 24u);
  // A checkpoint whose history is missing is passed over: the run goes on from the one before (step 0 here).
  run_ironing(dir / "lost", true, false);
  fs::remove(dir / "lost" / "checkpoint_00006.adaptations.bin");
  run_ironing(dir / "lost", false, true);
  EXPECT_EQ(file_text(dir / "whole" / "history.csv"), file_text(dir / "lost" / "history.csv"));
  fs::remove_all(dir);
}

TEST(Adapt, AResumeBetweenAnAdaptationAndItsUndoIsByteIdentical) {
  // The undo of an adaptation (the refinement history and the state before it) is kept beside the checkpoint
  // of the step it followed until the next step succeeds, so that a run resumed there undoes it as the
  // uninterrupted run does. ironing-2d with the friction law of the test above (adapted every step): a step s
  // that fails on the mesh adapted after step s − 1; a run of s steps, then the same run resumed from its
  // checkpoint of step s − 1, which must undo that adaptation again and end byte for byte as the first.
  test::register_test_laws();
  std::vector<std::string> sets = {"contact.friction=\"sized-coulomb\"", "contact.mu=0", "contact.min_measure=0.15",
                                   "adapt.resolve=0", "adapt.max_level=5"};
  const fs::path dir = fs::temp_directory_path() / "vpc-adapt-undo-resume";
  fs::remove_all(dir);
  auto run = [&](const fs::path& out, int steps, bool resume) {
    std::vector<std::string> with = sets;
    char T[48];
    std::snprintf(T, sizeof T, "time.T=%.17g", steps / 12.0);  // the time levels of 12 steps over [0, 1]
    with.emplace_back(T);
    testing::internal::CaptureStderr();
    const RunResult r = run_into(
        out, [&](const MeshRequest& m) { return load_case("ironing-2d", {.sets = with, .steps = steps, .every = 1}, m); },
        resume, 1);
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_EQ(r.steps, steps) << err;
    return err;
  };
  const std::string whole = run(dir / "whole", 12, false);
  const std::regex undone(R"(step (\d+) \(t = [^)]*\) failed on the mesh adapted at step (\d+))");
  int s = 0;
  for (auto m = std::sregex_iterator(whole.begin(), whole.end(), undone); m != std::sregex_iterator() && s == 0; ++m)
    if (std::stoi((*m)[1]) >= 2 && std::stoi((*m)[2]) == std::stoi((*m)[1]) - 1) s = std::stoi((*m)[1]);
  ASSERT_GT(s, 0) << "no step failed right after an adaptation:\n" << whole;
  const fs::path out = dir / "cut";
  const std::string first = run(out, s, false);
  const std::string warning = "step " + std::to_string(s) + " (t = ";
  ASSERT_NE(first.find(warning), std::string::npos) << first;
  const std::string history = file_text(out / "history.csv"), probes = file_text(out / "probes.csv");
  char name[32];
  std::snprintf(name, sizeof name, "checkpoint_%05d.undo.bin", s - 1);
  ASSERT_TRUE(fs::exists(out / name)) << name;
  // The run as if stopped at step s − 1: its checkpoint of step s gone.
  std::snprintf(name, sizeof name, "checkpoint_%05d", s);
  for (const auto& e : fs::directory_iterator(out))
    if (e.path().filename().string().starts_with(name)) fs::remove(e.path());
  const std::string resumed = run(out, s, true);
  EXPECT_NE(resumed.find(warning), std::string::npos) << resumed;
  EXPECT_EQ(file_text(out / "history.csv"), history);
  EXPECT_EQ(file_text(out / "probes.csv"), probes);
  fs::remove_all(dir);
}

TEST(Adapt, TwoBodiesThroughAContactPairKeepTheirBodiesPartsAndPair) {
  // cattaneo-mindlin-pair-2d coarse: a half-disc pressed into a block through a Coulomb pair, then sheared.
  const Case c = load_case("cattaneo-mindlin-pair-2d",
                           {.sets = {"mesh.size_factor=5", "body[0].mesh.size_factor=5"}, .steps = 4});
  TimeStepper s(c.problem, c.solvers);
  for (int n = 0; n < 2; ++n) ASSERT_TRUE(s.step().ok);
  AdaptSpec spec;
  spec.where = "test: [adapt]";
  MeshAdaptivity a(c.problem, s.solvers(), spec);
  auto next = a.adapt(s, 0, s.state(), s.times(), s.step_control_state());
  ASSERT_TRUE(next);
  const Mesh& before = s.mesh();
  const Mesh& after = next->mesh();
  ASSERT_EQ(after.n_bodies(), 2);
  EXPECT_EQ(after.part_names(), before.part_names());
  std::array<int, 2> cells_before{}, cells_after{};
  for (int k = 0; k < before.n_cells(); ++k) ++cells_before[static_cast<std::size_t>(before.cell_body(k))];
  for (int k = 0; k < after.n_cells(); ++k) ++cells_after[static_cast<std::size_t>(after.cell_body(k))];
  EXPECT_GE(cells_after[0], cells_before[0]);
  EXPECT_GE(cells_after[1], cells_before[1]);
  EXPECT_GT(cells_after[0] + cells_after[1], cells_before[0] + cells_before[1]);
  // The pair's normal force carried (as pressures on the slave side, summed with the new measures) and
  // the run going on through it.
  EXPECT_NEAR(next->state().lambda.sum(), s.state().lambda.sum(), 1e-9 * std::abs(s.state().lambda.sum()) + 1e-12);
  for (int n = 0; n < 2; ++n) EXPECT_TRUE(next->step().ok);
}

TEST(Adapt, AnAdaptedMeshThatCannotBeSetUpLeavesTheRunOnTheMeshBefore) {
  // Under a memory limit that the coarse mesh fits and the finer adapted ones do not: an adapted mesh's
  // set-up is refused (the old stepper freed already), the mesh before it is made again from the history,
  // and the run ends, every step within its tolerances, on that mesh (it used to crash on the freed stepper).
  const fs::path dir = fs::temp_directory_path() / "vpc-adapt-memory";
  const RunResult r = run_into(dir, [](const MeshRequest& m) {
    Case c = load_case("hertz-2d-adapt", {.memory_limit = "60M"}, m);
    c.solvers.memory_limit = "60M";
    return c;
  });
  EXPECT_EQ(r.steps, 1);
  const auto j = nlohmann::json::parse(std::ifstream(dir / "summary.json"));
  EXPECT_TRUE(j.at("checks").at("all_steps_ok").get<bool>());
  // Stopped short of its 16 passes, on the last mesh that could be set up.
  const auto& log = j.at("adaptations");
  EXPECT_LT(log.size(), 16u);
  EXPECT_EQ(j.at("mesh").at("cells").get<long long>(),
            log.empty() ? 3200 : log.back().at("cells_after").get<long long>());
  // The run goes on from the last pass's solution on that mesh: its one step recorded once (not solved
  // again from the state before it).
  std::ifstream h(dir / "history.csv");
  std::string line;
  int rows = 0;
  while (std::getline(h, line)) rows += !line.empty();
  EXPECT_EQ(rows, 2);  // the header and step 1
  fs::remove_all(dir);
}

}  // namespace
}  // namespace vpc
