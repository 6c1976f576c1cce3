#pragma once
// The gap a step leaves at the contact nodes, g(t_n) − N u_n, for the output of cases with
// contact pairs (VTU `gap`, on the slave nodes and, mortar-averaged, on the master nodes:
// io/state_fields.cpp). It follows from u and t, so a checkpoint does not carry it.
#include "scheme/discrete_system.hpp"
#include "scheme/state.hpp"

namespace vpc {

/// Whether the state records the gap: a case with contact pairs.
bool records_gap(const DiscreteSystem& sys);

/// s.gap = g − N u per contact node (replicated like λ; negative: a compliant law's
/// penetration), from the bound g at the owned rows (StepData::gap) and u's owned free dofs.
/// Nothing without contact pairs. Collective.
void record_gap(const DiscreteSystem& sys, const Vector& g, const Vector& u_free, State& s);

}  // namespace vpc
