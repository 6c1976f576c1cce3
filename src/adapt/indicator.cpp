#include "adapt/indicator.hpp"

#include "fem/cell_geometry.hpp"
#include "mesh/facet_key.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

namespace vpc {

namespace {

/// The facet opposite vertex i of a cell: its unit outward normal and measure (|F| = d |K| |∇λ_i|).
struct Face {
  Point n{0, 0, 0};
  double measure = 0;
};

Face face_of(const CellGeometry& g, int dim, int i) {
  const auto& grad = g.grad[static_cast<std::size_t>(i)];
  const double len = std::sqrt(grad[0] * grad[0] + grad[1] * grad[1] + grad[2] * grad[2]);
  Face f;
  for (int j = 0; j < 3; ++j) f.n[j] = -grad[static_cast<std::size_t>(j)] / len;
  f.measure = dim * g.volume * len;
  return f;
}

/// h_F: a facet's diameter scale (its length in 2D, √area in 3D).
double facet_size(double measure, int dim) { return dim == 2 ? measure : std::sqrt(measure); }

/// σ n as a vector (the first d components).
Point traction(const SymTensor& s, const Point& n, int dim) {
  Point t{0, 0, 0};
  for (int i = 0; i < dim; ++i)
    for (int j = 0; j < dim; ++j) t[i] += s(i, j) * n[j];
  return t;
}

double norm2(const Point& p) { return p[0] * p[0] + p[1] * p[1] + p[2] * p[2]; }

/// Each part's share of its own total, weighted, added into `combined`.
void add_share(const std::vector<double>& part, double weight, std::vector<double>& combined) {
  const double total = std::accumulate(part.begin(), part.end(), 0.0);
  if (!(total > 0) || weight == 0) return;
  for (std::size_t k = 0; k < part.size(); ++k) combined[k] += weight * part[k] / total;
}

}  // namespace

CellIndicators cell_indicators(const Mesh& mesh, const std::vector<SymTensor>& sigma, const Eigen::VectorXd& beta,
                               const std::vector<double>& pressure, const AdaptSpec& spec,
                               const std::vector<double>& approach) {
  const int d = mesh.dim(), nc = mesh.n_cells(), npc = mesh.nodes_per_cell();
  const std::vector<CellGeometry> geo = compute_geometry(mesh);
  CellIndicators out;
  out.stress.assign(static_cast<std::size_t>(nc), 0.0);
  out.contact.assign(static_cast<std::size_t>(nc), 0.0);
  out.damage.assign(static_cast<std::size_t>(nc), 0.0);
  out.combined.assign(static_cast<std::size_t>(nc), 0.0);

  // ∇β per cell (P1: constant).
  std::vector<Point> grad_beta(static_cast<std::size_t>(nc), Point{0, 0, 0});
  for (int c = 0; c < nc; ++c)
    for (int a = 0; a < npc; ++a)
      for (int j = 0; j < 3; ++j)
        grad_beta[static_cast<std::size_t>(c)][j] += beta[mesh.cell(c)[a]] * geo[static_cast<std::size_t>(c)].grad[static_cast<std::size_t>(a)][static_cast<std::size_t>(j)];

  // Interior facets: the first cell that has one waits in the map for the second.
  std::unordered_map<FacetKey, std::pair<int, int>, FacetKeyHash> first;  // facet → (cell, local vertex opposite)
  first.reserve(static_cast<std::size_t>(nc) * static_cast<std::size_t>(npc));
  // Round-off is not an error to refine: a jump counts only above 1e-10 of its scale (σ's largest
  // component; for ∇β, β ∈ [0, 1] changing by 1e-10 across the facet's cell). Without this a uniform β
  // (∇β ≈ 1e-16/h) would make the damage part, normalized to 1, mark the cells of its round-off.
  double sigma_max = 0;
  for (const SymTensor& x : sigma)
    for (double v : x.c) sigma_max = std::max(sigma_max, std::abs(v));
  const double stress_floor = 1e-20 * sigma_max * sigma_max;
  int nodes[3];
  double sigma2 = 0;
  for (int c = 0; c < nc; ++c) {
    sigma2 += geo[static_cast<std::size_t>(c)].volume * sigma[static_cast<std::size_t>(c)].dot(sigma[static_cast<std::size_t>(c)]);
    for (int i = 0; i < npc; ++i) {
      cell_facet(mesh.cell(c), npc, i, nodes);
      const FacetKey key = facet_key(nodes, d);
      const auto [it, fresh] = first.try_emplace(key, c, i);
      if (fresh) continue;
      const auto [c1, i1] = it->second;
      first.erase(it);
      const Face f = face_of(geo[static_cast<std::size_t>(c1)], d, i1);  // outward from c1
      const double weight = 0.5 * facet_size(f.measure, d) * f.measure;  // ½ h_F |F|, each cell's half
      const Point t1 = traction(sigma[static_cast<std::size_t>(c1)], f.n, d);
      const Point t2 = traction(sigma[static_cast<std::size_t>(c)], f.n, d);
      double js = norm2({t1[0] - t2[0], t1[1] - t2[1], t1[2] - t2[2]});
      if (js <= stress_floor) js = 0;
      double jb = 0;
      for (int j = 0; j < 3; ++j) jb += (grad_beta[static_cast<std::size_t>(c1)][j] - grad_beta[static_cast<std::size_t>(c)][j]) * f.n[j];
      const double h = geo[static_cast<std::size_t>(c1)].volume * d / f.measure;  // c1's height onto F
      if (std::abs(jb) * h <= 1e-10) jb = 0;
      for (int k : {c1, c}) {
        out.stress[static_cast<std::size_t>(k)] += weight * js;
        out.damage[static_cast<std::size_t>(k)] += weight * jb * jb;
      }
    }
  }
  out.stress_relative = sigma2 > 0 ? std::sqrt(std::accumulate(out.stress.begin(), out.stress.end(), 0.0) / sigma2) : 0;

  // Γ3: the nodal pressures of the contact rows, over the boundary facets whose nodes are all rows.
  double p_ref = 0;
  for (double p : pressure)
    if (p > p_ref) p_ref = p;
  if (p_ref == 0) p_ref = 1;  // (before any contact: the forecast alone, normalized below)
  for (int f = 0; f < mesh.n_facets(); ++f) {
    const int* v = mesh.facet(f);
    double lo = INFINITY, hi = -INFINITY, mean = 0;
    bool all = true;
    for (int a = 0; a < d; ++a) {
      const double p = pressure[static_cast<std::size_t>(v[a])];
      all = all && !std::isnan(p);
      lo = std::min(lo, p);
      hi = std::max(hi, p);
      mean += p / d;
    }
    if (!all) continue;
    if (hi - lo <= 1e-10 * std::max(std::abs(hi), std::abs(lo))) continue;  // (round-off)
    // The variance of the facet's nodal pressures, times |F|: on a segment 3 ‖p − p̄_F‖²_F of the P1
    // trace (the scale drops out in the normalization).
    double var = 0;
    for (int a = 0; a < d; ++a) var += std::pow(pressure[static_cast<std::size_t>(v[a])] - mean, 2) / d;
    const double measure = mesh.facet_measure(f);
    out.contact[static_cast<std::size_t>(mesh.facet_cell(f))] += facet_size(measure, d) * measure * var;
  }

  for (int f : facets_about_to_touch(mesh, pressure, approach)) {
    const double measure = mesh.facet_measure(f);
    out.contact[static_cast<std::size_t>(mesh.facet_cell(f))] += facet_size(measure, d) * measure * p_ref * p_ref;
  }

  add_share(out.stress, spec.stress_weight, out.combined);
  add_share(out.contact, spec.contact_weight, out.combined);
  add_share(out.damage, spec.damage_weight, out.combined);
  return out;
}

std::vector<int> facets_about_to_touch(const Mesh& mesh, const std::vector<double>& pressure,
                                       const std::vector<double>& approach, double reach) {
  std::vector<int> out;
  if (approach.empty()) return out;
  const int d = mesh.dim();
  for (int f = 0; f < mesh.n_facets(); ++f) {
    const int* v = mesh.facet(f);
    bool all = true, near = false;
    const double h = reach * facet_size(mesh.facet_measure(f), d);
    for (int a = 0; a < d; ++a) {
      const auto i = static_cast<std::size_t>(v[a]);
      all = all && !std::isnan(pressure[i]);
      near = near || (!(pressure[i] > 0) && approach[i] < h);  // (a NaN margin: not forecast)
    }
    if (all && near) out.push_back(f);
  }
  return out;
}

}  // namespace vpc
