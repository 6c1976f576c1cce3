#pragma once
// Where the mesh is too coarse (issue 51): a per-cell indicator η_K of three parts, each a standard
// a-posteriori quantity of a P1 displacement, a P0 stress and a P1 damage field:
//   stress   η²_σ,K = Σ_{F ⊂ ∂K interior} ½ h_F ‖[σ n]‖²_F   (the flux-jump estimator of linear
//            elasticity, Verfürth 2013 §4.2; the volume residual h_K‖f + div σ‖ vanishes for P0 σ and
//            is left out with the body force, which no shipped case makes dominant);
//   contact  η²_c,K = Σ_{F ⊂ ∂K ∩ Γ3} h_F ‖p − p̄_F‖²_F with p = λ_i/|Γ3|_i the nodal pressure: the
//            pressure's variation over the facet, largest at the edge of the contact zone, where p
//            drops to 0 (the "boundary of the contact zone" and "the pressure's variation"); and the
//            surfaces about to touch: a Γ3 facet with a node not in contact (p = 0) whose margin to the
//            obstacle at a step before the next adaptation, min_j g(t_{n+j}) − u_ν (j ≤ [adapt] every),
//            is below h_F adds h_F |F| p_ref² (p_ref: the
//            largest pressure, 1 before any contact), as a facet whose pressure jumps by p_ref would;
//            so a coarse mesh sees an indenter coming before its nodes reach it;
//   damage   η²_β,K = Σ_{F ⊂ ∂K interior} ½ h_F ‖[∇β · n]‖²_F   (the jumps of ∇β).
// Each part is normalized to Σ_K η² = 1 (a part that is zero everywhere stays 0) and the parts are
// added with the AdaptSpec weights: the marking (adapt/marking.hpp) is scale-free and needs no units.
#include "adapt/adapt_spec.hpp"
#include "mesh/mesh.hpp"

#include <Eigen/Dense>

#include <vector>

namespace vpc {

struct CellIndicators {
  /// Per cell of the stepper's mesh, each part's η_K² (as defined above, not normalized).
  std::vector<double> stress, contact, damage;
  /// Σ_parts weight × η²_part,K / Σ_K η²_part,K: what marking reads.
  std::vector<double> combined;
  /// (Σ_K η²_σ,K)^½ / ‖σ‖_L2(Ω): the relative stress estimate (0 for a stress-free state).
  double stress_relative = 0;
};

/// The indicators of σ (per cell), β and the nodal contact pressure p_i = λ_i/|Γ3|_i (per node; NaN off
/// the contact rows) on `mesh`, summed in its numbering: the adaptivity passes the leaf mesh, so that the
/// marking does not depend on an engine's numbering of its part. `approach` (per node, NaN where not
/// forecast; empty: none): the margin min_j g(t_{n+j}) − u_ν of a contact row to its obstacle over the steps
/// to the next adaptation.
CellIndicators cell_indicators(const Mesh& mesh, const std::vector<SymTensor>& sigma, const Eigen::VectorXd& beta,
                               const std::vector<double>& pressure, const AdaptSpec& spec,
                               const std::vector<double>& approach = {});

/// The Γ3 facets of `mesh` (those whose nodes all have a pressure, not NaN) about to touch: a node not in
/// contact (p not > 0) whose `approach` margin is below `reach` × the facet's size h_F (its length in 2D,
/// √area in 3D). With reach 1: what the contact part's forecast adds to, and what an adaptation refines to
/// its final level (adapt/mesh_adaptivity.hpp); with 2, what coarsening leaves alone (a parent's facet is at
/// most twice as large: coarsening it would make it about to touch, and the forecast refine it again).
std::vector<int> facets_about_to_touch(const Mesh& mesh, const std::vector<double>& pressure,
                                       const std::vector<double>& approach, double reach = 1);

}  // namespace vpc
