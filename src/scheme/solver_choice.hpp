#pragma once
// How a run solves (the contact and damage solvers, tolerances, halving, memory) and where
// its set-up time and memory go: the choices TimeStepper's set-up (scheme/scheme_solvers.hpp) acts on.
#include "core/process_memory.hpp"
#include "solvers/contact_capabilities.hpp"
#include "solvers/contact_solver.hpp"
#include "solvers/damage_solver.hpp"

#include <functional>
#include <string>

namespace vpc {

struct SolverChoice {
  std::string contact = "auto";  // "active-set" (dual), "primal-active-set", "penalty-duality" (pick_contact_solver)
  std::string damage = "active-set";   // or "penalty-duality"
  ContactSolverOptions contact_options;
  /// Damage active set: how systems with some β_i at a bound are solved.
  ReducedSolve damage_reduced = ReducedSolve::automatic;
  /// A step whose residuals exceed this (relative) is reported as failed.
  double residual_tolerance = 1e-8;
  /// PETSc engine: each contact pair's row goes with its slave node's owner and its
  /// master nodes become ghosts there (distribute_mesh's spread_pairs; docs/parallel.md), the rows'
  /// entries at those masters sent to their owners as remote pieces (the dual alone solves them).
  /// Nothing to spread on one process.
  bool spread_pairs = false;
  /// A failed step is retried as two steps of half the size, at most this many
  /// times nested (0: a failed step is reported as it is).
  int max_halvings = 0;
  /// Optional: told as each setup stage starts (seconds < 0) and when it ends
  /// (its wall time), so that a long setup shows what it is doing (vpcontact run/check).
  std::function<void(const std::string& stage, double seconds)> on_setup_stage;
  /// The memory a run may use (la/memory_estimate.hpp): a size such as "8G",
  /// or empty for $VPCONTACT_MEMORY_LIMIT, else the machine's available memory.
  std::string memory_limit;

  /// Tells on_setup_stage, if set.
  void stage(const std::string& what, double seconds = -1) const {
    if (on_setup_stage) on_setup_stage(what, seconds);
  }
};

/// Where the setup time (seconds) and memory go.
struct SetupTiming {
  double total = 0;
  double assembly = 0;  // K, M, A
  double factor_K = 0;  // factorization of K
  double factor_H = 0;  // the damage solver's setup (factor of M + kκA)
  double contact = 0;   // contact rows N and the contact solver's setup (S = N K⁻¹ Nᵀ)
  /// This process's memory as each stage ended: its part of the mesh (as the discrete system
  /// starts), the assembly (K, M, A, H), K's factor or preconditioner (none yet for the primal
  /// contact solver, which factors K with its active rows at its first solve), H's, the contact
  /// set-up (summary.json "memory_bytes").
  ProcessMemory mesh, assembled, factored_K, factored_H, contact_ready;
};

}  // namespace vpc
