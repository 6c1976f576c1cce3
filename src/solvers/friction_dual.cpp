#include "solvers/friction_dual.hpp"

#include "core/error.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>

namespace vpc {

namespace {

constexpr double kTolerance = 1e-13;  // ‖Φ‖∞ relative: converged
constexpr double kStallFloor = 1e-10;  // a stall (no decrease) this close is round-off of S, not a failure
constexpr int kFullSteps = 10;         // full steps taken where the line search finds no decrease

double max_abs(const Vector& v) { return v.size() ? v.cwiseAbs().maxCoeff() : 0.0; }

bool has_tangent(const FrictionDualSets& f, int node, int j) {
  return f.tangent[static_cast<std::size_t>(node * (f.block - 1) + j)] != 0;
}

/// ρ: 1/S_kk on a normal row; one ρ for a node's tangents (1/the largest of their S_kk): the
/// projection onto a disc keeps the friction law only under a scalar multiple of Δ.
Vector step_lengths(const Eigen::MatrixXd& S, const FrictionDualSets& f) {
  const int d = f.block;
  Vector rho(S.rows());
  for (int i = 0; i < f.nodes(); ++i) {
    rho[i * d] = 1 / S(i * d, i * d);
    double most = 0;
    for (int j = 0; j < d - 1; ++j)
      if (has_tangent(f, i, j)) most = std::max(most, S(i * d + 1 + j, i * d + 1 + j));
    for (int j = 0; j < d - 1; ++j) rho[i * d + 1 + j] = most > 0 ? 1 / most : 1.0;
  }
  return rho;
}

/// A node whose normal force is its law's λ(d) (a law that is not linear), not a projection.
const ContactLaw* force_law(const FrictionDualSets& f, int node) {
  return f.force_law.empty() ? nullptr : f.force_law[static_cast<std::size_t>(node)];
}

/// Coulomb's bound at node i for the normal force p_ν, capped by the shear limit (`capped`: the
/// limit holds, and the bound does not move with λ_ν).
double coulomb_bound(const FrictionDualSets& f, int i, double p_nu, bool& capped) {
  return f.bound_of(i).at(p_nu, &capped);
}

/// The radius of node i's disc that P uses: min(s, |z_τ|) (|z_τ|: z_τ inside the disc), but
/// where z_ν's round-off dz_ν times μ leaves s unresolved (a node in contact with λ_ν ≈ 0 and μ
/// huge, whose slip law μ λ_ν = |λ_τ| puts λ_ν below z_ν's round-off: a bonded face's trailing
/// node), the radius among those s takes over [z_ν − dz_ν, z_ν + dz_ν] (at most |z_τ|) whose
/// projection of z_τ lies nearest λ_τ: Φ is then measured to what the data resolve. dz empty, a
/// capped bound or a force law's node: min(s, |z_τ|).
double resolvable_radius(const FrictionDualSets& f, int i, const Vector& z, const Vector& lambda, const Vector& dz,
                         Eigen::Index k, double s, double norm, bool keep) {
  if (keep || f.mu[i] <= 0 || dz.size() == 0 || norm == 0 || !f.friction_of(i).disc()) return std::min(s, norm);
  bool capped = false;
  const double lo = coulomb_bound(f, i, std::clamp(z[k] - dz[k], f.lo[i], f.hi[i]), capped);
  if (norm <= lo) return norm;  // stick whatever z_ν's round-off
  const double hi = coulomb_bound(f, i, std::clamp(z[k] + dz[k], f.lo[i], f.hi[i]), capped);
  double along = 0;  // λ_τ · z_τ/|z_τ|
  for (int j = 0; j < f.block - 1; ++j)
    if (has_tangent(f, i, j)) along += lambda[k + 1 + j] * z[k + 1 + j] / norm;
  return std::clamp(along, lo, std::min(hi, norm));
}

/// p = P(z), node by node, and where dP is given its derivative: row k holds ∂p_k/∂z over the
/// d unknowns of k's node (the branch of λ's own value at a tie, as solve_compliance_dual). At a
/// node with a force law p_ν = λ(d) at its penetration d = (z_ν − λ_ν)/ρ_ν = r_ν (λ: the iterate
/// z was made from); dP holds its slope through z_ν, and newton_step adds λ_ν's own part.
void project(const FrictionDualSets& f, const Vector& z, const Vector& lambda, const Vector& rho, const Vector& dz,
             Vector& p, Eigen::MatrixXd* dP) {
  const int d = f.block, t = d - 1;
  p.setZero(z.size());
  if (dP) dP->setZero(z.size(), d);
  for (int i = 0; i < f.nodes(); ++i) {
    const Eigen::Index k = static_cast<Eigen::Index>(i) * d;
    double slope = 0;  // ∂p_ν/∂z_ν
    if (const ContactLaw* law = force_law(f, i)) {
      const double pen = (z[k] - lambda[k]) / rho[k];
      p[k] = law->force(pen, f.compliance[i]);
      slope = law->force_slope(pen, f.compliance[i]) / rho[k];
    } else if (const double a = f.bond.size() ? f.bond[i] : 0.0; a > 0) {  // the bond's resolvent (the header)
      const double L = f.bond_length[i], base = f.lo[i] + a * L, zz = z[k] - base;
      if (zz > 0) {
        p[k] = std::min(z[k], f.hi[i]);
        slope = z[k] < f.hi[i] ? 1.0 : 0.0;
      } else if (zz > -(a + rho[k]) * L) {
        slope = a / (a + rho[k]);
        p[k] = base + slope * zz;
      } else {
        p[k] = f.lo[i];
      }
    } else {
      p[k] = std::clamp(z[k], f.lo[i], f.hi[i]);
      slope = z[k] > f.lo[i] && z[k] < f.hi[i] ? 1.0 : 0.0;
    }
    if (dP) (*dP)(k, 0) = slope;
    bool capped = false;
    const double s = coulomb_bound(f, i, p[k], capped);
    const double ds = !capped && p[k] > 0 ? f.mu[i] * slope : 0.0;  // ∂s/∂z_ν
    // The node's tangents (a symmetry plane's missing one left out) and its law's set C_s.
    const FrictionLaw& law = f.friction_of(i);
    double zt[2], pt[2], dp_dz[4], dp_ds[2];
    int tangent[2], nt = 0;
    for (int j = 0; j < t; ++j)
      if (has_tangent(f, i, j)) tangent[nt] = j, zt[nt++] = z[k + 1 + j];
    const double norm = law.gauge(zt, nt);
    const double radius = resolvable_radius(f, i, z, lambda, dz, k, s, norm, capped || force_law(f, i));
    // Off s, λ_ν is the slip law's (radius − tresca)/μ, within p_ν's round-off: the bound it gives
    // is the radius (as the primal solver's law_normal_force).
    if (radius != std::min(s, norm)) p[k] = f.bound_of(i).normal_force_at(radius);
    if (nt == 0) continue;
    if (norm <= s && radius == norm) {  // stick: inside the set
      for (int a = 0; a < nt; ++a) {
        p[k + 1 + tangent[a]] = zt[a];
        if (dP) (*dP)(k + 1 + tangent[a], 1 + tangent[a]) = 1;
      }
      continue;
    }
    law.project(zt, nt, radius, pt);  // slip: on the set's boundary of that radius
    for (int a = 0; a < nt; ++a) p[k + 1 + tangent[a]] = pt[a];
    if (!dP) continue;
    if (norm <= s) {  // stick by s, on the boundary by the radius s can have
      for (int a = 0; a < nt; ++a) (*dP)(k + 1 + tangent[a], 1 + tangent[a]) = 1;
      continue;
    }
    law.project_derivative(zt, nt, s, dp_dz, dp_ds);
    for (int a = 0; a < nt; ++a) {
      (*dP)(k + 1 + tangent[a], 0) = ds * dp_ds[a];
      for (int b = 0; b < nt; ++b) (*dP)(k + 1 + tangent[a], 1 + tangent[b]) = dp_dz[a * nt + b];
    }
  }
}

/// A bound on the round-off of z_ν = λ_ν + ρ_ν (b − Sλ)_ν at each normal row (n ε times the sum of
/// its terms' sizes; empty where no node has μ > 1, whose bound cannot turn it into a force).
Vector z_roundoff(const Eigen::MatrixXd& S, const Vector& b, const FrictionDualSets& f, const Vector& rho,
                  const Vector& lambda) {
  if (!(f.mu.size() > 0 && f.mu.maxCoeff() > 1)) return {};
  const double gamma = static_cast<double>(b.size() + 2) * std::numeric_limits<double>::epsilon();
  const Vector terms = b.cwiseAbs() + S.cwiseAbs() * lambda.cwiseAbs();
  return gamma * (lambda.cwiseAbs() + rho.cwiseProduct(terms));
}

/// Alart–Curnier's Φ(λ) = λ − P(λ + ρ(b − Sλ)); p = P(·).
Vector alart_curnier(const Eigen::MatrixXd& S, const Vector& b, const FrictionDualSets& f, const Vector& rho,
                     const Vector& lambda, Vector& p, Eigen::MatrixXd* dP) {
  project(f, Vector(lambda + rho.cwiseProduct(b - S * lambda)), lambda, rho, z_roundoff(S, b, f, rho, lambda), p, dP);
  return lambda - p;
}

/// The Newton step J δ = −Φ with J = I − P'(I − ρS). A row where P' vanishes (a normal force
/// at its bound, a slip bound that does not move) reads δ_k = −Φ_k; the other rows, the
/// contact zone's, form the reduced system, dense and (with Coulomb) not symmetric.
Vector newton_step(const Eigen::MatrixXd& S, const FrictionDualSets& f, const Vector& rho, const Eigen::MatrixXd& dP,
                   const Vector& phi) {
  const int d = f.block;
  const Eigen::Index n = phi.size();
  std::vector<Eigen::Index> free;
  for (Eigen::Index k = 0; k < n; ++k)
    if (dP.row(k).squaredNorm() > 0) free.push_back(k);
  Vector step = -phi;
  if (free.empty()) return step;
  const auto nf = static_cast<Eigen::Index>(free.size());
  for (const Eigen::Index k : free) step[k] = 0;
  Eigen::MatrixXd J_FF(nf, nf);
  Vector rhs(nf);
  Vector row(n);
  for (Eigen::Index a = 0; a < nf; ++a) {
    const Eigen::Index k = free[static_cast<std::size_t>(a)], base = k / d * d;
    row.setZero();
    for (int l = 0; l < d; ++l)
      if (const double v = dP(k, l); v != 0) {
        row.noalias() += (v * rho[base + l]) * S.row(base + l).transpose();
        row[base + l] -= v;
      }
    row[k] += 1;
    // A force law's node: p depends on λ_ν also directly, through d = (z_ν − λ_ν)/ρ_ν.
    if (force_law(f, static_cast<int>(k / d))) row[base] += dP(k, 0);
    rhs[a] = -phi[k] - row.dot(step);  // the fixed rows' δ moved to the right
    for (Eigen::Index c = 0; c < nf; ++c) J_FF(a, c) = row[free[static_cast<std::size_t>(c)]];
  }
  const Vector x = J_FF.partialPivLu().solve(rhs);
  for (Eigen::Index a = 0; a < nf; ++a) step[free[static_cast<std::size_t>(a)]] = x[a];
  return step;
}

/// Where no step along Newton's direction decreases ½‖Φ‖²: a node that sticks in contact and would
/// leave contact by the full `step` (z_ν ≤ 0 after it) with its tangential force above its Tresca
/// part first slips in contact along z_τ, its bound coupled (Φ_τ = λ_τ − s n, ∂/∂z_ν = μ n); the
/// step is solved again with those rows (false, `step` kept: no such node). Between sticking (whose
/// step takes λ_ν < 0) and leaving (free, it presses in again) the answer can be that slip state,
/// z_ν in (0, |z_τ|/μ): no wider than z_ν's round-off where μ is huge (a bonded face's trailing
/// node), so the line search, stuck at the kink z_ν = 0, never lands in it.
bool slip_before_leaving(const Eigen::MatrixXd& S, const Vector& b, const FrictionDualSets& f, const Vector& rho,
                         const Vector& lambda, const Vector& phi, const Eigen::MatrixXd& dP, Vector& step) {
  const int d = f.block, t = d - 1;
  if (!f.coulomb() || !f.force_law.empty()) return false;
  const Vector z = lambda + rho.cwiseProduct(b - S * lambda);
  const Vector next = lambda + step;
  const Vector z_next = next + rho.cwiseProduct(b - S * next);
  Vector phi2 = phi;
  Eigen::MatrixXd dP2 = dP;
  bool any = false;
  for (int i = 0; i < f.nodes(); ++i) {
    const Eigen::Index k = static_cast<Eigen::Index>(i) * d;
    if (f.mu[i] <= 0 || dP(k, 0) != 1 || z_next[k] > 0 || !f.friction_of(i).disc()) continue;
    double norm2 = 0;
    bool stick = true;
    for (int j = 0; j < t; ++j)
      if (has_tangent(f, i, j)) norm2 += z[k + 1 + j] * z[k + 1 + j], stick = stick && dP(k + 1 + j, 1 + j) == 1 && dP(k + 1 + j, 0) == 0;
    const double norm = std::sqrt(norm2);
    if (!stick || norm <= f.tresca[i]) continue;
    bool capped = false;
    const double s = coulomb_bound(f, i, std::clamp(z[k], f.lo[i], f.hi[i]), capped);
    if (capped) continue;  // its bound does not move with λ_ν: no slip law to couple
    any = true;
    for (int j = 0; j < t; ++j) {
      if (!has_tangent(f, i, j)) continue;
      const double n_j = z[k + 1 + j] / norm;
      phi2[k + 1 + j] = lambda[k + 1 + j] - s * n_j;
      dP2(k + 1 + j, 0) = f.mu[i] * n_j;
      for (int l = 0; l < t; ++l)
        if (has_tangent(f, i, l)) dP2(k + 1 + j, 1 + l) = (j == l ? 1.0 : 0.0) - n_j * z[k + 1 + l] / norm;
    }
  }
  if (any) step = newton_step(S, f, rho, dP2, phi2);
  return any;
}

/// The force scale of the tolerance besides ‖λ‖∞: the normal forces b_ν / S_νν would take
/// alone, and the tangential ones b_τ / S_ττ up to the Tresca bound: a far slide (h large) makes
/// b_τ any size, and the forces it gives are bounded by s; a bound far above the forces (1e8: a
/// stuck face) is no force scale either, and would loosen the tolerance by as much.
double b_scale(const Eigen::MatrixXd& S, const Vector& b, const FrictionDualSets& f) {
  double scale = 0;
  for (int i = 0; i < f.nodes(); ++i) {
    const Eigen::Index k = static_cast<Eigen::Index>(i) * f.block;
    scale = std::max(scale, std::abs(b[k] / S(k, k)));
    for (int j = 0; j < f.block - 1; ++j)
      if (has_tangent(f, i, j)) scale = std::max(scale, std::min(f.tresca[i], std::abs(b[k + 1 + j] / S(k + 1 + j, k + 1 + j))));
  }
  return scale;
}

/// Semismooth Newton on Φ (the header's second path).
BoxQpResult newton(const Eigen::MatrixXd& S, const Vector& b, const FrictionDualSets& f, Vector& lambda,
                   int max_iterations) {
  BoxQpResult r;
  const Vector rho = step_lengths(S, f);
  const double bs = b_scale(S, b, f);
  auto scale = [&] { return std::max({max_abs(lambda), bs, 1e-300}); };
  Eigen::MatrixXd dP;
  Vector p, trial_p, trial;
  Vector phi = alart_curnier(S, b, f, rho, lambda, p, &dP);
  int full_steps = 0;
  for (r.iterations = 0;; ++r.iterations) {
    if (!phi.allFinite()) break;
    if (max_abs(phi) <= kTolerance * scale()) {
      r.converged = true;
      break;
    }
    if (r.iterations == max_iterations) break;
    Vector step = newton_step(S, f, rho, dP, phi);
    // Backtracking on ½‖Φ‖² (Armijo along the Newton direction, where its slope is −‖Φ‖²).
    const double merit = phi.squaredNorm();
    auto decreases = [&] {
      double alpha = 1;
      for (int halving = 0; halving < 30; ++halving, alpha *= 0.5) {
        trial = lambda + alpha * step;
        if (alart_curnier(S, b, f, rho, trial, trial_p, nullptr).squaredNorm() <= (1 - 1e-4 * alpha) * merit) return true;
      }
      return false;
    };
    bool decreased = decreases();
    if (!decreased) {
      if (max_abs(phi) <= kStallFloor * scale()) {  // round-off of an ill-conditioned S
        r.converged = true;
        break;
      }
      // Stuck at the kink between sticking and leaving contact: the slip state between them.
      if (slip_before_leaving(S, b, f, rho, lambda, phi, dP, step)) decreased = decreases();
    }
    if (!decreased) {
      // No decrease along the direction (Coulomb's problem is not a minimization): the full
      // step leaves the region, a few times at most; then the step control retries.
      if (full_steps++ == kFullSteps) break;
      ++r.cycles;
      trial = lambda + step;
    }
    lambda = trial;
    phi = alart_curnier(S, b, f, rho, lambda, p, &dP);
  }
  r.kkt_residual = phi.allFinite() ? max_abs(phi) / scale() : std::numeric_limits<double>::infinity();
  if (r.converged) lambda = p;  // exactly in its set: λ_ν ≥ lo, |λ_τ| ≤ s
  return r;
}

}  // namespace

FrictionDualSets friction_sets(const la::Comm& comm, const ContactConstraints& c,
                               const std::vector<const ContactLaw*>& laws, const Vector& lower,
                               const std::vector<const FrictionLaw*>& frictions, Eigen::MatrixXd& S) {
  const int m = c.m, b = c.block, t = b - 1;
  FrictionDualSets f;
  f.block = b;
  for (const FrictionLaw* law : frictions) f.friction.push_back(law ? law : &disc_friction());
  f.lo = Vector::Zero(m);
  f.hi = Vector::Constant(m, std::numeric_limits<double>::infinity());
  for (std::size_t j = 0; j < laws.size(); ++j) {
    f.lo[static_cast<Eigen::Index>(j)] = lower.size() ? lower[static_cast<Eigen::Index>(j)] : 0.0;
    f.hi[static_cast<Eigen::Index>(j)] = laws[j]->dual_upper();
  }
  Vector has(c.T.rows());
  for (Eigen::Index k = 0; k < has.size(); ++k) has[k] = c.tangent_dof[static_cast<std::size_t>(k)] >= 0;
  const Vector all = replicate_blocks(comm, c, c.mu, has);
  // The shear limits (+∞: none), replicated where some row has one (a sum with one owner a row: exact).
  const double inf = std::numeric_limits<double>::infinity();
  const auto rows = static_cast<Eigen::Index>(c.rows.size());
  const Vector limit = c.limit.size() == rows ? c.limit : Vector(Vector::Constant(rows, inf));
  if (comm.any(rows > 0 && limit.minCoeff() < inf)) f.limit = replicate(comm, c, limit);
  f.mu.resize(m);
  f.tresca = Vector::Zero(m);
  f.tangent.assign(static_cast<std::size_t>(m * t), 0);
  for (int i = 0; i < m; ++i) {
    f.mu[i] = all[i * b];
    for (int j = 0; j < t; ++j) {
      const int k = i * b + 1 + j;
      f.tangent[static_cast<std::size_t>(i * t + j)] = all[k] != 0;
      if (all[k] == 0) S(k, k) = 1;
    }
  }
  return f;
}

bool FrictionDualSets::coulomb() const { return mu.size() > 0 && mu.maxCoeff() > 0; }

bool FrictionDualSets::discs() const {
  return std::ranges::all_of(friction, [](const FrictionLaw* law) { return law->disc(); });
}

void tresca_box(const FrictionDualSets& f, Vector& lo, Vector& hi) {
  const int d = f.block;
  lo.resize(static_cast<Eigen::Index>(f.nodes()) * d);
  hi.resizeLike(lo);
  for (int i = 0; i < f.nodes(); ++i) {
    lo[i * d] = f.lo[i];
    hi[i * d] = f.hi[i];
    for (int j = 0; j < d - 1; ++j) {
      const double s = has_tangent(f, i, j) ? f.tresca[i] : 0.0;
      lo[i * d + 1 + j] = -s;
      hi[i * d + 1 + j] = s;
    }
  }
}

BoxQpResult solve_friction_dual(DenseBoxQpOperator& S, const Vector& b, const FrictionDualSets& f, Vector& lambda,
                                int max_iterations) {
  const Eigen::Index n = b.size();
  const int d = f.block;
  require(d >= 2 && S.size() == n && n == static_cast<Eigen::Index>(f.nodes()) * d &&
              f.hi.size() == f.nodes() && f.tresca.size() == f.nodes() && f.mu.size() == f.nodes() &&
              (f.limit.size() == 0 || f.limit.size() == f.nodes()) &&
              (f.force_law.empty() || (f.force_law.size() == static_cast<std::size_t>(f.nodes()) &&
                                       f.compliance.size() == f.nodes())) &&
              (f.bond_length.size() == 0 || (f.bond_length.size() == f.nodes() && f.bond.size() == f.nodes())) &&
              f.tangent.size() == static_cast<std::size_t>(f.nodes() * (d - 1)) &&
              (f.friction.empty() || f.friction.size() == static_cast<std::size_t>(f.nodes())),
          "internal: friction dual of {} unknowns for {} nodes of block {}", n, f.nodes(), d);
  if (lambda.size() != n) lambda = Vector::Zero(n);
  if (!b.allFinite()) {  // NaN or Inf data: report, never "solve"
    BoxQpResult r;
    r.kkt_residual = std::numeric_limits<double>::infinity();
    return r;
  }
  if (d == 2 && !f.coulomb() && f.force_law.empty() && f.discs() && f.bond_length.size() == 0) {
    Vector lo, hi;
    tresca_box(f, lo, hi);
    return solve_box_qp(S, b, lo, hi, lambda, max_iterations);
  }
  return newton(S.matrix(), b, f, lambda, max_iterations);
}

double friction_dual_residual(const Eigen::MatrixXd& S, const Vector& b, const FrictionDualSets& f,
                              const Vector& lambda) {
  Vector p;
  const Vector phi = alart_curnier(S, b, f, step_lengths(S, f), lambda, p, nullptr);
  return max_abs(phi) / std::max({max_abs(lambda), b_scale(S, b, f), 1e-300});
}

}  // namespace vpc
