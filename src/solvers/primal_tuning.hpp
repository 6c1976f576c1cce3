#pragma once
// The primal contact solver's tuning constants, named once (issue 49). None changes what the
// solver converges to, only how it gets there; each has its reason in one line and a pointer to
// its measurement: docs/scheme.md §3 ("primal-active-set" and "primal-active-set with friction"),
// docs/performance.md ("The contact solver", "Friction"), or the numbers beside the constant.
// The solves before it gives up (kPrimalMaxIterations, kPrimalFrictionMaxIterations) are part of
// its interface: solvers/primal_active_set.hpp.

namespace vpc::primal_tuning {

// --- Loose solves: an iterative solver finds the active set with them (primal_operator.cpp) ---
/// A loose solve's relative tolerance: finding a set costs a few iterations, and the signs rarely
/// mislead (foundation-3d n = 40, 5 steps on CG + GAMG: 1e-6 → 3.2 s a step, 1e-4 → 3.0 s, 1e-3 →
/// up to 25 set iterations in a step; docs/scheme.md, "primal-active-set").
inline constexpr double kLooseTolerance = 1e-4;
/// ... or this reduction of the guess's own residual where smaller: a set change must be answered
/// even when the guess already meets kLooseTolerance (else the set flips on an unchanged w).
inline constexpr double kLooseReduction = 1e-2;
/// Below this a loose solve takes the solver's own tolerance (that close to the answer).
inline constexpr double kLooseFloor = 1e-9;

// --- Corrections with friction: inexact Newton (primal_operator.cpp) ---
/// An iterative solver's correction reduces its residual by at most kForcing and at least
/// kLeastForcing, else to Newton's target (frictional foundation-3d n = 10 on CG + GAMG, 100 steps:
/// 3,815 Krylov iterations with kForcing every time, 3,457 to the tolerance, 3,370 to the square of
/// the directions' change; docs/scheme.md, "primal-active-set with friction").
inline constexpr double kForcing = 1e-2, kLeastForcing = 1e-6;
/// A direct solver keeps its factor while each slip row's spring changed by at most this share of
/// its stiffness c_i + k_i (the lagged iteration still contracts): foundation-3d n = 20 on CHOLMOD,
/// 100 steps, 199 factorizations against 720 (1,494 s) with one at every iterate (docs/scheme.md,
/// "primal-active-set with friction"; docs/performance.md, "Friction", "On a direct solver").
inline constexpr double kLaggedSpringShare = 0.5;

// --- Newton's slip springs (primal_friction.cpp) ---
/// Newton's spring across a slip direction at most this many times c: stiffer slows the multigrid
/// on the tangent dofs, softer loses Newton's rate (frictional foundation-3d n = 40 on CG + GAMG,
/// 2 ranks, 100 steps, Krylov iterations: 4,735 at 1e4 c, 4,303 at 1e2 c, 3,735 at 10 c, 4,264 at
/// 3 c, 7,096 at c; docs/performance.md, "Friction", "Two settings, and why").
inline constexpr double kMostSpring = 10;

// --- The frictional iteration (primal_friction_iteration.cpp) ---
/// On an iterative solver slip forces that no longer halve below this count as settled (its
/// accuracy): 1e-8 let a run's friction-bound residual reach 5.2e-9 against the step's tolerance
/// 1e-8 (foundation-3d n = 20 on CG + GAMG; docs/scheme.md, "primal-active-set with friction").
inline constexpr double kNoiseCeiling = 1e-10;
/// Coupled iterates (Coulomb's bound in Newton's step) before the bound is lagged instead, as after
/// a cycle (docs/scheme.md, "primal-active-set with friction": "the same fallback after 40").
inline constexpr int kCoupledIterations = 40;
/// The lagged bound's Anderson mixing keeps this many iterates (a plain fixed point on the bound
/// need not contract: anderson_mixing.hpp; docs/scheme.md, "primal-active-set with friction").
inline constexpr int kAndersonDepth = 8;
/// Within a lagged Tresca problem the slip directions are iterated only to this share of the
/// bound's last change (an inexact inner solve; 3D partial slip on the test block: 93 → 38 solves,
/// 3D full slip 47 → 19).
inline constexpr double kInnerShare = 0.1;
/// The secant step for c (PrimalFriction::secant) is updated while the slip forces move by more
/// than this (of the force scale), then frozen (a pressed 3D block, ν = 0.3: updated to the end, a
/// step stalled near 1e-9; docs/scheme.md, "primal-active-set with friction").
inline constexpr double kSecantUntil = 1e-6;

}  // namespace vpc::primal_tuning
