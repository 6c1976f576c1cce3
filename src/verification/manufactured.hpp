#pragma once
// Manufactured solutions for Problem 2.1 on the unit box (0, 1)^d, d = 1, 2, 3.
//
// Γ1 (clamped) is the side x1 = 0 ("left"), Γ3 (contact, gap 0.5 along +e1) the side
// x1 = 1 ("right"), Γ2 every other side (none in 1D). A smooth triple (u, z, β) is
// chosen with u(0) = 0, z(0) = 0 (the scheme's u0 = σ0 = 0), u = 0 on x1 = 0,
// ∇u = 0 and z = 0 on x1 = 1 (so σν = 0 there: the contact constraint is present but
// inactive, u_ν ≤ 0.02 < g), ∂β/∂ν = 0 on the whole boundary (2.7) and
// 0.3 ≤ β ≤ 0.9 (the bounds of K are inactive). σ = ℰε(u) + z. The data that make it
// exact are
//   f0 = −Div σ,   f2 = σν on Γ2,   β0 = β(·, 0),
//   G_m = G(σ, ε(u), β) + g_m(x, t)   with g_m = ż − G(σ, ε(u), β),
//   φ_m = φ(σ, ε(u), β) + s_m(x, t)   with s_m = β̇ − κΔβ − φ(σ, ε(u), β),
// all evaluated on the exact fields. The scheme evaluates G_m and φ_m per element at
// the centroid and at t_{n−1} (PointState::x, t), like any law.
//
// Two choices of the source terms (ManufacturedForcing):
//  - continuous: g_m and s_m as above, pointwise in t. The exact solution then solves
//    the continuous problem, and the fully discrete error is O(h + k).
//  - discrete (time-consistent): g_m(x, t_{n−1}) = (z(t_n) − z(t_{n−1}))/k − G(t_{n−1}),
//    s_m(x, t_{n−1}) = (β(t_n) − β(t_{n−1}))/k − κΔβ(t_n) − φ(t_{n−1}). The exact
//    solution sampled at t_n then solves the time-discrete scheme of SPEC §2 (G and φ
//    lagged, backward Euler for β, z_n = z_{n−1} + k G_{n−1}, equilibrium at t_n)
//    exactly, so the fully discrete error is the spatial error alone: O(h) in energy
//    and L2(σ), O(h²) in L2(u) and L2(β), at any k. A scheme that lags G or φ
//    differently leaves an O(k) error floor, which a fixed-k h-study detects.
// With the elastic law (G = 0) z = 0 and g_m = 0.
#include "problem/problem.hpp"
#include "verification/dual.hpp"
#include "verification/norms.hpp"

#include <array>
#include <memory>
#include <string>

namespace vpc {

enum class ManufacturedForcing { Continuous, Discrete };

/// The exact fields as templates of the scalar type; X = (x1, x2, x3, t).
template <typename S>
struct ManufacturedValues {
  std::array<S, 3> u{};
  std::array<S, 6> z{};  // SymTensor order 11, 22, 33, 23, 13, 12
  S beta{};
};

struct ManufacturedOptions {
  int dim = 2;
  /// Base law G: "elastic" (z = 0), "maxwell-damage" (4.8), "perzyna" (4.2, E = 1,
  /// λ = 1, σ_Y = 0.05: yielding in part of the body) or "perzyna-von-mises" (the same
  /// with the von Mises norm).
  std::string law = "maxwell-damage";
  /// d = 2: plane strain instead of plane stress; z (and σ) then has a 33 component
  /// (z33 = 0.02 r (1 + y)), which G evolves.
  bool plane_strain = false;
  /// Base damage source φ: "strain" (φ = −2 tr ε) or "zero".
  std::string source = "strain";
  int cells = 2;  // cells per edge of the base mesh
  int n_steps = 4;
  double final_time = 1;
  double kappa = 1;
  ManufacturedForcing forcing = ManufacturedForcing::Continuous;
};

/// The manufactured solution: exact fields and their derivatives, and the data
/// (f0, f2, β0, G_m, φ_m) that make them solve Problem 2.1.
class ManufacturedSolution final : public ExactSolution {
 public:
  ManufacturedSolution(int dim, bool with_history, const Elasticity& elasticity, double kappa);

  int dim() const { return dim_; }
  Point u(const Point& x, double t) const override;
  std::array<Point, 3> grad_u(const Point& x, double t) const override;
  SymTensor sigma(const Point& x, double t) const override;
  double beta(const Point& x, double t) const override;
  Point grad_beta(const Point& x, double t) const override;
  /// All values from d evaluations of the fields with dual numbers.
  Values values(const Point& x, double t) const override;

  SymTensor eps(const Point& x, double t) const;
  SymTensor z(const Point& x, double t) const;
  /// ∂z/∂t, ∂β/∂t, Δβ.
  SymTensor z_dot(const Point& x, double t) const;
  double beta_dot(const Point& x, double t) const;
  double laplacian_beta(const Point& x, double t) const;
  /// The body force f0 = −Div σ.
  Point body_force(const Point& x, double t) const;
  /// σν with ν the outward normal of the unit box at boundary point x.
  Point traction(const Point& x, double t) const;
  /// What a law sees at (x, t) on the exact fields (β exact at x).
  PointState exact_state(const Point& x, double t) const;

  double kappa() const { return kappa_; }
  const Elasticity& elasticity() const { return elasticity_; }

  /// The fields themselves (for tests of the derivatives).
  template <typename S>
  ManufacturedValues<S> fields(const std::array<S, 4>& X) const;

 private:
  int dim_;
  bool with_history_;
  Elasticity elasticity_;
  double kappa_;
};

/// G + g_m: the base law plus the manufactured history source (see the file comment).
class ManufacturedLaw final : public ViscoplasticLaw {
 public:
  ManufacturedLaw(std::shared_ptr<const ViscoplasticLaw> base, std::shared_ptr<const ManufacturedSolution> exact,
                  ManufacturedForcing forcing, double k);
  SymTensor rate(const PointState& s) const override;
  /// g_m(x, t) alone.
  SymTensor forcing(const Point& x, double t) const;
  std::string describe() const override;
  /// The base law's: g_m(x, t) does not depend on σ.
  Lipschitz lipschitz(double beta) const override { return base_->lipschitz(beta); }

 private:
  std::shared_ptr<const ViscoplasticLaw> base_;
  std::shared_ptr<const ManufacturedSolution> exact_;
  ManufacturedForcing forcing_;
  double k_;
};

/// φ + s_m: the base damage source plus the manufactured one.
class ManufacturedSource final : public DamageSource {
 public:
  ManufacturedSource(std::shared_ptr<const DamageSource> base, std::shared_ptr<const ManufacturedSolution> exact,
                     ManufacturedForcing forcing, double k);
  double rate(const PointState& s) const override;
  /// s_m(x, t) alone.
  double forcing(const Point& x, double t) const;
  std::string describe() const override;

 private:
  std::shared_ptr<const DamageSource> base_;
  std::shared_ptr<const ManufacturedSolution> exact_;
  ManufacturedForcing forcing_;
  double k_;
};

/// The manufactured case on `mesh` (a refinement of the unit box) with N steps.
struct ManufacturedCase {
  std::shared_ptr<Problem> problem;
  std::shared_ptr<const ManufacturedSolution> exact;
};
ManufacturedCase make_manufactured_case(const ManufacturedOptions& o, const Mesh& mesh, int n_steps);
/// The base mesh of the unit box with o.cells cells per edge (sides tagged as in
/// mesh/generators.hpp).
Mesh manufactured_base_mesh(const ManufacturedOptions& o);

/// "mms-elastic-2d" and the like: mms-<law>-<d>d with law elastic, maxwell, perzyna,
/// perzyna-von-mises, or mms-<law>-2d-plane-strain.
bool is_manufactured_case_name(const std::string& name);
/// Options for such a name (throws vpc::Error for a malformed one).
ManufacturedOptions manufactured_options_from_name(const std::string& name);
ManufacturedForcing manufactured_forcing_from_name(const std::string& name);
std::string to_string(ManufacturedForcing f);

}  // namespace vpc
