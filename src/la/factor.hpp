#pragma once
// A factorization (or a preconditioned iterative solver) of an SpdOperator:
// solve for one right-hand side or a block. The triangular halves of a Cholesky
// factor A = PᵀLLᵀP (forward(B) = L⁻¹PB, backward(Y) = PᵀL⁻ᵀY) are an optional
// capability: CHOLMOD has them, MUMPS and CG do not (has_halves()).
// Backends: make_cholmod_factor (serial, la/cholmod_solver.cpp) and
// make_petsc_factor (la/petsc.hpp: MUMPS, CG + GAMG, CG + hypre).
#include "la/linear_solver.hpp"
#include "la/operator.hpp"

#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace vpc::la {

class Factor {
 public:
  virtual ~Factor() = default;
  /// Factorizes A (kept by reference by iterative backends: A must outlive the
  /// next factorize). Throws vpc::Error naming `what` when it fails.
  virtual void factorize(const SpdOperator& A, const char* what) = 0;
  /// The factor's size from a symbolic analysis alone (a following factorize of
  /// the same A reuses it); nullopt where the backend cannot say (PETSc).
  virtual std::optional<FactorEstimate> analyze(const SpdOperator&, const char*) { return std::nullopt; }
  /// The coordinate (x, y or z) each owned row stands for, rows in blocks of `dim`
  /// per node: algebraic multigrid builds the rigid-body modes of elasticity from
  /// them. Before factorize; ignored by direct solvers.
  virtual void set_coordinates(const Eigen::VectorXd& /*coordinates*/, int /*dim*/) {}
  /// x = A⁻¹ b on the owned entries; x on entry is an iterative solver's initial guess.
  virtual void solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) const = 0;
  /// X = A⁻¹ B for a block of right-hand sides (owned rows).
  virtual Eigen::MatrixXd solve(const Eigen::MatrixXd& B) const = 0;
  virtual bool has_halves() const { return false; }
  /// Only when has_halves().
  virtual Eigen::MatrixXd forward(const Eigen::MatrixXd& B) const;
  virtual Eigen::MatrixXd backward(const Eigen::MatrixXd& Y) const;
  virtual int n_factorizations() const = 0;
  /// Memory held by the factor (bytes; 0 where the backend does not say).
  virtual double factor_bytes() const { return 0; }
};

/// Makes a backend's factor; `name` says which matrix ("H", "H_reduced": the PETSc
/// backend reads its options under the prefix vpc_<name>_).
using FactorFactory = std::function<std::unique_ptr<Factor>(const std::string& name)>;

/// CHOLMOD's supernodal Cholesky of a SparseOperator (one process), with halves.
std::unique_ptr<Factor> make_cholmod_factor(const std::string& name = "");

}  // namespace vpc::la
