#pragma once
// A friction law on Γ3 (SPEC §7): the bound of a contact node's tangential force,
//     |λ_τ,i|_C ≤ s_i = min(g_τ(x_i, t) |Γ3|_i + μ(x_i) λ_ν,i, τ_max(x_i) |Γ3|_i),
// Tresca (a given bound g_τ, a traction) or Coulomb (μ times the normal force of the same
// step, capped by a shear limit τ_max where given). Below the bound the node sticks (its slip
// increment Δu_τ vanishes), at it it slips along the normal of the law's set C_s = {|λ_τ|_C ≤ s}
// (the friction force on the body, −λ_τ, opposes the slip; for Coulomb and Tresca C_s is the
// disc |λ_τ| ≤ s and the slip is along λ_τ). The normal part is the node's ContactLaw.
//
// A law is a per-node block (../shared/STYLE.md, "contact laws"): the solvers ask it for its
// set's gauge |·|_C, the dual gauge of a slip, and the Euclidean projection onto C_s with its
// derivative (Alart–Curnier's λ_τ = P_{C_s}(λ_τ + ρ Δ)), and never which law it is. Registered
// by name (friction_law.cpp's table, or register_friction_law); [contact] friction = "coulomb" |
// "tresca" | "none".
#include "contact/contact_law.hpp"
#include "core/sym_tensor.hpp"

#include <algorithm>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace vpc {

/// A contact node's bound, lumped at the node by its law: Tresca's g_τ(x_i, t_n) |Γ3|_i and the shear
/// limit τ_max(x_i) |Γ3|_i as forces, Coulomb's μ(x_i).
struct FrictionBound {
  double tresca = 0, mu = 0;
  double limit = std::numeric_limits<double>::infinity();  // +∞: none
  /// s(λ_ν) = min(tresca + μ max(λ_ν, 0), limit): the one place the bound is written. `capped`
  /// (where given): the limit holds, so that s does not move with λ_ν.
  double at(double lambda_nu, bool* capped = nullptr) const {
    const double coulomb = tresca + mu * std::max(lambda_nu, 0.0);
    const bool at_limit = coulomb >= limit;
    if (capped) *capped = at_limit;
    return at_limit ? limit : coulomb;
  }
  /// The normal force at which the bound below the limit is s (μ > 0): at's inverse, (s − tresca)/μ.
  double normal_force_at(double s) const { return (s - tresca) / mu; }
};

/// A number or a formula of a case file's key, at a point and a time.
using LawField = std::function<double(const Point& x, double t)>;

/// The keys of a friction law's table: LawKeys plus fields (a number or a formula).
class FrictionKeys : public LawKeys {
 public:
  /// A required field: a number or a formula in x, y, z (and t where `time`); located errors.
  virtual LawField field(const std::string& key, bool time) = 0;
  /// Whether `key` is a plain number (then the law checks its value at once; a formula's values
  /// are checked at the nodes) and whether its formula uses t.
  virtual bool is_number(const std::string& key) = 0;
  virtual bool uses_time(const std::string& key) = 0;
};

/// The field of `key` (required; `what` names it in messages); a plain number is checked here to be
/// finite and >= 0 and `text` set to it ("(a formula)" for a formula, whose values the set-up checks
/// at the nodes).
LawField nonnegative_field(FrictionKeys& keys, const std::string& key, bool time, const std::string& what,
                           std::string& text);

class FrictionLaw : public SurfaceHistory {
 public:
  virtual ~FrictionLaw() = default;
  /// Its registry name ("coulomb") and one line for the run's header ("Coulomb friction mu = 0.3").
  virtual std::string name() const = 0;
  virtual std::string describe() const = 0;
  /// μ(x) ≥ 0: the share of the normal force in the bound (Coulomb; 0 for Tresca).
  virtual double coefficient(const Point& /*x*/) const { return 0; }
  /// g_τ(x, t) ≥ 0: the bound per unit of Γ3, a traction (Tresca; 0 for Coulomb), lumped at a
  /// node by its tributary measure.
  virtual double bound(const Point& /*x*/, double /*t*/) const { return 0; }
  /// Whether bound() changes in time (then it is evaluated at every step).
  virtual bool bound_moves() const { return false; }
  /// τ_max(x) > 0: a shear-stress limit (a traction) that caps Coulomb's bound, lumped at a node
  /// by its tributary measure: s_i = min(μ λ_ν,i, τ_max |Γ3|_i); +∞ where none.
  virtual double limit(const Point& /*x*/) const { return std::numeric_limits<double>::infinity(); }
  /// Whether limit() is finite somewhere (a law that has one).
  virtual bool has_limit() const { return false; }
  /// Whether its bound acts where λ_ν = 0 (Tresca's given bound acts on all of Γ3, in or out of
  /// contact: the runs count those nodes, ContactStatus::Open, and warn).
  virtual bool acts_out_of_contact() const { return false; }

  // The node's block: its set C_s = {λ_τ : |λ_τ|_C ≤ s} of tangential forces (t ≤ 2 numbers along the
  // node's tangents, ContactConstraints::T), convex, with 0 inside. The default is the disc of Coulomb
  // and Tresca (|·|_C the Euclidean norm); a law with another set overrides all five.
  /// |l|_C, the gauge of the set (C_s is {|l|_C ≤ s}).
  virtual double gauge(const double* l, int t) const;
  /// The dual gauge of a slip d: max over |l|_C ≤ 1 of l·d, so that l·d ≤ |l|_C |d|_C* with equality
  /// exactly where d lies in the normal cone of C_{|l|_C} at l (the slip-direction residual).
  virtual double dual_gauge(const double* d, int t) const;
  /// p = P(z), the Euclidean projection onto C_r of a z outside it (|z|_C > r ≥ 0).
  virtual void project(const double* z, int t, double r, double* p) const;
  /// P's derivative at a z outside C_s: ∂p/∂z (t × t, row-major: dp_dz[j t + l] = ∂p_j/∂z_l) and ∂p/∂s (t).
  virtual void project_derivative(const double* z, int t, double s, double* dp_dz, double* dp_ds) const;
  /// Whether C_s is the Euclidean disc (the default): its rows keep the solvers' own arithmetic (the primal's
  /// springs k(I − nnᵀ)) and the steps that use its geometry (the dual's slip before leaving contact, its radius).
  virtual bool disc() const { return true; }
};

/// The disc's law (Coulomb's and Tresca's set) for a node without a friction law: s = 0 there.
const FrictionLaw& disc_friction();

/// Coulomb: s_i = μ(x_i) λ_ν,i; key mu (a number or a formula in x, y, z; ≥ 0); with the key
/// shear_limit (τ_max > 0, a traction, a number or a formula in x, y, z) s_i = min(μ λ_ν,i,
/// τ_max |Γ3|_i): acting in contact only, unlike Tresca's bound.
class CoulombFriction final : public FrictionLaw {
 public:
  explicit CoulombFriction(FrictionKeys& keys);
  explicit CoulombFriction(double mu);
  std::string name() const override { return "coulomb"; }
  std::string describe() const override { return "Coulomb friction mu = " + text_; }
  double coefficient(const Point& x) const override { return mu_(x, 0.0); }
  double limit(const Point& x) const override {
    return limit_ ? limit_(x, 0.0) : std::numeric_limits<double>::infinity();
  }
  bool has_limit() const override { return static_cast<bool>(limit_); }

 private:
  LawField mu_, limit_;
  std::string text_;
};

/// Tresca: s_i = g_τ(x_i, t) |Γ3|_i; key friction_bound (a traction, a number or a formula in
/// x, y, z, t; ≥ 0).
class TrescaFriction final : public FrictionLaw {
 public:
  explicit TrescaFriction(FrictionKeys& keys);
  explicit TrescaFriction(double bound);
  std::string name() const override { return "tresca"; }
  std::string describe() const override { return "Tresca friction bound = " + text_; }
  double bound(const Point& x, double t) const override { return g_(x, t); }
  bool bound_moves() const override { return moves_; }
  bool acts_out_of_contact() const override { return true; }

 private:
  LawField g_;
  bool moves_ = false;
  std::string text_;
};

using FrictionLawFactory = std::function<std::shared_ptr<const FrictionLaw>(FrictionKeys&)>;
/// Adds a friction law under `name`; returns true, for a static initializer.
bool register_friction_law(const std::string& name, FrictionLawFactory make);
/// "none", "coulomb", "tresca", then the added ones.
std::vector<std::string> friction_law_names();
/// The law `name` with its keys (nullptr for "none"); throws vpc::Error listing the names for an unknown one.
std::shared_ptr<const FrictionLaw> make_friction_law(const std::string& name, FrictionKeys& keys);
/// The keys each friction law reads ("mu", "friction_bound"), for the messages of a key given to
/// the wrong law.
std::vector<std::string> friction_keys();
/// The keys the law `name` reads ({"mu"} for Coulomb; none for "none" or an unknown name): what
/// `--set contact.friction=...` drops of the old law.
std::vector<std::string> friction_law_keys(const std::string& name);

}  // namespace vpc
