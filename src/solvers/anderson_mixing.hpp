#pragma once
// Anderson acceleration of a fixed point over vectors distributed like the contact rows.
#include "la/comm.hpp"
#include "la/linear_solver.hpp"  // Vector

#include <vector>

namespace vpc {

/// Anderson acceleration (type II; Walker & Ni, SIAM J. Numer. Anal. 49, 2011) of a fixed point
/// x = G(x) over vectors distributed like the contact rows: from the last `depth` iterates, the
/// combination of the G(x_k) whose residuals G(x_k) − x_k combine to the least norm. Coulomb's bound
/// s = tresca + μ λ_ν(s) over Tresca problems: a plain iteration contracts only by μ times the
/// coupling of tangential to normal forces, and not at all where that exceeds 1 (a sheared block
/// whose tangential forces tilt it: measured ratio ≈ −0.95 at μ = 1); a linear map's fixed point it
/// finds as GMRES would (in at most as many steps as unknowns). Collective.
class AndersonMixing {
 public:
  explicit AndersonMixing(int depth) : depth_(depth) {}
  Vector next(const la::Comm& comm, const Vector& x, const Vector& g);

 private:
  int depth_;
  std::vector<Vector> dx_, df_;  // differences of the iterates and of their residuals
  Vector x_last_, f_last_;
  bool have_last_ = false;
};

}  // namespace vpc
