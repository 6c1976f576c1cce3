#include "solvers/primal_friction_iteration.hpp"

#include "solvers/active_set_history.hpp"
#include "solvers/anderson_mixing.hpp"
#include "solvers/primal_tuning.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

namespace vpc {

using namespace primal_tuning;

void FrictionalSolve::constrain(std::vector<char>& fixed, std::vector<Eigen::Triplet<double>>& springs) const {
  friction.springs(springs);  // Newton's springs across the slip directions
  friction.fix(fixed);
}

la::Perturbation FrictionalSolve::load(const PrimalOperator& op, const std::vector<char>& active, const Vector& b,
                                       Vector& rhs, Vector& fixed_values) {
  law_rhs_ = Vector::Zero(b.size());
  la::Perturbation C = coupling.build(op, friction, couple, active, b, rhs, law_rhs_);
  friction.load(op.constraints(), coupling.coupled(), rhs, fixed_values);
  return C;
}

void FrictionalSolve::weigh(Vector& rhs) const {
  if (!coupling.weighted()) return;
  coupling.weigh(rhs);  // D rhs, the law rows' own part already over μ
  rhs += law_rhs_;
}

std::optional<TangentialPart::Correction> FrictionalSolve::correction(bool perturbed, bool tight,
                                                                      bool iterative) const {
  // Also without C on a tight iterative solve: the fixed rows (stick dofs at h, which grows with the
  // slip) can dominate ‖rhs‖, against which an iterative solver's tolerance is relative.
  if (!perturbed && !(tight && iterative)) return std::nullopt;
  const bool newton = couple && coupling.any_coupled();
  return Correction{std::max(0.5 * force_tolerance, newton ? newton_target : 0.0) * force_scale, couple};
}

PrimalFrictionIteration::PrimalFrictionIteration(const PrimalOperator& op, double force_tolerance)
    : s_(op.constraints(), op.diagonal(), force_tolerance) {}

ContactReport PrimalFrictionIteration::solve(PrimalOperator& op, PrimalWarmStart& answers, int max_iterations,
                                            const Vector& F, Vector& u, Vector& lambda) {
  const ContactConstraints& c = op.constraints();
  PrimalFriction& friction = s_.friction;
  const auto rows = op.n_rows();
  const la::Comm& comm = op.comm();
  const Vector b = op.rotate(F);
  Vector w = answers.start_point(op, F, u);
  const bool warm = lambda.size() == static_cast<Eigen::Index>(c.m) * c.block;
  Vector normal_in = warm ? local_normal(c, lambda) : Vector(Vector::Zero(rows));
  Vector tangential_in = warm ? local_tangential(c, lambda) : Vector();
  const bool extrapolated =
      warm && answers.continuing(comm, u) && forces_before_.size() == normal_in.size() + tangential_in.size();
  if (extrapolated) {
    // The forces extrapolated as w is (a step's load changes smoothly).
    const Vector forces = 2 * forces_last_ - forces_before_;
    normal_in = forces.head(rows);
    tangential_in = forces.tail(tangential_in.size());
  }
  std::vector<char> active(static_cast<size_t>(rows));
  for (Eigen::Index i = 0; i < rows; ++i) active[i] = op.first_state(i, normal_in[i], op.gap_left(w, i));
  // A bonded row on its bond's spring pulls (λ_ν < 0): its Coulomb bound is 0, it starts free to slip.
  std::vector<char> pressed = active;
  for (char& a : pressed) a = a == PrimalOperator::kOn;
  friction.start(c, pressed, normal_in, tangential_in);
  if (extrapolated) {
    // Newton's first linearization at the extrapolated start (w, λ), HSW's rule with its bound,
    // instead of the last answer's sets and springs with the extrapolated forces: there the
    // first solve's iterate re-opened the residual by 6x and a sliding step took three
    // linearizations after it (frictional foundation-3d n = 20 on CG + GAMG: the residual of
    // the second linearization 1.2e-3 → 1.6e-5 of the force scale; n = 40, 100 steps, 2 ranks:
    // 6,703 → 6,008 Krylov iterations).
    friction.take(friction.next(c, w, tangential_in, hsw_bound(op, active, normal_in, w)));
  }
  Vector bound = Vector::Zero(rows);  // Coulomb's bound: the iterate's own, or the lagged Tresca problem's
  // (λ_τ sized from the start: a first coupled solve that fails leaves it as it is.)
  Vector lambda_local = Vector::Zero(rows), tangential = Vector::Zero(rows * (c.block - 1));
  auto history = std::make_unique<ActiveSetHistory>();
  AndersonMixing coulomb(kAndersonDepth);
  ContactReport rep;
  bool monotone = false, converged = false, tight = !op.iterative();
  const double inf = std::numeric_limits<double>::infinity();
  double last_direction = inf, last_bound = inf;  // the last changes after tight solves
  double bound_change = inf;                       // of the last Tresca problem's bound (lagged)
  const double b_scale = comm.max(b.size() ? b.cwiseAbs().maxCoeff() : 0.0);
  // The first solve's scale is the iteration's own (b's and λ_ν's), λ_ν from the warm start: a case
  // loaded only through its gap or obstacle has b = 0, and a scale of b alone asked that solve's
  // GMRES for 1e-14 of an already small residual (shear-3d: 12-15 solves with the factor a step).
  s_.force_scale = std::max({b_scale, comm.max(normal_in.size() ? normal_in.cwiseAbs().maxCoeff() : 0.0),
                             std::numeric_limits<double>::min()});
  auto settled = [&](double change, double& last) {
    const bool yes = change <= s_.force_tolerance ||
                     (tight && op.iterative() && change <= kNoiseCeiling && change > 0.5 * last);
    if (tight) last = change;
    return yes;
  };
  s_.couple = true;
  s_.newton_target = 0;
  for (int it = 0; it < max_iterations && !converged; ++it) {
    if (s_.couple && it == kCoupledIterations) s_.couple = false;  // no convergence yet: lag the bound
    auto [r, next, most_negative, worst, residual_left, failed] =
        op.iterate(active, b, w, tight, lambda_local, rep, s_);
    if (failed) break;  // Coulomb's linearization singular: not converged
    if (monotone) op.release_one(active, next, most_negative, worst);
    tangential = friction.forces(r);
    if (s_.couple) {
      bound = hsw_bound(op, next, lambda_local, w, active);
    }
    const double scale = std::max({b_scale, comm.max(lambda_local.size() ? lambda_local.cwiseAbs().maxCoeff() : 0.0),
                                   std::numeric_limits<double>::min()});
    s_.force_scale = scale;
    // c's secant step while the slip forces still move much; then fixed (kSecantUntil).
    friction.secant(c, w, tangential, comm, last_direction > kSecantUntil);
    PrimalFriction::Next up = friction.next(c, w, tangential, bound);
    if (monotone) friction.slip_one(up, comm);
    if (s_.couple) friction.slip_before_leaving(c, active, tangential, bound, next, up);
    if (!comm.all(next == active) || !comm.all(up.stick == friction.stick()) || !comm.all(up.bond == friction.bond())) {
      if (history->came_back(contact_sets(next, up.stick, up.bond), comm) && !monotone) {
        monotone = true;
        ++rep.cycles;
        // The sets cycle: Coulomb's bound is lagged from here on, each Tresca problem (the
        // bound frozen) solved before the next bound, where the monotone updates cannot cycle.
        // The coupling's nonsymmetric step can swing a row in and out of contact (2D block,
        // μ = 1, full slip; a tilted one, μ = 0.3, partial slip).
        s_.couple = false;
      }
      active = std::move(next);
      friction.take(std::move(up));
      last_direction = inf;
      continue;
    }
    const double direction_change = comm.max(up.change) / scale;
    const bool was_tight = tight, directions_held = settled(direction_change, last_direction);
    tight = true;  // sets found: tight solves from here on (an iterative solver's forces need them)
    if (s_.couple) {
      // ... and the last correction's equilibrium residual within the same tolerance: from a
      // loose iterate, one correction leaves kForcing of the loose residual (a pressed block
      // that sticks: equilibrium 9.8e-9 against the step's 1e-8).
      converged = directions_held && was_tight && residual_left <= s_.force_tolerance * scale;
      if (!converged) friction.take(std::move(up));  // Newton's next linearization
      s_.newton_target = direction_change * direction_change;
      continue;
    }
    // Lagged: within a Tresca problem the slip directions are iterated only to a share of the
    // bound's last change (an inexact inner solve, kInnerShare), to the friction tolerance at the end.
    if (!directions_held && direction_change > kInnerShare * bound_change) {
      friction.take(std::move(up));
      continue;
    }
    // This Tresca problem is solved: Coulomb's bound from its λ_ν.
    Vector coulomb_bound(rows);
    for (Eigen::Index i = 0; i < rows; ++i) coulomb_bound[i] = c.bound(i, active[i] ? lambda_local[i] : 0.0);
    bound_change = comm.max(bound_moved(c, coulomb_bound, bound, tangential)) / scale;
    const bool bound_held = settled(bound_change, last_bound);
    if (bound_held && directions_held) {
      converged = was_tight && residual_left <= s_.force_tolerance * scale;
      continue;
    }
    if (bound_held) {  // the directions still to settle
      friction.take(std::move(up));
      continue;
    }
    // A loose solve's λ_ν (an iterative solver's first, finding the sets) is a guess, not G(s):
    // in Anderson's history it would be the one small residual and hold the bound near itself.
    bound = was_tight ? coulomb.next(comm, bound, coulomb_bound) : coulomb_bound;
    if (!was_tight) bound_change = inf;
    for (Eigen::Index i = 0; i < rows; ++i) bound[i] = std::max(bound[i], c.bound(i, 0.0));  // μ λ_ν ≥ 0
    friction.take(std::move(up));
    friction.rescale(bound);
    history = std::make_unique<ActiveSetHistory>();
    monotone = false;
    last_direction = inf;
  }
  answers.keep_answer(op, w, u);
  forces_before_ = std::move(forces_last_);
  forces_last_.resize(rows + tangential.size());
  forces_last_ << lambda_local, tangential;
  lambda = replicate_blocks(comm, c, lambda_local, tangential);
  ContactReport out = friction_report(op.K(), c, F, u, lambda, converged, rep.iterations);
  out.factorizations = rep.factorizations;
  out.cycles = rep.cycles;
  return out;
}

double PrimalFrictionIteration::bound_moved(const ContactConstraints& c, const Vector& coulomb_bound, const Vector& bound,
                                            const Vector& tangential) const {
  const auto t = static_cast<Eigen::Index>(c.block - 1);
  double moved = 0;
  for (Eigen::Index i = 0; i < coulomb_bound.size(); ++i) {
    const double d = std::abs(coulomb_bound[i] - bound[i]);
    if (s_.friction.stick()[static_cast<std::size_t>(i)] && bound[i] - force_size(c.friction_of(i), tangential.segment(i * t, t)) > d)
      continue;
    moved = std::max(moved, d);
  }
  return moved;
}

Vector PrimalFrictionIteration::hsw_bound(const PrimalOperator& op, const std::vector<char>& in_contact,
                                          const Vector& normal, const Vector& w, const std::vector<char>& held) {
  const ContactConstraints& c = op.constraints();
  Vector bound(normal.size());
  for (Eigen::Index i = 0; i < bound.size(); ++i) {
    const auto k = static_cast<std::size_t>(i);
    const double gap = op.gap_left(w, i);
    bound[i] = c.bound(i, !in_contact[k]                   ? 0.0
                          : !held.empty() && held[k] ? normal[i]
                          : op.compliant(i)          ? -gap / op.spring(k)
                                                     : normal[i] - op.scale(i) * gap);
  }
  return bound;
}

}  // namespace vpc
