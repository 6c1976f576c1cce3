#pragma once
// Solvers of the damage inequality (3.8) in matrix form: the box-constrained QP
//     min ½ βᵀHβ − rᵀβ,  0 ≤ β ≤ 1,  H = M + kκA (constant over a run),
//     r = M β_{n−1} + k F_φ.
#include "solvers/box_qp.hpp"
#include "la/linear_solver.hpp"

#include <memory>
#include <string>
#include <vector>

namespace vpc {

struct DamageReport {
  bool converged = false;
  int iterations = 0;
  int n_lower = 0, n_upper = 0;  // nodes with β = 0, β = 1
  double kkt_residual = 0;       // relative natural KKT residual (box_qp_kkt_residual)
};

/// What failed in a damage solve judged against `tolerance`, for a failed step's message; empty
/// when it converged within it: the KKT residual (stationarity, bounds and complementarity of
/// the box QP together, box_qp_kkt_residual) against the tolerance, the iteration limit, or NaN/Inf.
std::string damage_failure(const DamageReport& r, double tolerance);

class DamageSolver {
 public:
  virtual ~DamageSolver() = default;
  /// rhs, β: owned entries. β is the warm start on entry and the solution, exactly
  /// in [0, 1], on exit. Collective.
  virtual DamageReport solve(const Vector& rhs, Vector& beta) = 0;
  virtual std::string name() const = 0;
  /// The owned nodes whose β stays as it is (lo = hi = β in the box; constant_damage_nodes in
  /// scheme/discrete_system.hpp): their β is no unknown. Empty (the default): none.
  void hold(std::vector<char> held) { held_ = std::move(held); }
  /// Internal warm-start state carried from step to step (penalty–duality's
  /// multiplier, this rank's owned entries: a node field; empty for the active-set
  /// method, whose warm start is the solution itself): saved in checkpoints so that
  /// a resumed run is bit-identical.
  virtual Vector warm_state() const { return {}; }
  virtual void set_warm_state(const Vector&) {}
  /// Sparse factorizations done so far (constant-matrix factor plus reduced ones).
  virtual int n_factorizations() const = 0;
  /// Memory held by its factors (bytes).
  virtual double factor_bytes() const = 0;

 protected:
  /// The box of (3.8), [0, 1] at each node, the point {β_i} at a held node.
  void bounds(const Vector& beta, Vector& lo, Vector& hi) const;
  /// The report's n_lower and n_upper: the nodes with β = 0 and β = 1 exactly, over every rank.
  static void count_bounds(const Vector& beta, const la::Comm& comm, DamageReport& r);

 private:
  std::vector<char> held_;
};

/// H: the assembled operator (owned rows of this rank), `make_factor` a backend's
/// factors (la/): the same algorithms on one process and on many. "active-set"
/// (primal–dual active set, factor of H cached; reduced systems by `reduced`, see
/// ReducedSolve) or "penalty-duality" (Bermúdez–Moreno, factor of H + ωI). `kappa_at`:
/// where κ is given ("case.toml:9:1: damage.kappa", "--set damage.kappa=1e300"), which
/// an H that k κ has made singular names. Collective.
std::unique_ptr<DamageSolver> make_damage_solver(const std::string& name, std::unique_ptr<la::SpdOperator> H,
                                                 const la::LinearSolverFactory& make_factor,
                                                 ReducedSolve reduced = ReducedSolve::automatic,
                                                 const std::string& kappa_at = "[damage] kappa",
                                                 double tolerance = 1e-13, int max_iterations = 200000);
/// One process: H in Eigen, CHOLMOD.
std::unique_ptr<DamageSolver> make_damage_solver(const std::string& name, const SparseMatrix& H,
                                                 double tolerance = 1e-13, int max_iterations = 200000,
                                                 ReducedSolve reduced = ReducedSolve::automatic);

}  // namespace vpc
