// Red refinement: conformity, measures, nestedness, boundary parts, exact P1/P0
// prolongation, and the norms of prolonged fields (which must not change).
#include "../mesh_measures.hpp"
#include "fem/cell_geometry.hpp"
#include "mesh/generators.hpp"
#include "mesh/gmsh_reader.hpp"
#include "verification/norms.hpp"
#include "verification/refine.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

namespace vpc {
namespace {

/// Barycentric coordinates of x in cell c of m.
std::array<double, 4> barycentric(const Mesh& m, int c, const Point& x) {
  const int d = m.dim();
  Eigen::MatrixXd J(d, d);
  Eigen::VectorXd r(d);
  const Point& x0 = m.node(m.cell(c)[0]);
  for (int a = 1; a <= d; ++a)
    for (int i = 0; i < d; ++i) J(i, a - 1) = m.node(m.cell(c)[a])[i] - x0[i];
  for (int i = 0; i < d; ++i) r[i] = x[i] - x0[i];
  const Eigen::VectorXd l = J.partialPivLu().solve(r);
  std::array<double, 4> lam{1, 0, 0, 0};
  for (int a = 1; a <= d; ++a) {
    lam[a] = l[a - 1];
    lam[0] -= l[a - 1];
  }
  return lam;
}

/// A box mesh with its interior nodes moved at random (still valid): unstructured.
Mesh distorted(Mesh m, double amount) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-amount, amount);
  std::vector<int> on_boundary(m.n_nodes(), 0);
  for (int f = 0; f < m.n_facets(); ++f)
    for (int a = 0; a < m.nodes_per_facet(); ++a) on_boundary[m.facet(f)[a]] = 1;
  for (int i = 0; i < m.n_nodes(); ++i)
    if (!on_boundary[i])
      for (int j = 0; j < m.dim(); ++j) m.nodes()[i][j] += u(rng);
  return m;
}

std::vector<Mesh> test_meshes() {
  std::vector<Mesh> out;
  out.push_back(make_interval(0, 2, 5));
  out.push_back(make_rectangle({0, 0, 0}, {2, 1, 0}, 3, 2));
  out.push_back(distorted(make_rectangle({0, 0, 0}, {1, 1, 0}, 4, 4), 0.05));
  out.push_back(make_box({0, 0, 0}, {1, 2, 1}, 2, 2, 2));
  out.push_back(distorted(make_box({0, 0, 0}, {1, 1, 1}, 3, 3, 3), 0.04));
  out.back().tag_facets("contact", [](const Point& x) { return x[2] < 1e-12 && x[0] < 0.5; });
  return out;
}

TEST(Refine, CountsVolumesAndConformity) {
  for (const Mesh& m : test_meshes()) {
    const int d = m.dim(), children = 1 << d;
    const Refinement r = refine_uniform(m);
    EXPECT_EQ(r.fine.n_cells(), children * m.n_cells());
    EXPECT_EQ(r.fine.n_facets(), (children / 2) * m.n_facets());
    EXPECT_NEAR(total_volume(r.fine), total_volume(m), 1e-13 * total_volume(m));
    // Every child has 1/2^d of its parent's measure (true for red refinement in 1D-3D).
    const auto gc = compute_geometry(m), gf = compute_geometry(r.fine);
    for (int c = 0; c < r.fine.n_cells(); ++c)
      EXPECT_NEAR(gf[c].volume, gc[r.parent_cell[c]].volume / children, 1e-13);
    // Conforming: the boundary of the fine cell complex is exactly the refined boundary.
    Mesh rebuilt = r.fine;
    rebuilt.build_boundary();
    EXPECT_EQ(rebuilt.n_facets(), r.fine.n_facets()) << "d = " << d;
  }
}

TEST(Refine, ChildrenLieInTheirParents) {
  for (const Mesh& m : test_meshes()) {
    const Refinement r = refine_uniform(m);
    for (int c = 0; c < r.fine.n_cells(); ++c)
      for (int a = 0; a <= m.dim(); ++a) {
        const auto lam = barycentric(m, r.parent_cell[c], r.fine.node(r.fine.cell(c)[a]));
        for (int b = 0; b <= m.dim(); ++b) ASSERT_GE(lam[b], -1e-12) << "cell " << c;
      }
  }
}

TEST(Refine, BoundaryPartsAreKept) {
  for (const Mesh& m : test_meshes()) {
    const Refinement r = refine_uniform(m);
    EXPECT_EQ(r.fine.part_names(), m.part_names());
    for (const auto& p : m.part_names()) {
      EXPECT_EQ(r.fine.part_size(p), (1 << (m.dim() - 1)) * m.part_size(p)) << p;
      EXPECT_NEAR(part_measure(r.fine, p), part_measure(m, p), 1e-13) << p;
    }
    for (int f = 0; f < r.fine.n_facets(); ++f) {
      const int pf = r.parent_facet[f];
      EXPECT_EQ(r.fine.facet_part(f), m.facet_part(pf));
      // The outward normal is the parent's (the child lies in the parent facet).
      const Point nf = r.fine.facet_normal(f), np = m.facet_normal(pf);
      for (int j = 0; j < 3; ++j) EXPECT_NEAR(nf[j], np[j], 1e-12);
    }
  }
}

TEST(Refine, P1AndP0ProlongationAreExact) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (const Mesh& m : test_meshes()) {
    const int d = m.dim();
    const Refinement r = refine_uniform(m);
    // A P1 function with random nodal values (two components): the prolonged values
    // at every fine node equal the coarse function evaluated there.
    Vector coarse(2 * m.n_nodes());
    for (auto& v : coarse) v = u(rng);
    const Vector fine = prolong_p1(r, coarse, 2);
    for (int c = 0; c < r.fine.n_cells(); ++c) {
      const int p = r.parent_cell[c];
      for (int a = 0; a <= d; ++a) {
        const int node = r.fine.cell(c)[a];
        const auto lam = barycentric(m, p, r.fine.node(node));
        for (int comp = 0; comp < 2; ++comp) {
          double expected = 0;
          for (int b = 0; b <= d; ++b) expected += lam[b] * coarse[m.cell(p)[b] * 2 + comp];
          ASSERT_NEAR(fine[node * 2 + comp], expected, 1e-12);
        }
      }
    }
    // P0: the integral is kept.
    std::vector<double> q(m.n_cells());
    for (auto& v : q) v = u(rng);
    const auto qf = prolong_p0(r, q);
    const auto gc = compute_geometry(m), gf = compute_geometry(r.fine);
    double ic = 0, ifine = 0;
    for (int c = 0; c < m.n_cells(); ++c) ic += gc[c].volume * q[c];
    for (int c = 0; c < r.fine.n_cells(); ++c) ifine += gf[c].volume * qf[c];
    EXPECT_NEAR(ic, ifine, 1e-13);
  }
}

TEST(Refine, NormsOfProlongedFieldsAreUnchanged) {
  // Exact transfer means the norms of (3.39) of a coarse field are the same on the
  // fine mesh: this is what makes comparisons against a finer reference exact.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  const std::vector<std::pair<Mesh, Elasticity>> cases = {
      {make_interval(0, 1, 4), Elasticity(Elasticity::Kind::Uniaxial, 2.0, 0.0)},
      {distorted(make_rectangle({0, 0, 0}, {1, 1, 0}, 3, 3), 0.05), Elasticity(Elasticity::Kind::PlaneStress, 3.0, 0.3)},
      {distorted(make_box({0, 0, 0}, {1, 1, 1}, 2, 2, 2), 0.03), Elasticity(Elasticity::Kind::Isotropic, 1.0, 0.25)}};
  for (const auto& [m, el] : cases) {
    const int d = m.dim();
    const MeshHierarchy h(m, 2);
    Vector uc(d * m.n_nodes()), bc(m.n_nodes());
    for (auto& v : uc) v = u(rng);
    for (auto& v : bc) v = u(rng);
    std::vector<SymTensor> sc(m.n_cells());
    for (auto& s : sc)
      for (int i = 0; i < 6; ++i) s[i] = u(rng);
    const DiscreteNorms nc(m, el), nf(h.mesh(2), el);
    const Vector uf = h.prolong_p1(uc, 0, 2, d), bf = h.prolong_p1(bc, 0, 2, 1);
    const auto sf = h.prolong_p0(sc, 0, 2);
    EXPECT_NEAR(nf.energy(uf), nc.energy(uc), 1e-12 * nc.energy(uc));
    EXPECT_NEAR(nf.l2_vector(uf), nc.l2_vector(uc), 1e-12 * nc.l2_vector(uc));
    EXPECT_NEAR(nf.l2(sf), nc.l2(sc), 1e-12 * nc.l2(sc));
    EXPECT_NEAR(nf.l2(bf), nc.l2(bc), 1e-12 * nc.l2(bc));
    EXPECT_NEAR(nf.h1_seminorm(bf), nc.h1_seminorm(bc), 1e-12 * nc.h1_seminorm(bc));
    // The ancestors of level 2 are the parents of the parents.
    const auto& a = h.ancestors(0, 2);
    for (int c = 0; c < h.mesh(2).n_cells(); ++c)
      EXPECT_EQ(a[c], h.refinement(0).parent_cell[h.refinement(1).parent_cell[c]]);
  }
}

TEST(Refine, TetrahedraKeepTheirShape) {
  // Bey's refinement along the shortest diagonal produces finitely many shapes:
  // the ratio of largest to smallest edge stays bounded under repeated refinement.
  const MeshHierarchy h(distorted(make_box({0, 0, 0}, {1, 1, 1}, 2, 2, 2), 0.03), 3);
  auto aspect = [](const Mesh& m) {
    double worst = 0;
    for (int c = 0; c < m.n_cells(); ++c) {
      double lo = INFINITY, hi = 0;
      for (int a = 0; a < 4; ++a)
        for (int b = a + 1; b < 4; ++b) {
          const Point& x = m.node(m.cell(c)[a]);
          const Point& y = m.node(m.cell(c)[b]);
          const double l = std::hypot(x[0] - y[0], x[1] - y[1], x[2] - y[2]);
          lo = std::min(lo, l);
          hi = std::max(hi, l);
        }
      worst = std::max(worst, hi / lo);
    }
    return worst;
  };
  const double a0 = aspect(h.mesh(0));
  for (int l = 1; l < h.n_levels(); ++l) EXPECT_LE(aspect(h.mesh(l)), 1.5 * a0) << "level " << l;
}

TEST(Refine, GmshMeshKeepsItsPhysicalGroups) {
  const Mesh m = read_gmsh(std::string(VPC_TEST_DATA_DIR) + "/meshes/square.msh");
  const Refinement r = refine_uniform(m);
  EXPECT_EQ(r.fine.part_names(), m.part_names());
  for (const auto& p : m.part_names()) EXPECT_NEAR(part_measure(r.fine, p), part_measure(m, p), 1e-12) << p;
  EXPECT_NEAR(total_volume(r.fine), total_volume(m), 1e-12);
}

}  // namespace
}  // namespace vpc
