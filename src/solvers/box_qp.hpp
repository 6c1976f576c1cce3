#pragma once
// Bound-constrained convex quadratic programs
//     min ½ xᵀHx − bᵀx   subject to  lo ≤ x ≤ hi   (hi may be +∞),
// solved exactly by the primal–dual active-set method (a semismooth Newton method
// on the KKT system). The damage inequality (3.8) is one (H = M + kκA, bounds
// [0, 1]); the dual of the contact inequality (3.9) is another (H = N K⁻¹ Nᵀ,
// bounds [0, ∞)). The operator hides how the reduced systems are solved.
//
// Written once for one process and for many (la/): vectors are a rank's owned
// entries, the active sets are local to each rank, and every decision (the sets
// repeat, the KKT residual, nothing fixed) is a reduction over the operator's
// communicator, trivial on one process. A dense operator is replicated: each
// rank solves the same small problem and needs no reduction.
#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <memory>
#include <string>
#include <vector>

#include "la/linear_solver.hpp"

namespace vpc {

class BoxQpOperator {
 public:
  virtual ~BoxQpOperator() = default;
  /// Where the entries live: one process unless a distributed operator says otherwise.
  virtual const la::Comm& comm() const;
  /// Entries on this rank.
  virtual int size() const = 0;
  virtual Vector multiply(const Vector& x) const = 0;
  virtual const Vector& diagonal() const = 0;
  /// Sets x_F = H_FF⁻¹ (b_F − H_FA x_A), with A = {i : fixed[i]} and x_A as given in x.
  virtual void solve_free(const std::vector<char>& fixed, const Vector& b, Vector& x) = 0;
};

/// H dense (small: the contact unknowns); reduced systems by dense Cholesky.
class DenseBoxQpOperator final : public BoxQpOperator {
 public:
  explicit DenseBoxQpOperator(Eigen::MatrixXd H);
  int size() const override { return static_cast<int>(H_.rows()); }
  Vector multiply(const Vector& x) const override { return H_ * x; }
  const Vector& diagonal() const override { return diag_; }
  void solve_free(const std::vector<char>& fixed, const Vector& b, Vector& x) override;
  const Eigen::MatrixXd& matrix() const { return H_; }
  /// H_kk += v (a step's compliance on one unknown: nothing is factored ahead of solve_free).
  void add_to_diagonal(Eigen::Index k, double v) {
    H_(k, k) += v;
    diag_[k] += v;
  }

 private:
  Eigen::MatrixXd H_;
  Vector diag_;
};

/// How SparseBoxQpOperator solves a reduced system H_FF x_F = b_F − H_FA x_A.
enum class ReducedSolve {
  /// Capacitance when its estimated cost for the active set at hand (forward
  /// solves for the new indices plus the dense a × a Cholesky) is below half the
  /// estimated cost of factorizing H (both from the factor's analysis: flops and
  /// entries, so that the choice is the same on every run), and its columns of Z
  /// fit in half the factor's memory; else the reduced factor.
  automatic,
  /// With the factor of the whole H = PᵀLLᵀP only: x = H⁻¹(b − Eμ), where E
  /// selects A and (EᵀH⁻¹E) μ = EᵀH⁻¹b − x_A; EᵀH⁻¹E = ZᵀZ with Z = L⁻¹PE, one
  /// forward solve per index that becomes active (cached), a dense a × a Cholesky
  /// per active set, and one solve (two halves) per reduced system.
  capacitance,
  /// Factorize H_FF whenever the active set changes (reused while it repeats).
  reduced_factor,
};

/// H sparse (an la::SpdOperator, serial or distributed) and constant over a run:
/// its factor is computed once; reduced systems use it (capacitance, when the
/// factor has triangular halves) or a factor of H_FF made when the active set changes.
class SparseBoxQpOperator final : public BoxQpOperator {
 public:
  /// `make_factor` makes the factors of H and of the H_FF (a backend's la::LinearSolver); `what`
  /// names H in their errors (e.g. the damage matrix).
  SparseBoxQpOperator(std::unique_ptr<la::SpdOperator> H, const la::LinearSolverFactory& make_factor,
                      ReducedSolve method = ReducedSolve::automatic, std::string what = "box QP matrix");
  /// One process: H in Eigen, factors by CHOLMOD.
  explicit SparseBoxQpOperator(SparseMatrix H, ReducedSolve method = ReducedSolve::automatic);
  const la::Comm& comm() const override { return H_->comm(); }
  int size() const override { return H_->n_owned(); }
  Vector multiply(const Vector& x) const override {
    Vector y;
    H_->mult(x, y);
    return y;
  }
  const Vector& diagonal() const override { return diag_; }
  void solve_free(const std::vector<char>& fixed, const Vector& b, Vector& x) override;
  /// Factorizations done (full + reduced), for reports.
  int n_factorizations() const { return full_->n_factorizations() + reduced_->n_factorizations(); }
  double factor_bytes() const { return full_->factor_bytes() + reduced_->factor_bytes(); }
  /// The automatic choice's cost model: the seconds of factorizing H and of one
  /// forward solve (from the factor's analysis at 10⁹ flop/s; tests set other values).
  void set_costs(double seconds_factor, double seconds_forward) {
    seconds_factor_ = seconds_factor;
    seconds_forward_ = seconds_forward;
  }
  /// Reduced systems solved so far by each method (for tests and benchmarks).
  int n_capacitance_solves() const { return n_capacitance_; }
  int n_reduced_factor_solves() const { return n_reduced_factor_; }

 private:
  bool use_capacitance(const std::vector<int>& active);
  void solve_capacitance(const std::vector<int>& active, const Vector& b, Vector& x);
  void solve_reduced_factor(const std::vector<char>& fixed, const Vector& b, Vector& x);

  std::unique_ptr<la::SpdOperator> H_, HFF_;
  std::string what_, what_reduced_;  // the factors keep the names' pointers
  Vector diag_;
  ReducedSolve method_;
  std::unique_ptr<la::LinearSolver> full_, reduced_;
  std::vector<char> reduced_mask_;
  std::vector<int> free_ids_;
  // Capacitance: columns L⁻¹P e_i of the indices active so far, and the Cholesky
  // factor of ZᵀZ for the current active set.
  std::vector<Eigen::SparseVector<double>> z_columns_;  // by index; empty until needed
  std::vector<char> has_z_;
  double z_bytes_ = 0;
  double seconds_factor_ = 0, seconds_forward_ = 0;  // measured: factor of H, one forward solve
  std::vector<int> capacitance_set_;
  SparseMatrix Z_;
  Eigen::LLT<Eigen::MatrixXd> C_;
  int n_capacitance_ = 0, n_reduced_factor_ = 0;
};

struct BoxQpResult {
  bool converged = false;
  int iterations = 0;            // reduced solves done (0: the warm start was already optimal)
  int n_lower = 0, n_upper = 0;  // indices at their bounds
  double kkt_residual = 0;       // box_qp_kkt_residual of the returned x
  int cycles = 0;                // active sets that came back (then the updates were monotone)
};

/// Primal–dual active-set method, warm-started from x (projected onto the box).
/// Converges when the active sets repeat, or when x satisfies KKT to round-off
/// (box_qp_kkt_residual ≤ 1e-14; this also ends round-off cycling at degenerate
/// bounds); x then lies exactly in the box. An index with lo = hi is held there from the
/// first iteration: it is no unknown, and round-off would flip it between its two bounds.
/// Returns converged = false after max_iterations.
BoxQpResult solve_box_qp(BoxQpOperator& H, const Vector& b, const Vector& lo, const Vector& hi,
                         Vector& x, int max_iterations = 200);

/// Relative natural residual of the KKT conditions, ‖x − P(x + D⁻¹(b − Hx))‖∞ / scale,
/// D = diag(H), P the projection onto the box, scale = max(‖x‖∞, ‖D⁻¹b‖∞). It is zero
/// iff x solves the QP; it also measures bound violation. Collective over H.comm().
double box_qp_kkt_residual(const BoxQpOperator& H, const Vector& b, const Vector& lo, const Vector& hi,
                           const Vector& x);
/// The same residual from Hx and diag(H) (this rank's entries; maxima over `comm`).
double box_qp_kkt_residual(const Vector& Hx, const Vector& diag, const Vector& b, const Vector& lo,
                           const Vector& hi, const Vector& x, const la::Comm& comm = {});

}  // namespace vpc
