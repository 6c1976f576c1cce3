#pragma once
// The contact laws' per-node state (contact/surface_state.hpp) in the scheme: declared once per
// problem, set to its initial values at t_0 and updated after each solved step by each node's own
// laws. A rejected step restores the state it was taken from, surface fields included.
#include "scheme/discrete_system.hpp"
#include "scheme/state.hpp"
#include "scheme/step_report.hpp"

#include <vector>

namespace vpc {

/// Every variable the problem's normal and friction laws declare, once by name, in the order of
/// ContactSpec::laws() (each law's normal law, then its friction law). A name declared by two laws
/// must be declared alike (width, initial value); a located vpc::Error otherwise.
std::vector<SurfaceVariable> declared_surface_state(const ContactSpec& contact);

/// State::surface at t_0: each declared variable at its initial value on every contact node.
std::vector<SurfaceField> initial_surface_state(const ContactSpec& contact, int n_contact);

/// The node-dependent part of State::surface at t_0 (SurfaceHistory::initial_at: adhesion's α_0(x)), from
/// `gap`, g(t_0) per owned row; a located vpc::Error on every process where a node cannot start so
/// (bonded across an open gap). Collective; nothing where no law declares state.
void set_initial_surface_state(const DiscreteSystem& sys, const Vector& gap, State& s);

/// Adhesion's bonds a_i of step n of size k per owned row in row order (SurfaceHistory::bond times
/// |Γ3|_i, from the state at t_{n−1}); empty where no law bonds (ContactSpec::adhesive).
StepBonds surface_bond(const DiscreteSystem& sys, const State& s, double k);

/// What the laws' state at t_{n−1} adds to the gap of step n (SurfaceHistory::gap_shift), per owned
/// row in row order; empty where no law keeps state.
Vector surface_gap_shift(const DiscreteSystem& sys, const State& s);

/// State::gap (pairs only; nothing without) from `g`, g(t_n) at the owned rows: the gap left with the
/// laws' state at t_n, g + shift − N u, as the step records it and a restore computes it again.
void record_gap_left(const DiscreteSystem& sys, const Vector& g, State& s);

/// After step n is solved (u, λ and the slip increments in s, s.t still t_{n−1}; `gap`: the gap it solved
/// with per owned row, g(t_n) and the shift; u_before: s.u at t_{n−1}; t: t_n):
/// each owned node's laws update their variables (SurfaceHistory::update_surface), and the values
/// are replicated again. Returns the largest shares of the laws' limits the updates used, over every
/// process, with the law's text where one passes 1 (the step's acceptance and the run's warning).
/// Collective; nothing where no law declares state.
SurfaceLimits update_surface_state(const DiscreteSystem& sys, const Vector& gap, double k, const Vector& u_before,
                                   double t, State& s);

}  // namespace vpc
