#pragma once
// Everything that defines one instance of Problem 2.1 and its discretization:
// mesh and boundary parts, ℰ, G, φ, κ, loads, gap, initial damage and times.
// Case files (cases/*.toml included) and the manufactured cases fill it.
#include "contact/contact_spec.hpp"
#include "contact/shared_contact_rows.hpp"
#include "fem/assembly.hpp"
#include "material/damage_source.hpp"
#include "material/elasticity.hpp"
#include "material/viscoplastic_law.hpp"
#include "mesh/mesh.hpp"
#include "mesh/mesh_block.hpp"
#include "problem/time_grid.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace vpc {

class Expression;

/// A normal pressure p(x, t) on boundary parts: the traction −p n with n the outward
/// normal of the reference configuration (small deformations: not a follower load).
struct PressureLoad {
  std::vector<std::string> parts;
  ScalarField p;
};

/// Prescribed displacement components on boundary parts (SPEC §6): u_i = value[i](x, t)
/// for every component i that has a value; the others stay free (or in contact).
struct PrescribedDisplacement {
  std::vector<std::string> parts;
  std::array<ScalarField, 3> value;  // empty: the component is free
};

/// A material of the body (SPEC §6): ℰ, G and φ on the cells of its mesh regions.
struct Material {
  std::string name;
  std::vector<std::string> regions;  // Mesh regions (Gmsh physical groups of dimension d, or `where` predicates)
  Elasticity elasticity{Elasticity::Kind::Uniaxial, 1.0, 0.0};
  std::shared_ptr<const ViscoplasticLaw> law;
  std::shared_ptr<const DamageSource> source;
};

/// A further body (SPEC §8, `[[body]]`): the cells whose Mesh::cell_body is k ≥ 1 are body k's
/// (body 0 is the case's [mesh], whose data are Problem's own). Bodies share no node, so no
/// damage flux crosses from one to another; each has its own κ and β0.
struct Body {
  std::string name;
  double kappa = 1;
  ScalarField beta0;  // empty: β0 = 1
  /// ℰ, G, φ of its cells that no [[material]] region takes (named as the body).
  Material material;
};

struct Problem {
  std::string name;
  Mesh mesh;
  /// Where `mesh` is this rank's block of a generated mesh, not the whole (issue 30): what
  /// it is a block of. Checks that need the whole mesh (a part that exists somewhere, the
  /// body held) are then made by all ranks together (parallel/block_part.hpp).
  std::shared_ptr<MeshBlock> block;
  /// Node i of `mesh` as messages name it: its number in the whole mesh (not a block's own).
  long long node_number(int i) const { return vpc::node_number(block.get(), i); }
  std::vector<std::string> clamped;   // Γ1: every component zero (may be empty when `displacement` or `symmetry` holds the body)
  std::vector<PrescribedDisplacement> displacement;
  /// Symmetry planes (rollers): parts lying in a plane x_i = const, whose normal component u_i is zero.
  std::vector<std::string> symmetry;
  std::vector<std::string> traction;  // Γ2; empty: every boundary facet not in Γ1 or Γ3
  ContactSpec contact;
  Elasticity elasticity{Elasticity::Kind::Uniaxial, 1.0, 0.0};
  std::shared_ptr<const ViscoplasticLaw> law;
  std::shared_ptr<const DamageSource> source;
  /// Further materials on the cells of their regions; every other cell has ℰ, G, φ
  /// above (the body's material). One damage field β over the whole body, one κ.
  std::vector<Material> materials;
  double kappa = 1;  // damage diffusion κ in (2.2) (of body 0)
  /// Further bodies (`[[body]]`): bodies[k − 1] is body k of Mesh::cell_body.
  std::vector<Body> bodies;
  VectorField f0, f2;
  /// f0 (f2) does not depend on x: its load vector is f(t) times the integrals of
  /// the basis functions, computed once, instead of a quadrature at every step.
  bool f0_uniform = false, f2_uniform = false;
  std::vector<PressureLoad> pressure;  // on parts outside Γ1 and Γ3, added to any f2 there
  ScalarField beta0;  // initial damage β0(x) in [0, 1]; u0 = 0, σ0 = 0
  double final_time = 1;
  int n_steps = 100;  // N of a fixed grid (k = T / N when step_times is empty); 0 with step_control
  /// A fixed non-uniform grid t_1 < … < t_N = T (problem/time_grid.hpp); empty: uniform, t_n = n T / N.
  std::vector<double> step_times;
  /// Its step sizes k_n (t_n − t_{n−1} to round-off; empty: those differences).
  std::vector<double> step_sizes;
  /// Error-controlled steps instead of a fixed grid (completed: StepControl::completed).
  std::optional<StepControl> step_control;
  /// Where a case file gives the keys that the checks across keys name, by key path
  /// ("boundary.contact" -> "case.toml:9:1: boundary.contact"); filled by the case reader.
  std::map<std::string, std::string> key_locations;
  /// The formulas whose values reach the state (loads, prescribed displacements, the gap,
  /// the obstacles' positions, φ): check_formulas stops a run at the first value of
  /// theirs that is not finite.
  std::vector<std::shared_ptr<const Expression>> formulas;

  /// `key` located for a message: its key_locations entry, else "<name>: <key>".
  std::string where(const std::string& key) const;
  /// Where `key` of the table `table` ("contact.pair[0]") is, or the table where the key is not given
  /// (a default).
  std::string where_in(const std::string& table, const std::string& key) const;
  /// The step of a uniform grid, T / N.
  double step() const { return final_time / n_steps; }
  bool uniform_steps() const { return step_times.empty() && !step_control; }
  /// A fixed non-uniform grid (problem/time_grid.hpp) instead of the uniform one or error control.
  void set_fixed_grid(FixedGrid grid);
  /// t_n of a fixed grid, n = 0 … N (uniform: n T / N, and T exactly at n = N).
  double time_at(int n) const;
  /// k_n = t_n − t_{n−1} of a fixed grid (uniform: T / N for every n, as before non-uniform grids).
  double step_at(int n) const;
  /// The step of a fixed grid whose time is nearest t (ties: the earlier one).
  int step_nearest(double t) const;
  /// The first step's size (the one the damage matrix is factorized for at set-up).
  double first_step() const;
  /// N of a fixed grid; with error control, T / dt_initial (for estimates of the run's cost).
  int expected_steps() const;
  /// The largest step of a fixed grid (the k of Theorem 3.5); dt_max when error-controlled
  /// (capped at the stable step of the explicit G: stable_step_control, problem/stability.hpp).
  double largest_step() const;
  /// "k = 0.01, N = 100", "k in [0.001, 0.05], N = 57", or the step control's description.
  std::string describe_steps() const;
  /// The body's material (ℰ, G, φ above) named "body", then `materials`, then each further
  /// body's (Body::material): the list that cell_materials indexes.
  std::vector<Material> material_list() const;
  /// κ of body b (0: `kappa`, k: bodies[k − 1]'s).
  double kappa_of(int b) const { return b == 0 ? kappa : bodies[static_cast<std::size_t>(b) - 1].kappa; }
  /// β0 of body b (empty: 1).
  const ScalarField& beta0_of(int b) const { return b == 0 ? beta0 : bodies[static_cast<std::size_t>(b) - 1].beta0; }
  /// β0 at each node of `mesh`, whose cell c is in body cell_body[c] (empty: every cell in body 0):
  /// each node takes its body's β0 (a node lies in one body).
  Vector initial_damage(const Mesh& mesh, const std::vector<int>& cell_body) const;
  /// Throws vpc::Error describing the first invalid datum (the checks below and
  /// the parts, the law, the source). The one place each datum is checked. Returns the whole
  /// mesh's contact rows, which its checks build (contact_rows; a block's own, Problem::block):
  /// a set-up keeps them (Case::contact_rows) rather than building them again.
  ContactRows validate() const;
};

// The checks of Problem::validate that concern one datum, for a reader that knows
// where the datum came from (a case file's line, an option) and puts that before
// the message. Each throws vpc::Error saying what was expected.
void check_kappa(double kappa);
void check_final_time(double final_time);
void check_n_steps(int n_steps);
/// N = T / k; throws unless k > 0 divides T into whole steps (to a relative 1e-9).
int steps_of_time_step(double final_time, double k);
/// β0 in [0, 1] at every node.
/// (`body` ≥ 0: at the nodes of that body's cells only.)
void check_beta0(const Mesh& mesh, const ScalarField& beta0, int body = -1, const MeshBlock* block = nullptr);
/// Throws vpc::Error, naming the key, the value, the time and the point, if a formula
/// of p.formulas has given a value that is not finite (Expression::check_finite): the
/// time stepper calls it after each step's data (F_n, u_D, g) and sources (φ_n).
void check_formulas(const Problem& p);
/// Where the displacement is prescribed (the Dirichlet data of SPEC §6), per node and component.
struct DirichletDofs {
  /// Per full dof (node · d + component): −1 free; 0 prescribed zero (Γ1, a symmetry plane);
  /// k ≥ 1 prescribed by Problem::displacement[k − 1].
  std::vector<int> condition;
  /// The parts whose reactions are reported (dirichlet_parts), and per node a bit
  /// for each of them that the node lies on.
  std::vector<std::string> parts;
  std::vector<std::uint64_t> on_parts;
  /// Per part: bit i set where the part prescribes component i (its reaction's components).
  std::vector<unsigned> components;
};
/// Γ1's parts, then those of Problem::displacement and Problem::symmetry (each name once).
std::vector<std::string> dirichlet_parts(const Problem& p);
/// The axis i of a symmetry part: its facets all lie in one plane x_i = const. Throws
/// vpc::Error naming the part otherwise (and a node, by its number in the whole mesh where
/// `mesh` is `block`).
int symmetry_axis(const Mesh& mesh, const std::string& part, const MeshBlock* block = nullptr);

/// Problem::validate's check that the body is held (its prescribed components stop every rigid
/// motion), on a block of its mesh (Problem::block): `nodes` are this rank's own, and `sum` adds
/// up n values over the ranks in place. Collective through `sum`; throws as validate.
void check_block_held(const Problem& p, const std::vector<int>& condition, const std::vector<int>& nodes,
                      const std::vector<ContactRow>& rows, const std::function<void(double*, int)>& sum);
/// The Dirichlet data of every node. Throws vpc::Error where two conditions prescribe
/// different values of one component at a node (compared at t = 0 and t = T).
DirichletDofs dirichlet_dofs(const Problem& p);

/// The body of each cell of `mesh` (Mesh::cell_body).
std::vector<int> cell_bodies(const Mesh& mesh);
/// The body of each node of `mesh`, whose cell c is in body cell_body[c] (a node lies in one body:
/// bodies share no node); 0 where no cell touches the node.
std::vector<int> node_bodies(const Mesh& mesh, const std::vector<int>& cell_body);

/// The material of each cell of p.mesh, an index into Problem::material_list(): its body's
/// (0, or a Body::material) where no material's region holds the cell. Throws vpc::Error for a region the mesh
/// lacks (or that holds no cell), a region in two materials, an elasticity of
/// another kind than the body's (plane stress beside plane strain) and a missing law.
std::vector<int> cell_materials(const Problem& p);

/// Γ2: the given traction parts, or every boundary facet on none of Γ1, Γ3, the
/// prescribed-displacement and the symmetry parts.
std::vector<int> traction_facets(const Problem& p);
/// The facets of each pressure load's parts, in the order of Problem::pressure.
std::vector<std::vector<int>> pressure_facets(const Problem& p);

}  // namespace vpc

