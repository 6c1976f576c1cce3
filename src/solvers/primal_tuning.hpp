#pragma once
// The primal contact solver's tuning constants, named once (issue 49). None changes what the
// solver converges to, only how it gets there. Each has its reason on its first line, then where
// it was measured: the numbers here, and the text around them in docs/scheme.md §3
// ("primal-active-set", "primal-active-set with friction") or docs/performance.md ("Friction").
// The solves before the solver gives up (kPrimalMaxIterations, kPrimalFrictionMaxIterations) are
// part of its interface: solvers/primal_active_set.hpp.

namespace vpc::primal_tuning {

// --- Loose solves: an iterative solver finds the active set with them (primal_operator.cpp) ---

/// A loose solve's relative tolerance: finding a set costs a few iterations, the signs rarely mislead.
/// Measured: foundation-3d n = 40, 5 steps on CG + GAMG: 1e-6 → 3.2 s a step, 1e-4 → 3.0 s,
/// 1e-3 → up to 25 set iterations in a step (docs/scheme.md, "primal-active-set").
inline constexpr double kLooseTolerance = 1e-4;
/// ... or this share of the guess's own residual where smaller: a set change is always answered.
/// (Else the set flips back and forth on an unchanged w where the guess meets kLooseTolerance.)
inline constexpr double kLooseReduction = 1e-2;
/// Below this a loose solve takes the solver's own tolerance: that close to the answer.
inline constexpr double kLooseFloor = 1e-9;

// --- Corrections with friction: inexact Newton (primal_operator.cpp) ---

/// A correction's residual reduction on an iterative solver: at most kForcing, at least kLeastForcing.
/// Measured: frictional foundation-3d n = 10 on CG + GAMG, 100 steps: 3,815 Krylov iterations with
/// kForcing every time, 3,457 to the friction tolerance, 3,370 to the square of the directions'
/// last change (docs/scheme.md, "primal-active-set with friction").
inline constexpr double kForcing = 1e-2, kLeastForcing = 1e-6;
/// A direct solver keeps its factor, as GMRES's preconditioner, until the products GMRES took beyond
/// a fresh factor's add up to a factorization's cost (ski rental: at most twice the better of the
/// two); a fresh factor's GMRES takes this many products a decade of residual reduction (plus one).
/// Measured: shear-3d --n 16 on CHOLMOD, fresh factor: 7-12 products for 8-12 decades, 2-5 for 2;
/// a kept one 10-130 (PrimalOperator::keep_factor; docs/performance.md, "Friction").
inline constexpr double kFreshProductsPerDecade = 1.5;
/// A factorization's cost in solves where the backend gives no analysis to estimate it (MUMPS).
/// (CHOLMOD's: flops and entries at solver_cost.hpp's rates; shear-3d --n 16: 20.1.)
inline constexpr double kFactorSolves = 20;

// --- Newton's slip springs (primal_friction.cpp) ---

/// Newton's spring across a slip direction at most this many times c: stiffer slows the multigrid.
/// (Softer loses Newton's rate.) Measured: frictional foundation-3d n = 40 on CG + GAMG, 2 ranks,
/// 100 steps, Krylov iterations (solves): 4,735 at 1e4 c, 4,303 at 1e2 c, 3,735 (360) at 10 c,
/// 4,264 (484) at 3 c, 7,096 (833) at c (docs/performance.md, "Friction", "Two settings, and why").
inline constexpr double kMostSpring = 10;

// --- The frictional iteration (primal_friction_iteration.cpp) ---

/// On an iterative solver, slip forces that no longer halve below this count as settled: its accuracy.
/// Measured: with 1e-8 a run's friction-bound residual reached 5.2e-9 against the step's tolerance
/// 1e-8 (foundation-3d n = 20 on CG + GAMG; docs/scheme.md, "primal-active-set with friction").
inline constexpr double kNoiseCeiling = 1e-10;
/// Coupled iterates (Coulomb's bound in Newton's step) without convergence before the bound is lagged.
/// (The fallback after a cycle; docs/scheme.md, "primal-active-set with friction".)
inline constexpr int kCoupledIterations = 40;
/// The lagged bound's Anderson mixing keeps this many iterates: a plain fixed point need not contract.
/// (anderson_mixing.hpp: a sheared block tilting at μ = 1 has ratio ≈ −0.95; docs/scheme.md,
/// "primal-active-set with friction".)
inline constexpr int kAndersonDepth = 8;
/// Within a lagged Tresca problem the slip directions go only to this share of the bound's last change.
/// (An inexact inner solve.) Measured on the test block: 3D partial slip 93 → 38 solves, 3D full
/// slip 47 → 19.
inline constexpr double kInnerShare = 0.1;
/// The secant step for c (PrimalFriction::secant) is updated until the slip forces move less than this.
/// (Of the force scale.) Measured: a pressed 3D block, ν = 0.3, with it updated to the end, a step
/// stalled near 1e-9 (docs/scheme.md, "primal-active-set with friction").
inline constexpr double kSecantUntil = 1e-6;

}  // namespace vpc::primal_tuning
