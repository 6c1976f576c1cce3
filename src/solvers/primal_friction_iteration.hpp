#pragma once
// The primal contact solver with friction (issue 28; split out of primal_active_set.cpp in issue
// 49): HSW's semismooth Newton method on Coulomb's law (SPEC §7) as one iteration over the operator
// (PrimalOperator), the per-row tangential linearization (PrimalFriction, primal_friction.hpp) and
// Coulomb's bound in the matrix (CoulombCoupling), with the fallbacks that make it converge: monotone
// updates against cycling, the lagged bound with Anderson mixing, the secant step for c. Its tuning
// constants: primal_tuning.hpp.
#include "solvers/primal_active_set.hpp"
#include "solvers/primal_coupling.hpp"
#include "solvers/primal_friction.hpp"
#include "solvers/primal_operator.hpp"

#include <vector>

namespace vpc {

/// What friction adds to the operator's solves (its TangentialPart), owned by the frictional iteration.
struct FrictionalSolve final : TangentialPart {
  FrictionalSolve(const ContactConstraints& c, const Vector& diagonal, double force_tolerance)
      : friction(c, diagonal), force_tolerance(force_tolerance) {}
  PrimalFriction friction;   // the tangential linearization: stick set, slip forces and springs
  CoulombCoupling coupling;  // Coulomb's bound in the matrix, made at each solve
  const double force_tolerance;  // ContactSolverOptions::friction_tolerance
  double force_scale = 0;        // the iteration's force scale (the direct solver's GMRES target)
  double newton_target = 0;      // the next coupled correction's residual (of the force scale), at least
  bool couple = true;            // Coulomb's bound in Newton's step (else lagged one iterate)

  void constrain(std::vector<char>& fixed, std::vector<Eigen::Triplet<double>>& springs) const override;
  void spring_pattern(std::vector<Eigen::Triplet<double>>& springs) const override { friction.spring_pattern(springs); }
  bool keeps_factor() const override { return true; }
  la::Perturbation load(const PrimalOperator& op, const std::vector<char>& active, const Vector& b, Vector& rhs,
                        Vector& fixed_values) override;
  void weigh(Vector& rhs) const override;
  std::optional<Correction> correction(bool perturbed, bool tight, bool iterative) const override;
  bool law_determines(Eigen::Index i, const ContactConstraints& c) const override {
    return coupling.law_determines(i, c);
  }
  double law_normal_force(Eigen::Index i, const Vector& r, const ContactConstraints& c) const override {
    return CoulombCoupling::law_normal_force(i, r, friction, c);
  }

 private:
  Vector law_rhs_;  // the law rows' right-hand side, already over μ (CoulombCoupling::build)
};

class PrimalFrictionIteration final : public PrimalIteration {
 public:
  /// `force_tolerance`: ContactSolverOptions::friction_tolerance.
  PrimalFrictionIteration(const PrimalOperator& op, double force_tolerance);

  /// HSW's semismooth Newton method on Coulomb's law as one iteration. Each iterate solves with the
  /// normal set, the stick set and the slip rows' linearizations, Coulomb's bound μ λ_ν(w) coupled
  /// into the matrix at the slip rows in contact (CoulombCoupling); from its answer the normal set
  /// is updated as without friction, and the stick set and the slip directions by HSW's rule with
  /// the iterate's own bound tresca + μ (λ_ν + c (N u − g))₊. It is solved when both sets hold, the
  /// slip forces s n of the update equal the iterate's λ_τ to the friction tolerance of the force
  /// scale (max(‖QF‖∞, ‖λ_ν‖∞)), and the last solve's equilibrium residual is within the same
  /// tolerance. On an iterative solver the forces count as settled also when they stop contracting
  /// at its accuracy (below kNoiseCeiling and less than halved by a tight solve). (Until issue 28's
  /// fourth part the bound was an outer fixed point over Tresca problems: 4–5 tight solves a step
  /// for it alone, frictional foundation-3d on CG + GAMG.)
  /// Cycling: once a pair of sets comes back (ActiveSetHistory), updates turn monotone: every
  /// violated normal row is added and only the most negative force released (as without
  /// friction); every slip row that would stick sticks, but only the stick row furthest beyond its
  /// bound starts to slip; slip directions keep being updated. No convergence in `max_iterations`
  /// solves, or a coupled solve that fails (Coulomb's problem has no solution, or too large a μ):
  /// converged = false, the step fails (contact_failure) and the step control retries a smaller step.
  /// The arguments as ContactSolver::solve's; `warm`: the solver's last answers.
  ContactReport solve(PrimalOperator& op, PrimalWarmStart& warm, int max_iterations, const Vector& F, Vector& u,
                      Vector& lambda) override;
  int most_iterations() const override { return kPrimalFrictionMaxIterations; }

 private:
  /// How far Coulomb's bound moved (|G(s) − s|, largest) over the rows where it acts: the slip
  /// rows (their force is s n), and the stick rows that it could turn to slip (their |λ_τ|_C closer
  /// to s than the move). A stick row further inside its set sticks under either bound, and the
  /// Tresca problem's answer is then Coulomb's there whatever its s (frictional foundation-3d
  /// n = 10 on CG + GAMG, 100 steps, lagged bound: 5.1 → 4.8 solves a step while pressed).
  double bound_moved(const ContactConstraints& c, const Vector& coulomb_bound, const Vector& bound,
                     const Vector& tangential) const;
  /// HSW: Coulomb's bound tresca + μ (λ_ν + c_ν (N u − g))₊ on the normal set `in_contact` (λ_ν
  /// `normal` at the rows in contact; a row that enters gets its penetration's force). `held`: the
  /// normal set the iterate w was solved with (empty: none), whose rows have their λ_ν: a Signorini
  /// row N u = g by its constraint, not the round-off of g − α (g/α) that μ would multiply (μ = 1e8:
  /// 1e-8 of the bound), a compliant one its spring's force (or the law's, law_determines).
  static Vector hsw_bound(const PrimalOperator& op, const std::vector<char>& in_contact, const Vector& normal,
                          const Vector& w, const std::vector<char>& held = {});

  FrictionalSolve s_;                   // the friction the operator's solves take
  Vector forces_last_, forces_before_;  // this rank's λ_ν then λ_τ of the last two answers
};

}  // namespace vpc
