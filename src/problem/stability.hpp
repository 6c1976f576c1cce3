#pragma once
// The stability of the lagged viscoplastic step (3.6), z_n = z_{n−1} + k G(σ_{n−1}, ε(u_{n−1}), β_{n−1}):
// the paper's scheme is explicit in G, so it is stable only for k L ≤ 2, L the law's Lipschitz
// constant (ViscoplasticLaw::lipschitz). Why 2: σ_n = ℰε(u_n) + z_n = Q z_n + (the loads' part),
// where Q is the ℰ⁻¹-orthogonal projection onto the self-equilibrated stresses (u_n minimizes
// ½|ℰε(u) + z_n|²_{ℰ⁻¹} − (f_n, u)); Q's eigenvalues are 0 and 1 whatever ℰ, so no elasticity
// constant enters for a law of σ. A perturbation δz then grows by I + k ∂G/∂σ Q per step; with
// ∂G/∂σ = −L I (Perzyna far outside its yield set, Maxwell at a fixed β) that is 1 − kL on the
// stresses that flow: |1 − kL| ≤ 1 iff kL ≤ 2. For 1 < kL ≤ 2 the step overshoots (σ alternates,
// decaying); beyond 2 it alternates and grows by |1 − kL| per step (docs/scheme.md).
#include "problem/problem.hpp"

#include <string>
#include <vector>

namespace vpc {

/// 2 / L(β): the largest stable step of a law at damage β (infinite for L = 0).
double stable_step(const ViscoplasticLaw& law, double beta);

/// The largest step stable at every state (β = 0) for every material of p, which
/// error-controlled steps never exceed; infinite where no law has L > 0.
double stable_step_limit(const Problem& p);

/// p's step control completed (StepControl::completed) with dt_max (and dt_initial, event_dt)
/// capped at stable_step_limit(p): the steps error control takes.
/// p.step_control must be set.
StepControl stable_step_control(const Problem& p);

/// Throws vpc::Error (one line: the material, the law and its parameters, L, the bound and a
/// number of steps that is stable) when a step of p's fixed grid exceeds 2/L(β) for a material
/// at its initial damage (the least β0 at its cells' centroids): such a run blows up as soon as
/// the material flows. Error-controlled steps: when dt_min exceeds stable_step_limit.
/// `cell_material`: cell_materials(p).
void check_step_stability(const Problem& p, const std::vector<int>& cell_material);

/// The message of a run stopped by the backstop of TimeStepper: the lagged rate's change
/// ΔG_n = G_n − G_{n−1} flipped sign and grew `steps` steps in a row, `growth` times over them,
/// which a stable step cannot do (an unstable mode has ΔG_n = (1 − kL) ΔG_{n−1}). `material`: the
/// one with the largest |ΔG|; `beta`: its least centroid β where ΔG is.
std::string unstable_step_message(const Problem& p, const Material& material, double beta, int n, double t, double k,
                                  double growth, int steps);

}  // namespace vpc
