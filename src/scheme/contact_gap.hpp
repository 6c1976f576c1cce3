#pragma once
// The gap a step leaves at the contact nodes, g(t_n) − N u_n, for the output of cases with
// contact pairs (VTU `gap`, on the slave nodes and, mortar-averaged, on the master nodes:
// io/state_fields.cpp). It follows from u and t, so a checkpoint does not carry it.
#include "scheme/discrete_system.hpp"
#include "scheme/state.hpp"

namespace vpc {

/// Whether the state records the gap: a case with contact pairs.
bool records_gap(const DiscreteSystem& sys);

/// g − N u at the owned rows (g: per owned row, StepData::gap's order), each row whole: from
/// ContactSet::N_local and s.u's free dofs, ghosts included (current once a step's u has updated
/// them), so that a spread pair row's ghost masters count. Exact, without communication.
Vector rows_gap_left(const DiscreteSystem& sys, const Vector& g, const State& s);

/// s.gap = g − N u per contact node (replicated like λ; negative: a compliant law's
/// penetration), from the bound g at the owned rows (StepData::gap) and s.u (rows_gap_left).
/// Nothing without contact pairs. Collective.
void record_gap(const DiscreteSystem& sys, const Vector& g, State& s);

}  // namespace vpc
