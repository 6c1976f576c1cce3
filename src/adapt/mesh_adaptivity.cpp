#include "adapt/mesh_adaptivity.hpp"

#include "adapt/adaptation_json.hpp"
#include "adapt/indicator.hpp"
#include "adapt/marking.hpp"
#include "adapt/state_transfer.hpp"
#include "core/stopwatch.hpp"
#include "fem/cell_geometry.hpp"
#include "core/error.hpp"
#include "core/process_memory.hpp"
#include "contact/contact_spec.hpp"
#include "problem/contact_rows.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <tuple>
#include <unordered_map>

namespace vpc {

struct ApproachForecast {
  double t = 0, k = 0;
  int steps = 0;
};

void check_adaptable(const Problem& p, const AdaptSpec& spec) {
  const Mesh& m = p.mesh;
  if (m.dim() == 1)
    fail("{}: mesh adaptivity bisects triangles and tetrahedra; this mesh is 1D. Remove [adapt], or refine the "
         "mesh uniformly ([mesh] refine, --n)",
         spec.where);
  if (p.block) fail("{}: mesh adaptivity runs on one process for now (not on blocks of a generated mesh)", spec.where);
}

namespace {

const Mesh& adaptable_mesh(const Problem& p, const AdaptSpec& spec) {
  check_adaptable(p, spec);
  return p.mesh;
}

double longest_edge(const BisectionForest& f, int c) {
  const auto v = f.vertices(c);
  double h = 0;
  for (std::size_t i = 0; i < v.size(); ++i)
    for (std::size_t j = i + 1; j < v.size(); ++j) {
      const Point& p = f.node(v[i]);
      const Point& q = f.node(v[j]);
      h = std::max(h, f.dim() == 2 ? std::hypot(p[0] - q[0], p[1] - q[1]) : std::hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]));
    }
  return h;
}

int alive_nodes(const BisectionForest& f) {
  int n = 0;
  for (int i = 0; i < f.n_nodes(); ++i) n += f.node_alive(i);
  return n;
}

SymTensor tensor_at(const std::vector<double>& v, std::size_t k) {
  SymTensor t;
  std::copy_n(v.begin() + static_cast<std::ptrdiff_t>(k * 6), 6, t.c.begin());
  return t;
}

/// The forecast from the stepper `s` over the `steps` steps to the next adaptation.
ApproachForecast forecast_of(const TimeStepper& s, int steps) {
  const Problem& p = s.problem();
  if (steps <= 0 || s.done() || (p.contact.obstacles.empty() && !p.contact.gap_moves)) return {};
  const std::vector<double>& times = s.times();
  const double t = s.state().t;
  return {t, times.size() >= 2 ? t - times[times.size() - 2] : p.final_time / std::max(1, p.n_steps), steps};
}

/// A gathered state on the forest's leaf mesh, in its numbering (cell k: leaves()[k]): what the indicator
/// and the forecast read, so that the marks do not depend on an engine's numbering of its part.
struct LeafState {
  Mesh mesh;
  Vector beta;
  std::vector<double> pressure;  // λ_ν / |Γ3|_i per node (NaN off Γ3)
  std::vector<double> u;         // d a node
  std::vector<SymTensor> sigma;  // per cell
};

LeafState leaf_state(const BisectionForest& forest, const ForestState& fs) {
  LeafState out;
  out.mesh = forest.leaf_mesh();
  const int d = out.mesh.dim();
  const std::vector<int> number = forest.mesh_numbers();
  out.beta.resize(out.mesh.n_nodes());
  out.pressure.assign(static_cast<std::size_t>(out.mesh.n_nodes()), NAN);
  out.u.assign(static_cast<std::size_t>(out.mesh.n_nodes() * d), 0.0);
  const auto w = static_cast<std::size_t>(fs.contact_width);
  for (std::size_t i = 0; i < number.size(); ++i) {
    if (number[i] < 0) continue;
    const auto m = static_cast<std::size_t>(number[i]);
    out.beta[number[i]] = fs.beta[i];
    out.pressure[m] = fs.contact[i * w];
    std::copy_n(fs.u.begin() + static_cast<std::ptrdiff_t>(i * static_cast<std::size_t>(d)), d,
                out.u.begin() + static_cast<std::ptrdiff_t>(m * static_cast<std::size_t>(d)));
  }
  out.sigma.resize(fs.leaves.size());
  for (std::size_t k = 0; k < out.sigma.size(); ++k) out.sigma[k] = tensor_at(fs.sigma, k);
  return out;
}

/// The margin min_j g(t_{n+j}) − u_ν of each obstacle row of `coarse`'s problem on the leaf mesh to its
/// obstacle over the forecast's steps, per leaf-mesh node (NaN elsewhere, and everywhere without a
/// forecast): adapt/indicator.hpp's surfaces about to touch, so that an adaptation every k steps refines
/// the whole path an indenter takes until the next one. The rows (direction, obstacles) are the leaf mesh's
/// own, as its stepper will have them; a pair's rows (whose gap is the reference configuration's) are not
/// forecast.
std::vector<double> approach_margins(const Problem& coarse, const LeafState& ls, const ApproachForecast& f) {
  const Mesh& mesh = ls.mesh;
  std::vector<double> out(static_cast<std::size_t>(mesh.n_nodes()), NAN);
  if (f.steps <= 0) return out;
  const int d = mesh.dim();
  const auto p = problem_on_mesh(coarse, mesh);
  const auto [lo, hi] = mesh.bounding_box();
  const double miss = contact_miss_gap(lo, hi);
  for (const ContactRow& row : contact_rows(*p, dirichlet_dofs(*p).condition)) {
    if (row.pair >= 0) continue;
    const Point& x = mesh.node(row.node);
    double u_nu = 0;
    for (int j = 0; j < d; ++j) u_nu += row.direction[j] * ls.u[static_cast<std::size_t>(row.node * d + j)];
    double margin = INFINITY;
    for (int j = 1; j <= f.steps; ++j) {
      const double at = std::min(f.t + j * f.k, coarse.final_time);
      margin = std::min(margin, contact_gap_at(coarse.contact, x, row.direction, at, miss, row.obstacles) - u_nu);
      if (at >= coarse.final_time) break;
    }
    out[static_cast<std::size_t>(row.node)] = margin;
  }
  return out;
}

CellIndicators leaf_indicators(const LeafState& ls, const AdaptSpec& spec, const std::vector<double>& approach) {
  return cell_indicators(ls.mesh, ls.sigma, ls.beta, ls.pressure, spec, approach);
}

/// What removing one node changes (squared L2 norms), per AdaptationRecord's measures.
struct PatchChange {
  double z2 = 0, sigma2 = 0, beta2 = 0, damage = 0;
};

}  // namespace

std::shared_ptr<const Problem> problem_on_mesh(const Problem& coarse, Mesh mesh) {
  auto p = std::make_shared<Problem>(coarse);
  p->mesh = std::move(mesh);
  return p;
}

MeshAdaptivity::MeshAdaptivity(std::shared_ptr<const Problem> coarse, SolverChoice choice, AdaptSpec spec,
                               StepperMaker make)
    : coarse_(std::move(coarse)),
      choice_(std::move(choice)),
      make_(make ? std::move(make)
                 : [](std::shared_ptr<const Problem> p, const SolverChoice& c) {
                     return std::make_unique<TimeStepper>(std::move(p), c);
                   }),
      spec_(std::move(spec)),
      forest_(adaptable_mesh(*coarse_, spec_)) {}

std::vector<int> MeshAdaptivity::levels(const TimeStepper& s) const {
  const std::vector<int> leaves = forest_.leaves();
  std::vector<int> out;
  for (int c : s.part().original_cell) out.push_back(forest_.level(leaves[static_cast<std::size_t>(c)]));
  return out;
}

std::vector<double> MeshAdaptivity::indicator(const TimeStepper& s) const {
  const LeafState ls = leaf_state(forest_, gather_state(forest_, s, s.state()));
  const CellIndicators ind = leaf_indicators(ls, spec_, approach_margins(*coarse_, ls, forecast_of(s, spec_.every)));
  std::vector<double> out;
  for (int c : s.part().original_cell) out.push_back(ind.combined[static_cast<std::size_t>(c)]);
  return out;
}

std::unique_ptr<TimeStepper> MeshAdaptivity::adapt(const TimeStepper& s, int pass, const State& carry,
                                                   std::vector<double> times, StepControlState control,
                                                   const std::function<void()>& release) {
  const auto t0 = std::chrono::steady_clock::now();
  const int d = s.mesh().dim();
  // The indicator on the leaf mesh (cell p: leaves[p]; node: its mesh_numbers), from the solution gathered
  // into the forest's numbering: the same marks whatever the engine's numbering of its part.
  ForestState solution = gather_state(forest_, s, s.state());
  const std::vector<int> leaves = forest_.leaves();
  const ApproachForecast forecast = forecast_of(s, pass == 0 ? spec_.every : 0);
  std::vector<char> about_to_touch(leaves.size(), 0);  // the cells of Γ3 facets about to touch, once coarsened
  const CellIndicators ind = [&] {
    const LeafState ls = leaf_state(forest_, solution);
    const std::vector<double> approach = approach_margins(*coarse_, ls, forecast);
    for (int f : facets_about_to_touch(ls.mesh, ls.pressure, approach, 2))
      about_to_touch[static_cast<std::size_t>(ls.mesh.facet_cell(f))] = 1;
    return leaf_indicators(ls, spec_, approach);
  }();
  if (spec_.tolerance > 0 && ind.stress_relative <= spec_.tolerance) return nullptr;
  AdaptationRecord rec;
  rec.step = s.state().n;
  rec.t = s.state().t;
  rec.pass = pass;
  rec.stress_relative = ind.stress_relative;
  rec.cells_before = s.mesh().n_cells();
  rec.unknowns_before = s.part().n_global_dofs;

  // Refinement: bulk marking, within the level and size limits, then the unknowns'.
  std::vector<int> refine;
  bool deep = false;
  // Each part's own Dörfler set (a part with weight 0 marks nothing), largest combined indicator first:
  // the order a truncation to max_unknowns keeps.
  std::vector<const std::vector<double>*> parts;
  if (spec_.stress_weight > 0) parts.push_back(&ind.stress);
  if (spec_.contact_weight > 0) parts.push_back(&ind.contact);
  if (spec_.damage_weight > 0) parts.push_back(&ind.damage);
  std::vector<int> marked = bulk_marking_each(parts, spec_.refine_fraction);
  std::stable_sort(marked.begin(), marked.end(), [&](int x, int y) {
    return ind.combined[static_cast<std::size_t>(x)] > ind.combined[static_cast<std::size_t>(y)];
  });
  for (int k : marked) {
    const int c = leaves[static_cast<std::size_t>(k)];
    if (forest_.level(c) >= spec_.max_level) {
      deep = true;
      continue;
    }
    if (spec_.min_size > 0 && longest_edge(forest_, c) <= spec_.min_size) continue;
    refine.push_back(c);
  }
  within_max_unknowns(refine, rec);
  if (deep) {
    rec.truncated = true;
    if (!warned_level_) {
      warned_level_ = true;
      warnings_.push_back(fmt::format("{}: max_level = {} reached at step {} (t = {:.6g}): cells at that level "
                                      "are not refined further",
                                      spec_.where, spec_.max_level, rec.step, rec.t));
    }
  }
  rec.marked = static_cast<int>(refine.size());

  // Coarsening: the smallest share of the indicator, not marked for refinement nor about to touch (the
  // forecast would refine it again), whose patches change z, σ, β by less than the tolerance, summed over
  // the adaptation.
  // What coarsening would change is measured on the solution the indicator read (s's state), whatever is
  // carried (a redo carries the state before the step).
  ForestState fs = &carry == &s.state() ? solution : gather_state(forest_, s, carry);
  std::vector<char> refined(static_cast<std::size_t>(forest_.n_cells()), 0);
  for (int c : refine) refined[static_cast<std::size_t>(c)] = 1;
  std::vector<char> eligible(leaves.size());
  for (std::size_t k = 0; k < leaves.size(); ++k)
    eligible[k] = forest_.level(leaves[k]) > 0 && !refined[static_cast<std::size_t>(leaves[k])] && !about_to_touch[k];
  std::vector<int> candidates;
  for (int k : smallest_share(ind.combined, spec_.coarsen_fraction, eligible)) candidates.push_back(leaves[static_cast<std::size_t>(k)]);
  const std::vector<Material> materials = s.problem().material_list();
  std::vector<const Elasticity*> elasticity(static_cast<std::size_t>(coarse_->mesh.n_cells()), nullptr);
  const std::vector<int>& leaf_of = s.part().original_cell;  // a part cell's place in `leaves`
  for (std::size_t k = 0; k < leaf_of.size(); ++k)
    elasticity[static_cast<std::size_t>(forest_.root(leaves[static_cast<std::size_t>(leaf_of[k])]))] =
        &materials[static_cast<std::size_t>(s.part().cell_material[k])].elasticity;
  std::vector<BisectionForest::Patch> accepted;
  if (!candidates.empty()) {
    std::unordered_map<int, std::size_t> place;  // a leaf's index in `leaves`
    for (std::size_t k = 0; k < leaves.size(); ++k) place.emplace(leaves[k], k);
    double sigma_scale2 = 0, volume = 0;
    for (std::size_t k = 0; k < leaves.size(); ++k) {
      const double a = forest_.area(leaves[k]);
      volume += a;
      const SymTensor sg = tensor_at(solution.sigma, k);
      sigma_scale2 += a * sg.dot(sg);
    }
    auto relative = [](double change2, double scale2) {
      return scale2 > 0 ? change2 / scale2 : (change2 > 0 ? INFINITY : 0.0);
    };
    std::vector<BisectionForest::Patch> patches = forest_.coarsenable(candidates);
    std::vector<PatchChange> change(patches.size());
    for (std::size_t q = 0; q < patches.size(); ++q) {
      const BisectionForest::Patch& patch = patches[q];
      PatchChange& ch = change[q];
      const auto [a, b] = forest_.made_at(patch.node);
      const double delta = solution.beta[static_cast<std::size_t>(patch.node)] -
                           0.5 * (solution.beta[static_cast<std::size_t>(a)] + solution.beta[static_cast<std::size_t>(b)]);
      double area = 0;
      for (int p : patch.parents) {
        area += forest_.area(p);
        // σ on the parent after: ℰε(u injected) + the children's mean z.
        const std::size_t k0 = place.at(forest_.children(p)[0]), k1 = place.at(forest_.children(p)[1]);
        const SymTensor z_mean = 0.5 * (tensor_at(solution.z, k0) + tensor_at(solution.z, k1));
        const SymTensor sigma_after =
            elasticity[static_cast<std::size_t>(forest_.root(p))]->apply(forest_cell_strain(forest_, solution.u, d, p)) + z_mean;
        for (std::size_t k : {k0, k1}) {
          const double ak = forest_.area(leaves[k]);
          const SymTensor dz = tensor_at(solution.z, k) - z_mean, ds = tensor_at(solution.sigma, k) - sigma_after;
          ch.z2 += ak * dz.dot(dz);
          ch.sigma2 += ak * ds.dot(ds);
        }
      }
      ch.beta2 = delta * delta * area / 6;  // ‖δ φ_m‖², ∫φ_m² = |patch| / 6
      ch.damage = delta * area / 3;         // ∫(1 − β) grows by δ ∫φ_m
    }
    std::vector<std::size_t> order(patches.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    auto cost = [&](std::size_t q) {
      return std::max({relative(change[q].z2, sigma_scale2), relative(change[q].sigma2, sigma_scale2),
                       relative(change[q].beta2, volume)});
    };
    std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return cost(x) < cost(y); });
    const double budget = spec_.coarsen_tolerance * spec_.coarsen_tolerance;
    PatchChange total;
    for (std::size_t q : order) {
      const PatchChange& ch = change[q];
      if (relative(total.z2 + ch.z2, sigma_scale2) > budget || relative(total.sigma2 + ch.sigma2, sigma_scale2) > budget ||
          relative(total.beta2 + ch.beta2, volume) > budget)
        continue;
      total.z2 += ch.z2;
      total.sigma2 += ch.sigma2;
      total.beta2 += ch.beta2;
      total.damage += ch.damage;
      accepted.push_back(patches[q]);
    }
    std::sort(accepted.begin(), accepted.end(), [](const auto& x, const auto& y) { return x.node < y.node; });
    rec.change_z = std::sqrt(relative(total.z2, sigma_scale2));
    rec.change_sigma = std::sqrt(relative(total.sigma2, sigma_scale2));
    rec.change_beta = std::sqrt(relative(total.beta2, volume));
    rec.change_damage_integral = total.damage;
  }
  // The forest changed and the state carried: coarsening first (its patches were found on the leaves
  // before), then refinement (its cells are leaves still: none was a coarsening candidate), then the zone the
  // forecast sees about to touch, to its final level.
  const std::size_t changes_before = changes_.size();
  if (!refine.empty() || !accepted.empty()) changes_.push_back({accepted, refine});
  if (!accepted.empty()) {
    rec.removed_nodes = forest_.coarsen_patches(accepted);
    carry_through_coarsening(forest_, elasticity, fs);
  }
  if (!refine.empty()) {
    rec.bisected = forest_.refine(refine);
    carry_through_refinement(forest_, fs);
  }
  refine_forecast_zone(fs, forecast, rec);
  if (changes_.size() == changes_before) return nullptr;
  Mesh mesh = forest_.leaf_mesh();
  rec.min_angle_degrees = forest_.min_angle() * 180 / M_PI;
  rec.h_min = mesh.size_range().first;
  for (int c : forest_.leaves()) rec.max_level = std::max(rec.max_level, forest_.level(c));
  rec.seconds_adapt = seconds_since(t0);

  solution = ForestState{};  // (freed before the new stepper is made)
  if (release) release();  // `s` and `carry` are gone from here on
  const auto t1 = std::chrono::steady_clock::now();
  std::unique_ptr<TimeStepper> next = make_(problem_on_mesh(*coarse_, std::move(mesh)), choice_);
  const auto t2 = std::chrono::steady_clock::now();
  const State state = scatter_state(forest_, fs, *next);
  next->restore({state, restrict_to_free(next->dofs(), state.u), next->contact_warm_state(), next->damage_warm_state()});
  next->set_step_history(std::move(times), control);
  std::tie(rec.dirichlet_mismatch, rec.penetration) = next->data_mismatch();
  rec.seconds_adapt += seconds_since(t2);
  rec.seconds_rebuild = std::chrono::duration<double>(t2 - t1).count();
  rec.resident_bytes = static_cast<double>(process_memory().resident);
  rec.cells_after = next->mesh().n_cells();
  rec.unknowns_after = next->part().n_global_dofs;
  rec.linear_solver = next->backend().linear_solver();
  log_.push_back(rec);
  return next;
}

bool MeshAdaptivity::within_max_unknowns(std::vector<int>& refine, AdaptationRecord& rec) {
  const int d = forest_.dim();
  auto unknowns_with = [&](std::size_t count) {
    BisectionForest trial = forest_;
    trial.refine(std::vector<int>(refine.begin(), refine.begin() + static_cast<std::ptrdiff_t>(count)));
    return static_cast<long long>(d) * alive_nodes(trial);
  };
  if (refine.empty() || unknowns_with(refine.size()) <= spec_.max_unknowns) return true;
  std::size_t lo = 0, hi = refine.size();  // the most cells, in the given order, within the limit
  while (lo < hi) {
    const std::size_t mid = (lo + hi + 1) / 2;
    if (unknowns_with(mid) <= spec_.max_unknowns) lo = mid;
    else hi = mid - 1;
  }
  refine.resize(lo);
  rec.truncated = true;
  if (!warned_unknowns_) {
    warned_unknowns_ = true;
    warnings_.push_back(fmt::format("{}: max_unknowns = {} reached at step {} (t = {:.6g}; the mesh has {} = d × "
                                    "nodes): refinement marking truncated, in the indicator's order (the forecast's "
                                    "zone in cell order; reported in summary.json \"adaptations\")",
                                    spec_.where, spec_.max_unknowns, rec.step, rec.t,
                                    static_cast<long long>(d) * alive_nodes(forest_)));
  }
  return false;
}

void MeshAdaptivity::refine_forecast_zone(ForestState& fs, const ApproachForecast& forecast, AdaptationRecord& rec) {
  if (forecast.steps <= 0) return;
  int target = -1;
  for (int pass = 0; pass < spec_.max_level; ++pass) {
    const LeafState ls = leaf_state(forest_, fs);
    const std::vector<int> leaves = forest_.leaves();
    const int d = ls.mesh.dim();
    if (target < 0) {
      // The level the solution-driven marking has taken the contact zone to: the deepest cell with a Γ3
      // facet in contact; before any contact, max_level.
      for (int f = 0; f < ls.mesh.n_facets(); ++f) {
        bool in_contact = false;
        for (int a = 0; a < d; ++a) in_contact = in_contact || ls.pressure[static_cast<std::size_t>(ls.mesh.facet(f)[a])] > 0;
        if (in_contact) target = std::max(target, forest_.level(leaves[static_cast<std::size_t>(ls.mesh.facet_cell(f))]));
      }
      target = target < 0 ? spec_.max_level : std::min(target, spec_.max_level);
    }
    std::vector<int> refine;
    std::vector<double> approach;
    try {
      approach = approach_margins(*coarse_, ls, forecast);
    } catch (const Error&) {
      return;  // (the refined mesh's contact rows refused: its stepper's set-up says why, and the run recovers)
    }
    const auto about = facets_about_to_touch(ls.mesh, ls.pressure, approach);
    for (int f : about) {
      const int c = leaves[static_cast<std::size_t>(ls.mesh.facet_cell(f))];
      if (forest_.level(c) >= target || (spec_.min_size > 0 && longest_edge(forest_, c) <= spec_.min_size)) continue;
      refine.push_back(c);
    }
    std::ranges::sort(refine);
    refine.erase(std::unique(refine.begin(), refine.end()), refine.end());
    const bool within = within_max_unknowns(refine, rec);
    if (refine.empty()) return;
    rec.marked += static_cast<int>(refine.size());
    rec.bisected += forest_.refine(refine);
    carry_through_refinement(forest_, fs);
    changes_.push_back({{}, refine});
    ++rec.forecast_passes;
    if (!within) return;
  }
}

std::string MeshAdaptivity::history() const {
  nlohmann::ordered_json j;
  j["format"] = "vpcontact adaptation history 1";
  j["changes"] = nlohmann::ordered_json::array();
  for (const Change& c : changes_) {
    nlohmann::ordered_json patches = nlohmann::ordered_json::array();
    for (const BisectionForest::Patch& p : c.coarsened) patches.push_back({{"node", p.node}, {"parents", p.parents}});
    j["changes"].push_back({{"coarsened", patches}, {"refined", c.refined}});
  }
  j["log"] = nlohmann::ordered_json::array();
  for (const AdaptationRecord& a : log_) j["log"].push_back(adaptation_json(a));
  j["warned"] = {warned_unknowns_, warned_level_};
  return j.dump();
}

void MeshAdaptivity::replay(const std::string& history) {
  require(changes_.empty(), "mesh adaptivity: a replay needs an adaptivity that has not adapted");
  try {
    const auto j = nlohmann::ordered_json::parse(history);
    require(j.at("format") == "vpcontact adaptation history 1", "not an adaptation history of this version");
    for (const auto& c : j.at("changes")) {
      Change change;
      for (const auto& p : c.at("coarsened"))
        change.coarsened.push_back({p.at("node").get<int>(), p.at("parents").get<std::vector<int>>()});
      change.refined = c.at("refined").get<std::vector<int>>();
      for (int cell : change.refined)
        require(cell >= 0 && cell < forest_.n_cells() && forest_.leaf(cell), "refined cell {} is not a leaf", cell);
      forest_.coarsen_patches(change.coarsened);
      forest_.refine(change.refined);
      changes_.push_back(std::move(change));
    }
    for (const auto& a : j.at("log")) log_.push_back(adaptation_record(a));
    warned_unknowns_ = j.at("warned").at(0).get<bool>();
    warned_level_ = j.at("warned").at(1).get<bool>();
  } catch (const nlohmann::json::exception& e) {
    fail("mesh adaptivity: a malformed adaptation history: {}", e.what());
  }
}

std::unique_ptr<TimeStepper> MeshAdaptivity::make_stepper() const {
  return make_(problem_on_mesh(*coarse_, forest_.leaf_mesh()), choice_);
}

}  // namespace vpc
