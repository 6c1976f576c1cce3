#pragma once
// The discrete system of SPEC §2 on this process's part (part/mesh_part.hpp): everything
// the scheme derives from the problem once and keeps over the run, like MFEM's
// TimeDependentOperator: the cells' geometry and materials, K of (3.9), M and A of (3.8),
// the lumped mass of the error estimate, the basis integrals of uniform loads, the cells
// that u_D's lifting touches, the contact set (nodes and rows N) and |Ω|. Built once by
// TimeStepper's set-up; after it nothing changes it, the step (scheme/scheme_step.hpp) and its
// checks only read it. The one field that may point elsewhere is `contact`, to a set that is itself
// fixed: where pairs slide large, TimeStepper points it at the set its PairSlider makes at the
// start of a step (scheme/pair_slider.hpp), and a reader holding the old set keeps it whole.
#include "fem/cell_geometry.hpp"
#include "la/backend.hpp"
#include "la/vector.hpp"
#include "part/contact_set.hpp"
#include "part/mesh_part.hpp"
#include "problem/problem.hpp"
#include "problem/time_grid.hpp"
#include "scheme/solver_choice.hpp"
#include "solvers/contact_solver.hpp"
#include "solvers/solver_cost.hpp"

#include <memory>
#include <optional>
#include <vector>

namespace vpc {

struct DiscreteSystem {
  /// Computes the geometry, materials and data above and assembles K, M, A and the first
  /// step's H = M + k_1 κA (the set-up stage "assembly", told to choice.on_setup_stage). Collective.
  DiscreteSystem(std::shared_ptr<const Problem> problem, MeshPart part, std::shared_ptr<const la::Backend> backend,
                 const SolverChoice& choice);

  std::shared_ptr<const Problem> problem;
  MeshPart part;
  std::shared_ptr<const la::Backend> backend;
  std::vector<CellGeometry> geo;
  std::vector<Material> materials;  // Problem::material_list(), indexed by part.cell_material
  const Material& material(int cell) const { return materials[part.cell_material[cell]]; }
  double volume = 0;  // |Ω|, over every process
  /// The error control of Problem::step_control completed and capped at the stable step
  /// (stable_step_control, problem/stability.hpp); empty for a fixed grid.
  std::optional<StepControl> control;
  double first_step = 0;  // k_1 (Problem::first_step): the step the set-up's H is for

  /// K of (3.9) over the free dofs, shared with the contact solver; its dofs come in blocks
  /// of K_block (d, or 1 where some node has only some components prescribed: a roller).
  std::shared_ptr<la::SpdOperator> K;
  int K_block = 1;
  double K_local_nonzeros = 0;  // for model_bytes
  /// K's assembled diagonal on the owned free dofs, where a contact law keeps per-node state (the
  /// nodes' normal stiffness its updates see: scheme/surface_fields.cpp); empty otherwise.
  Vector K_diagonal;
  /// The part's K: kept until the contact solver's set-up has made the primal solver's K_rot from
  /// it (scheme/scheme_solvers.hpp), then handed to the run's PairSlider (kept where a pair slides
  /// large, else released): empty after set-up.
  SparseMatrix K_local;
  std::unique_ptr<la::SpdOperator> M;
  SparseMatrix M_local, A_local;  // the part's mass and Laplacian (H for other step sizes)
  /// κ of (3.8), the factor of A_local: Problem::kappa with one body; with several, A_local holds
  /// each cell's body's κ (damage_laplacian) and this is 1.
  double kappa = 1;
  /// H = M + k_1 κA of the first step, assembled with K: handed to its damage solver at set-up.
  std::unique_ptr<la::SpdOperator> H_first;
  double H_first_local_nonzeros = 0;
  /// The owned nodes whose β stays β0 (constant_damage_nodes): held by the damage solvers.
  std::vector<char> constant_damage;
  Vector lumped_mass;  // the row sums of M (owned nodes): the error estimate's M_L
  Vector basis_integral_cells, basis_integral_traction;  // ∫ψ_a over Ω and Γ2 (for uniform f0, f2; else empty)
  std::vector<int> dirichlet_cells;  // the part's cells with a prescribed dof: u_D's lifting, the reactions
  /// The contact nodes, their rows and friction's frame (part/contact_set.hpp) in the configuration
  /// the step starts from: made by the constructor from the part's (taken: part.contact is empty
  /// after), a new one at each slide of a large-sliding pair (TimeStepper, scheme/pair_slider.hpp).
  std::shared_ptr<const ContactSet> contact;
  double assembly_seconds = 0, build_seconds = 0;
  ProcessMemory mesh_memory, assembly_memory;  // this process's as the construction starts and ends

  /// A factor of K's kind (name "K"), its coordinates set for multigrid's rigid-body modes.
  std::shared_ptr<la::LinearSolver> make_stiffness_factor() const;
};

/// Per owned node of `part`: whether its β stays β0 whatever the state: its body's cells all have
/// φ ≡ 0 (DamageSource::vanishes) and its β0 is uniform over the body. (3.8) then gives β_n = β_{n−1}
/// exactly, since A·1 = 0 and no damage flux crosses to another body (SPEC §8); left to the box
/// QP, the degenerate bound of such a body's β = 1 (multiplier 0) flips in and out of the active
/// set on round-off (an undamaged deformable foundation: 3 damage solves a step instead of 1).
/// Collective.
std::vector<char> constant_damage_nodes(const Problem& p, const MeshPart& part, const std::vector<Material>& materials);

/// The contact solver's data: N, g(0) and the law of each owned contact row (ContactSet::constraints). Collective.
ContactConstraints contact_constraints(const DiscreteSystem& sys);

/// The memory of a mesh (coordinates and cell array: `cell_entries` node numbers) and of the
/// state on its cells (bytes): what the estimates before set-up (run/solver_plan.hpp) and
/// check_before_factorizing count for them.
double mesh_and_state_bytes(double nodes, double cell_entries, double cells);

/// Refuses a run that cannot fit before the costly factorizations (issue 11), from the factors'
/// symbolic analyses (K's is kept in K_factor for its factorization), where the backend has them
/// (CHOLMOD): a stepper made without the solver plan (run/solver_plan.hpp: `converge`'s levels,
/// the library's callers) is refused here. Returns the run's estimated cost by both paths
/// (nothing without a symbolic analysis). `primal`: the primal contact solver (no S = N K⁻¹ Nᵀ).
std::optional<SolverCost> check_before_factorizing(const DiscreteSystem& sys, la::LinearSolver& K_factor,
                                                   const SolverChoice& choice, bool primal);

}  // namespace vpc
