#pragma once
// A normal contact law on Γ3 (SPEC §6) as one object: what the contact solvers ask of a
// contact node, whatever the law. The node's block of unknowns (1 for every normal law:
// the normal force λ_i; friction, issue 28, adds d − 1 tangential ones), its complementarity
// (the gap left s = g − N u + δ(λ) ≥ 0, ⟂ λ ≥ 0), the force law of a compliant node for the
// dual Newton and its linearization for the primal semismooth Newton, and its dual set.
//
// A law's parameters are per unit of Γ3 (c: a pressure per unit of penetration^e); at a
// node they are lumped by the law itself into the law's per-node datum (lumped(): its share of
// one facet, summed over the node's facets; k_i = c |Γ3|_i for normal compliance, nothing for
// Signorini), whose meaning the law alone knows: the solvers ask it for the node's compliance
// and dual bound at the datum. Registered by name in contact/registry.cpp.
#include "contact/surface_state.hpp"

#include <limits>
#include <memory>
#include <string>

namespace vpc {

/// The keys of one law's table in a case file ([contact] or a [[contact.part]]): a law reads
/// its own keys through it, and its errors are located like every other key's.
class LawKeys {
 public:
  virtual ~LawKeys() = default;
  virtual bool has(const std::string& key) = 0;
  /// A required number: a located error when it is missing or not a number.
  virtual double number(const std::string& key) = 0;
  virtual double number(const std::string& key, double fallback) = 0;
  /// "case.toml:9:1: contact.stiffness": where a key is, for a law's own messages.
  virtual std::string where(const std::string& key) = 0;
};

class ContactLaw : public SurfaceHistory {
 public:
  virtual ~ContactLaw() = default;
  /// Its registry name ("signorini") and one line for the run's header ("normal compliance c = 100").
  virtual std::string name() const = 0;
  virtual std::string describe() const = 0;
  /// What it is, in words, for a solver that cannot solve it ("a power-law compliance").
  virtual std::string kind() const = 0;
  /// Contact unknowns per node in a body of dimension `dim` (State::contact_block): 1 for a normal law.
  virtual int block_size(int /*dim*/) const { return 1; }

  /// Signorini (k = ∞): λ ⟂ g − N u ≥ 0, no compliance; it wins at a node that also has a compliant facet.
  virtual bool rigid() const { return false; }
  /// λ = k d₊ with d = N u − g: the dual is the box QP with S + diag(1/k) and the primal
  /// semismooth Newton puts a spring of k on an active node. A law that is not linear says so:
  /// the dual solves it with solve_compliance_dual's Newton, the primal refuses it.
  virtual bool linear() const { return true; }

  /// The per-node datum's share of one facet of Γ3 (measure |f|, `nodes` nodes), summed over the
  /// node's facets (ContactRow::datum): c |f| / nodes for normal compliance (k_i), 0 for Signorini.
  virtual double lumped(double /*facet_measure*/, int /*nodes*/) const { return 0; }
  /// Why a node cannot carry this law and `other` together (facets of both meet there), or
  /// empty when it can (then the datum sums both shares and the node takes this law). Asked
  /// both ways, of two compliant laws or of two rigid ones (a rigid one wins over a compliant one).
  virtual std::string conflict(const ContactLaw& /*other*/) const { return {}; }
  /// A node's compliance 1/k_i from its datum: by default a compliant law's datum is its k_i; a
  /// rigid law has none (0).
  virtual double compliance(double datum) const { return !rigid() && datum > 0 ? 1 / datum : 0.0; }

  /// The gap left s from s0 = g − N u at the force λ, for a node of compliance 1/k: s0 + δ(λ),
  /// δ the penetration the law gives at λ (the contact residuals' complementarity, λ ⟂ s ≥ 0).
  virtual double gap_left(double s0, double /*lambda*/, double /*compliance*/) const { return s0; }
  /// The force at the penetration d = N u − g and its slope dλ/dd (the dual Newton's row
  /// λ − λ(d) = 0 and its Jacobian); not asked of a rigid law.
  virtual double force(double /*d*/, double /*compliance*/) const { return 0; }
  virtual double force_slope(double /*d*/, double /*compliance*/) const { return 0; }
  /// The spring's compliance 1/k a linear law puts on an active node (the primal semismooth
  /// Newton: λ = (N u − g) / it where the node penetrates) and the diagonal it adds to the dual's S.
  virtual double spring_compliance(double compliance) const { return compliance; }

  /// The dual set of the node's force at its datum: λ ≥ lower (0 for the shipped normal laws; an
  /// adhesive law's −a_i lets a node carry a tension; a friction law's disc is a block's set, issue 28).
  /// The complementarity is then (λ − lower) ⟂ s ≥ 0.
  virtual double dual_lower(double /*datum*/) const { return 0; }
  virtual double dual_upper() const { return std::numeric_limits<double>::infinity(); }
};

/// The paper's law: Signorini (also the default of [contact]).
std::shared_ptr<const ContactLaw> signorini_law();

}  // namespace vpc
