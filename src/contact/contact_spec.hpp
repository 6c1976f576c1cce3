#pragma once
// The case's contact specification (SPEC §2's Γ3, §6's obstacles, §7's friction, §8's pairs):
// the normal and friction law of each entry ([contact], each [[contact.part]], each
// [[contact.pair]]), the gap or the obstacles, and the contact direction. The case file fills
// it (io/case_contact.cpp); the contact rows (problem/contact_rows.hpp) are built from it.
#include "contact/adhesion_law.hpp"
#include "contact/contact_law.hpp"
#include "contact/friction_law.hpp"
#include "contact/obstacle.hpp"
#include "contact/wear_law.hpp"
#include "fem/assembly.hpp"
#include "mesh/mesh.hpp"
#include "mesh/mesh_block.hpp"

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace vpc {

/// A contact law on some parts of Γ3, instead of ContactSpec::law.
struct PartContactLaw {
  std::vector<std::string> parts;
  std::shared_ptr<const ContactLaw> law;
  /// Its friction (SPEC §7; contact/friction_law.hpp): nullptr frictionless. A [[contact.part]]
  /// without a friction key takes [contact]'s.
  std::shared_ptr<const FrictionLaw> friction;
  /// Its wear (SPEC §9; contact/wear_law.hpp): nullptr none. Without a wear key, [contact]'s.
  std::shared_ptr<const ArchardWear> wear;
  /// Its adhesion (SPEC §9; contact/adhesion_law.hpp): nullptr none. Without an adhesion key, [contact]'s.
  std::shared_ptr<const FremondAdhesion> adhesion;
};

/// Contact between two bodies (SPEC §8, `[[contact.pair]]`): a normal law for the jump of u across
/// a slave and a master part, by dual mortar (mortar/, problem/contact_pairs.hpp), the gap measured
/// from the slave side along its nodal normals in the reference configuration.
struct ContactPair {
  std::string slave, master;  // boundary parts of two different bodies
  double search = 0;          // facets this far apart still couple (0: the slave part's longest facet)
  std::shared_ptr<const ContactLaw> law;  // its normal law (the pair's `law`; nullptr: [contact]'s)
  /// Its friction (SPEC §7 across the pair: the slip is the slave's relative to the master side's
  /// mortar mean); nullptr frictionless. A pair without a friction key takes [contact]'s.
  std::shared_ptr<const FrictionLaw> friction;
  /// Its wear, of the slave side (SPEC §9); nullptr none. A pair without a wear key takes [contact]'s.
  std::shared_ptr<const ArchardWear> wear;
  /// Its adhesion, on the slave side's rows (SPEC §9); nullptr none. A pair without an adhesion key takes [contact]'s.
  std::shared_ptr<const FremondAdhesion> adhesion;
  /// `sliding = "large"`: the pair's rows rebuilt at the start of every step in the configuration
  /// x + u_{n−1} (scheme/pair_slider.hpp); "small" (the default): once, in the reference one.
  bool large_sliding = false;
};

struct ContactSpec {
  std::vector<std::string> parts;    // Γ3
  std::vector<ContactPair> pairs;    // between bodies
  ScalarField gap;                   // g(x, t), measured along the contact direction; g(x, 0) ≥ 0
  bool gap_moves = false;            // g depends on t (a moving obstacle): evaluated at every step
  /// The normal law (contact/contact_law.hpp) on the parts of Γ3 that no part_laws entry names.
  std::shared_ptr<const ContactLaw> law = signorini_law();
  std::vector<PartContactLaw> part_laws;
  /// The friction law on the parts of Γ3 that no part_laws entry names (nullptr: frictionless, the paper's (2.6)).
  std::shared_ptr<const FrictionLaw> friction;
  /// Every law: `law`, then part_laws' in order, then each pair's (ContactRow::law and
  /// PartContactNode::law index it).
  std::vector<std::shared_ptr<const ContactLaw>> laws() const;
  /// Every friction law, in the order of laws() (nullptr: that entry is frictionless).
  std::vector<std::shared_ptr<const FrictionLaw>> frictions() const;
  bool frictional() const;
  /// The wear on the parts of Γ3 that no part_laws entry names (SPEC §9; nullptr: none).
  std::shared_ptr<const ArchardWear> wear;
  /// Every wear law, in the order of laws() (nullptr: that entry does not wear).
  std::vector<std::shared_ptr<const ArchardWear>> wears() const;
  /// The adhesion on the parts of Γ3 that no part_laws entry names (SPEC §9; nullptr: none), and every
  /// entry's, in the order of laws() (nullptr: that entry does not bond).
  std::shared_ptr<const FremondAdhesion> adhesion;
  std::vector<std::shared_ptr<const FremondAdhesion>> adhesions() const;
  /// Whether some entry's law keeps a bond (SurfaceHistory::bond_length > 0: adhesion), and whether some
  /// entry's adhesion has a tangential part (FremondAdhesion::shears: then the rows carry tangents).
  bool adhesive() const;
  bool shear_bonded() const;
  /// `held_by_bond = true`: the bonds on Γ3 hold the bodies that the prescribed displacements leave free
  /// (check_body_held); K is then singular, the primal solver factors it with the bonds' springs, and a
  /// step whose load the remaining bonds cannot hold fails as a pull-off (SPEC §9).
  bool held_by_bond = false;
  /// Whether the contact nodes carry tangential unknowns and slip (the friction frame, State::slip):
  /// friction somewhere, or wear, which needs the slip (a node without friction has the bound 0).
  bool tangential() const;
  /// The laws of laws() entry e that may keep per-node state (contact/surface_state.hpp): its normal
  /// law, its friction law, its wear and its adhesion, those it has.
  std::vector<const SurfaceHistory*> surface_laws(std::size_t e) const;
  /// The index in laws() of the law on one part of Γ3.
  int law_index(const std::string& part) const;
  /// The indices in `pairs` of those with `sliding = "large"` (true) or "small" (false): the one
  /// place that tells them apart.
  std::vector<std::size_t> sliding_pairs(bool large) const;
  /// Whether spreading the pairs' rows over the ranks (--spread-pairs: `asked`) spreads anything:
  /// the one place that says so (the plan, the PETSc engine's refusal and the partition).
  bool spreads_pairs(bool asked) const { return asked && !pairs.empty(); }
  /// The case table of laws() entry e: "contact", "contact.part[k]" or "contact.pair[q]" (Problem::where
  /// locates its keys).
  std::string entry_table(std::size_t e) const;
  /// The index in laws() of pair q's law.
  int pair_law_index(std::size_t q) const { return static_cast<int>(1 + part_laws.size() + q); }
  /// Contact unknowns per node (State::contact_block): the largest ContactLaw::block_size, or
  /// `dim` (λ_ν and d − 1 tangential forces) with friction or wear on some part (tangential()).
  int block_size(int dim) const;
  /// What a run prints of contact: Γ3's parts with their laws ([contact]'s, then each
  /// [[contact.part]]'s) if any, then each pair with its normal law, friction and sliding.
  std::vector<std::string> describe() const;
  /// Rigid obstacles instead of `gap`: g is the distance along ν to the nearest one, at every step.
  std::vector<Obstacle> obstacles;
  std::optional<Point> direction;    // a fixed direction, < 90° from the outward normal; unset: the normal
};

/// g finite and ≥ 0 at every node of Γ3.
void check_gap(const Mesh& mesh, const ContactSpec& contact, const MeshBlock* block = nullptr);

/// g at a contact node x with direction ν at time t: the gap formula, or the distance
/// to the nearest obstacle of the mask (those acting on the node's parts) (`miss` where every ray misses: see contact_miss_gap).
double contact_gap_at(const ContactSpec& contact, const Point& x, const Point& nu, double t, double miss,
                      ObstacleMask obstacles = kAllObstacles);
/// The gap of a node that no obstacle lies ahead of: the diagonal of the body's
/// bounding box [lo, hi], farther than any small-deformation displacement reaches.
double contact_miss_gap(const Point& lo, const Point& hi);

}  // namespace vpc
