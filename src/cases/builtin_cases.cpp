#include "cases/builtin_cases.hpp"

#include "core/error.hpp"
#include "mesh/generators.hpp"

#include <fmt/ranges.h>

#include <cmath>

namespace vpc {

namespace {

}  // namespace

void apply_case_overrides(Problem& p, const CaseOverrides& o) {
  if (o.steps) {
    require(*o.steps >= 1, "the number of time steps must be >= 1 (got {})", *o.steps);
    p.n_steps = *o.steps;
  }
  if (o.time_step) {
    const double k = *o.time_step;
    require(std::isfinite(k) && k > 0, "the time step must be > 0 (got {})", k);
    const double n = p.final_time / k;
    require(std::abs(n - std::round(n)) < 1e-9 * n,
            "the time step {} does not divide the final time T = {} into whole steps", k, p.final_time);
    p.n_steps = static_cast<int>(std::round(n));
  }
  if (o.kappa) {
    require(std::isfinite(*o.kappa) && *o.kappa >= 0, "kappa must be >= 0 (got {})", *o.kappa);
    p.kappa = *o.kappa;
  }
}

namespace {

/// Output every tenth of the run, at the case's probes.
Case make_case(std::string name, std::string description, std::shared_ptr<Problem> p, std::vector<Point> probes) {
  Case c;
  c.name = std::move(name);
  c.description = std::move(description);
  c.output.every = std::max(1, p->n_steps / 10);
  c.output.probes = std::move(probes);
  c.problem = std::move(p);
  return c;
}

int mesh_cells(const CaseOverrides& o, int fallback, int multiple_of, const char* why) {
  const int n = o.mesh_cells.value_or(fallback);
  require(n >= 1, "the mesh size n must be >= 1 (got {})", n);
  require(n % multiple_of == 0, "the mesh size n must be a multiple of {} ({}); got {}", multiple_of, why, n);
  return n;
}

/// SPEC §4.1: the rod of Problem 4.1 with data (4.6).
Case paper_1d(const CaseOverrides& o) {
  auto p = std::make_shared<Problem>();
  p->name = "paper-1d";
  const int n = mesh_cells(o, 100, 1, "");
  p->mesh = o.build_mesh ? make_interval(0.0, 1.0, n) : Mesh(1);
  p->clamped = {"left"};
  p->contact.parts = {"right"};
  p->contact.gap = [](const Point&, double) { return 0.25; };
  p->elasticity = Elasticity(Elasticity::Kind::Uniaxial, 1.0, 0.0);
  p->law = make_viscoplastic_law("perzyna", {{"E", 1.0}, {"lambda", 100.0}, {"sigma_y", 1.0}});
  p->source = make_damage_source("strain", {{"c", 2.0}});
  p->kappa = 1.0;
  p->f0 = [](const Point&, double t) { return Point{t, 0, 0}; };
  p->f0_uniform = true;
  p->beta0 = [](const Point&, double) { return 1.0; };
  p->final_time = 1.0;
  p->n_steps = 100;
  apply_case_overrides(*p, o);
  return make_case("paper-1d", "the paper's 1D rod (Problem 4.1, data 4.6): Perzyna, phi = -2 eps, gap 0.25", p,
                   {{0.25, 0, 0}, {0.5, 0, 0}, {1.0, 0, 0}});
}

/// SPEC §4.2: the plane-stress block of Section 4.2 with data (4.11).
Case paper_2d(const CaseOverrides& o) {
  auto p = std::make_shared<Problem>();
  p->name = "paper-2d";
  const int n = mesh_cells(o, 40, 5, "so that x = 0.8 and 1.2 are nodes");
  p->mesh = o.build_mesh ? make_rectangle({0, 0, 0}, {2, 2, 0}, n, n) : Mesh(2);
  p->mesh.tag_facets("contact", [](const Point& x) { return std::abs(x[1]) < 1e-12 && x[0] > 0.8 && x[0] < 1.2; });
  p->clamped = {"top"};
  p->contact.parts = {"contact"};
  p->contact.gap = [](const Point&, double) { return 0.0; };
  p->elasticity = Elasticity(Elasticity::Kind::PlaneStress, 1000.0, 0.3);
  p->law = make_viscoplastic_law("maxwell-damage", {});
  p->source = make_damage_source("von-mises", {{"c", 0.01}});
  p->kappa = 1.0;
  p->f0 = [](const Point&, double t) { return Point{0, -10 * t, 0}; };
  p->f2 = [](const Point&, double) { return Point{0, 0, 0}; };
  p->f0_uniform = p->f2_uniform = true;
  p->beta0 = [](const Point&, double) { return 1.0; };
  p->final_time = 1.0;
  p->n_steps = 100;
  apply_case_overrides(*p, o);
  return make_case("paper-2d", "the paper's 2D block (Section 4.2, data 4.11): plane stress, G = (beta - 1) sigma", p,
                   {{1.0, 0, 0}, {0.8, 0, 0}, {1.0, 1.0, 0}, {0.0, 0.0, 0}});
}

/// The 2D example's 3D counterpart: cube (0, 2)³ clamped on top, body force
/// (0, 0, −10t), contact patch [0.8, 1.2]² on the bottom face.
Case block_3d(const CaseOverrides& o) {
  auto p = std::make_shared<Problem>();
  p->name = "block-3d";
  const int n = mesh_cells(o, 10, 5, "so that x, y = 0.8 and 1.2 are nodes");
  p->mesh = o.build_mesh ? make_box({0, 0, 0}, {2, 2, 2}, n, n, n) : Mesh(3);
  p->mesh.tag_facets("contact", [](const Point& x) {
    return std::abs(x[2]) < 1e-12 && x[0] > 0.8 && x[0] < 1.2 && x[1] > 0.8 && x[1] < 1.2;
  });
  p->clamped = {"top"};
  p->contact.parts = {"contact"};
  p->contact.gap = [](const Point&, double) { return 0.0; };
  p->elasticity = Elasticity(Elasticity::Kind::Isotropic, 1000.0, 0.3);
  p->law = make_viscoplastic_law("maxwell-damage", {});
  p->source = make_damage_source("von-mises", {{"c", 0.01}});
  p->kappa = 1.0;
  p->f0 = [](const Point&, double t) { return Point{0, 0, -10 * t}; };
  p->f0_uniform = true;
  p->beta0 = [](const Point&, double) { return 1.0; };
  p->final_time = 1.0;
  p->n_steps = 100;
  apply_case_overrides(*p, o);
  return make_case("block-3d", "a 3D block (0,2)^3 pressed onto a foundation patch [0.8,1.2]^2", p,
                   {{1.0, 1.0, 0}, {1.0, 1.0, 1.0}});
}

}  // namespace

std::vector<std::string> builtin_case_names() { return {"paper-1d", "paper-2d", "block-3d"}; }

Case make_builtin_case(const std::string& name, const CaseOverrides& o) {
  try {
    if (name == "paper-1d") return paper_1d(o);
    if (name == "paper-2d") return paper_2d(o);
    if (name == "block-3d") return block_3d(o);
  } catch (const Error& e) {
    fail("{}{}: {}", name, o.mesh_cells ? fmt::format(" with n = {}", *o.mesh_cells) : "", e.what());
  }
  fail("unknown case '{}'; built-in cases are: {}", name, fmt::join(builtin_case_names(), ", "));
}

}  // namespace vpc
