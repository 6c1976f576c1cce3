// The dual-mortar coupling (mortar/mortar_coupling): matching and non-matching flat
// meshes (D, M, consistency, linear reproduction), constant and tilted gaps, partial
// and sliver coverage, curved surfaces under refinement, and the user errors.
#include "../error_of.hpp"
#include "mortar/mortar_coupling.hpp"
#include "mortar/nodal_normals.hpp"
#include "surfaces.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <numbers>
#include <string>
#include <tuple>
#include <utility>

namespace vpc::mortar {
namespace {


/// M as a map (slave id, master id) -> value, checking there is one entry per pair.
std::map<std::pair<int, int>, double> m_map(const MortarCoupling& c) {
  std::map<std::pair<int, int>, double> m;
  for (const auto& t : c.m) {
    EXPECT_TRUE(std::isfinite(t.value()));
    EXPECT_TRUE(m.emplace(std::pair{t.row(), t.col()}, t.value()).second)
        << "repeated (" << t.row() << ", " << t.col() << ")";
  }
  return m;
}

/// Σ_k M_jk f(x_k^m) for each slave node (by its index), f = 1 gives the row sums.
std::vector<double> m_times(const MortarCoupling& c, const Surface& slave, const Surface& master,
                            const std::function<double(const Point&)>& f) {
  std::map<int, int> slave_of, master_of;
  for (int j = 0; j < slave.n_nodes(); ++j) slave_of[slave.id(j)] = j;
  for (int k = 0; k < master.n_nodes(); ++k) master_of[master.id(k)] = k;
  std::vector<double> out(slave.n_nodes(), 0.0);
  for (const auto& t : c.m) out[slave_of.at(t.row())] += t.value() * f(master.node(master_of.at(t.col())));
  return out;
}

/// What every coupling must satisfy: finite values, d ≥ 0, rows exactly for d > 0,
/// Σ_k M_jk = D_jj, Σ_j D_jj = covered_area, unit normals.
void expect_consistent(const MortarCoupling& c, const Surface& slave, const Surface& master) {
  ASSERT_EQ(c.nodes.size(), static_cast<size_t>(slave.n_nodes()));
  const auto sums = m_times(c, slave, master, [](const Point&) { return 1.0; });
  std::map<int, int> rows;
  for (const auto& t : c.m) ++rows[t.row()];
  double total = 0;
  for (int j = 0; j < slave.n_nodes(); ++j) {
    const SlaveNodeCoupling& n = c.nodes[j];
    EXPECT_EQ(n.id, slave.id(j));
    ASSERT_TRUE(std::isfinite(n.d) && std::isfinite(n.gap)) << "node " << j;
    EXPECT_GE(n.d, 0);
    EXPECT_EQ(rows.count(n.id) > 0, n.d > 0) << "node id " << n.id;
    if (n.d == 0) {
      EXPECT_EQ(n.gap, 0);
    }
    EXPECT_NEAR(sums[j], n.d, 1e-14 * (1 + n.d)) << "node id " << n.id;
    EXPECT_NEAR(vec(n.normal).norm(), 1, 1e-15);
    total += n.d;
  }
  EXPECT_NEAR(total, c.covered_area, 1e-14);
}

/// ∫_C Φ_j N_k = δ_jk ∫_C N_k on every slave facet where no node was merged (D_jk = 0 for
/// j ≠ k); returns how many facets were checked.
int expect_biorthogonal_facets(const Surface& slave, const Surface& master, double margin) {
  const auto normals = nodal_normals(slave);
  const FacetPairs pairs = candidate_pairs(slave, master, margin);
  int checked = 0;
  for (int e = 0; e < slave.n_facets(); ++e) {
    const auto covers = facet_cover(slave, normals, e, master, pairs.of(e), 1e-10);
    Eigen::Matrix3d mass = Eigen::Matrix3d::Zero();
    for (const auto& c : covers) add_covered_mass(c.points, mass);
    const DualBasis b = dual_basis(slave.dim(), mass);
    if (covers.empty() || b.merged[0] || b.merged[1] || (slave.dim() == 3 && b.merged[2])) continue;
    ++checked;
    for (int j = 0; j < slave.dim(); ++j)
      for (int k = 0; k < slave.dim(); ++k) {
        double phi_n = 0;
        for (const auto& c : covers)
          for (const auto& p : c.points) phi_n += p.weight * b.phi(j, p.slave) * p.slave[k];
        EXPECT_NEAR(phi_n, j == k ? mass.row(k).sum() : 0.0, 1e-14 * slave.measure(e))
            << "facet " << e << ", j = " << j << ", k = " << k;
      }
  }
  return checked;
}

const auto flat = [](double) { return 0.0; };

// Slave bodies lie below their surfaces (normal +y / +z), masters above.

TEST(MortarCoupling, MatchingFlatMeshesGiveMEqualToD) {
  const auto x2 = test::line_points(8, 0, 1, flat, 0.3);
  const Surface s2 = test::polyline(x2, 0, FacetOrder::Inward), m2 = test::polyline(x2, 100, FacetOrder::Outward);
  const Surface s3 = test::grid(5, 4, 0, 1, 0, 1, test::plane_at(0), 0, FacetOrder::Outward, false, 0.3);
  const Surface m3 = test::grid(5, 4, 0, 1, 0, 1, test::plane_at(0), 1000, FacetOrder::Inward, false, 0.3);
  for (const auto& [slave, master, offset] : {std::tuple{&s2, &m2, 100}, std::tuple{&s3, &m3, 1000}}) {
    SCOPED_TRACE(testing::Message() << slave->dim() << "D");
    const MortarCoupling c = mortar_coupling(*slave, *master);
    expect_consistent(c, *slave, *master);
    const auto m = m_map(c);
    for (const auto& [key, value] : m) {
      const auto& node = c.nodes[key.first];
      EXPECT_NEAR(value, key.second == key.first + offset ? node.d : 0.0, 1e-14) << key.first << ", " << key.second;
    }
    // D is the lumped slave mass ∫ N_j: Σ_e |e|/n over the node's facets.
    std::vector<double> lumped(slave->n_nodes(), 0.0);
    for (int e = 0; e < slave->n_facets(); ++e)
      for (int a = 0; a < slave->dim(); ++a) lumped[slave->facet(e)[a]] += slave->measure(e) / slave->dim();
    for (int j = 0; j < slave->n_nodes(); ++j) {
      EXPECT_NEAR(c.nodes[j].d, lumped[j], 1e-15) << "node " << j;
      EXPECT_NEAR(m.at({j, j + offset}), c.nodes[j].d, 1e-15);
    }
    EXPECT_NEAR(c.covered_area, 1, 1e-14);
  }
}

/// The non-matching pairs: slave and master in the same flat line/plane (at height h for
/// the master), the master larger, irregular, rotated (3D) and of another resolution.
std::pair<Surface, Surface> non_matching(int dim, double h, double tilt_x = 0, double tilt_y = 0) {
  if (dim == 2)
    return {test::polyline(test::line_points(7, 0, 1, flat, 0.3), 0, FacetOrder::Inward),
            test::polyline(test::line_points(
                               11, -0.1, 1.1, [=](double x) { return h + tilt_x * x; }, 0.4),
                           100, FacetOrder::Outward)};
  const auto master_plane = [=](double u, double v) { return Point{u, v, h + tilt_x * u + tilt_y * v}; };
  return {test::grid(6, 6, 0, 1, 0, 1, test::plane_at(0), 0, FacetOrder::Outward, false, 0.25),
          test::grid(9, 8, -0.5, 1.5, -0.5, 1.5, test::rotated(0.35, 0.5, 0.5, master_plane), 1000, FacetOrder::Inward,
                     true, 0.3)};
}

TEST(MortarCoupling, NonMatchingFlatMeshesAreConsistentAndReproduceLinearFields) {
  for (const int dim : {2, 3}) {
    SCOPED_TRACE(testing::Message() << dim << "D");
    const auto [slave, master] = non_matching(dim, 0);
    const MortarCoupling c = mortar_coupling(slave, master);
    expect_consistent(c, slave, master);
    EXPECT_NEAR(c.covered_area, 1, 1e-14);  // the unit segment / square
    // Σ_k M_jk f(x_k^m) = D_jj f(x_j^s) for a linear f.
    const auto f = [](const Point& x) { return 2 + 3 * x[0] - 1.5 * x[1]; };
    const auto mf = m_times(c, slave, master, f);
    for (int j = 0; j < slave.n_nodes(); ++j) {
      EXPECT_GT(c.nodes[j].d, 0);
      EXPECT_NEAR(mf[j], c.nodes[j].d * f(slave.node(j)), 1e-12) << "node " << j;
      EXPECT_NEAR(c.nodes[j].gap, 0, 1e-15);
    }
    // D_jk = 0 for j ≠ k on every facet (all fully covered: none merged).
    EXPECT_EQ(expect_biorthogonal_facets(slave, master, 0), slave.n_facets());
    // Not the matching case in disguise: M has more entries than slave nodes.
    EXPECT_GT(c.m.size(), 2u * slave.n_nodes());
  }
}

TEST(MortarCoupling, ParallelPlanesGiveTheGapTimesD) {
  const double g0 = 0.05;
  for (const int dim : {2, 3}) {
    SCOPED_TRACE(testing::Message() << dim << "D");
    const auto [slave, master] = non_matching(dim, g0);
    EXPECT_EQ(mortar_coupling(slave, master, {.search_margin = 0.04}).covered_area, 0);  // the gap is beyond the margin
    const MortarCoupling c = mortar_coupling(slave, master, {.search_margin = 0.06});
    expect_consistent(c, slave, master);
    for (const auto& n : c.nodes) {
      EXPECT_NEAR(n.gap, g0 * n.d, 1e-15) << "node id " << n.id;
      EXPECT_NEAR(n.normal[dim - 1], 1, 1e-15);
    }
  }
}

TEST(MortarCoupling, TiltedMasterReproducesTheLinearGap) {
  // Master z = g0 + a x + b y above a flat slave: the gap along the slave normal is that
  // linear function, and g̃_j = D_jj g(x_j) in the weighted sense.
  const double g0 = 0.05, a = 0.1, b = -0.04;
  for (const int dim : {2, 3}) {
    SCOPED_TRACE(testing::Message() << dim << "D");
    const auto [slave, master] = non_matching(dim, g0, a, b);
    const MortarCoupling c = mortar_coupling(slave, master, {.search_margin = 0.2});
    expect_consistent(c, slave, master);
    EXPECT_NEAR(c.covered_area, 1, 1e-14);
    for (int j = 0; j < slave.n_nodes(); ++j) {
      const Point& x = slave.node(j);
      const double gap = g0 + a * x[0] + (dim == 3 ? b * x[1] : 0.0);
      EXPECT_NEAR(c.nodes[j].gap, c.nodes[j].d * gap, 1e-15) << "node " << j;
    }
  }
}

TEST(MortarCoupling, PartialCoverageLeavesUncoveredNodesOutAndStaysBiorthogonal) {
  const double g0 = 0.02;
  // 2D: the master covers x ∈ [0.33, 0.71] of the slave [0, 1] (10 segments).
  const Surface s2 = test::polyline(test::line_points(10, 0, 1, flat), 0, FacetOrder::Inward);
  const Surface m2 =
      test::polyline(test::line_points(5, 0.33, 0.71, [=](double) { return g0; }), 100, FacetOrder::Outward);
  // 3D: a square of side 0.4 turned by 30° about (0.5, 0.5), inside the slave's unit square.
  const Surface s3 = test::grid(8, 8, 0, 1, 0, 1, test::plane_at(0), 0, FacetOrder::Outward);
  const Surface m3 =
      test::grid(3, 3, 0.3, 0.7, 0.3, 0.7, test::rotated(std::numbers::pi / 6, 0.5, 0.5, test::plane_at(g0)), 1000,
                 FacetOrder::Inward, true, 0.2);
  for (const auto& [slave, master, area] : {std::tuple{&s2, &m2, 0.38}, std::tuple{&s3, &m3, 0.16}}) {
    SCOPED_TRACE(testing::Message() << slave->dim() << "D");
    const MortarCoupling c = mortar_coupling(*slave, *master, {.search_margin = 0.05});
    expect_consistent(c, *slave, *master);
    EXPECT_NEAR(c.covered_area, area, 1e-14);
    int uncovered = 0;
    for (int j = 0; j < slave->n_nodes(); ++j) {
      const auto& n = c.nodes[j];
      EXPECT_NEAR(n.gap, g0 * n.d, 1e-15);
      // A node none of whose facets meets the master's extent has no D and no row.
      double dist = 1;
      for (int k = 0; k < master->n_nodes(); ++k)
        dist = std::min(dist, (vec(slave->node(j)) - vec(master->node(k))).head(slave->dim() - 1).norm());
      if (dist > 0.25) {
        EXPECT_EQ(n.d, 0) << "node " << j;
        ++uncovered;
      }
    }
    EXPECT_GT(uncovered, 0);
    // The partly covered facets with no merged node are biorthogonal on their covered part.
    const int checked = expect_biorthogonal_facets(*slave, *master, 0.05);
    EXPECT_GT(checked, slave->dim() == 2 ? 4 : 10);
  }
}

TEST(MortarCoupling, SliversOfCoverageStayFiniteAndKeepTheArea) {
  // The master's edges lie 1e-9 (and 1e-14) inside slave facets: those facets' far
  // nodes would get coefficients ~1e9; they are merged instead.
  for (const double sliver : {1e-9, 1e-14}) {
    SCOPED_TRACE(testing::Message() << "sliver " << sliver);
    const Surface s2 = test::polyline(test::line_points(10, 0, 1, flat), 0, FacetOrder::Inward);
    const Surface m2 =
        test::polyline(test::line_points(3, 0.3 - sliver, 0.6, [](double) { return 0.01; }), 100, FacetOrder::Outward);
    const Surface s3 = test::grid(4, 4, 0, 1, 0, 1, test::plane_at(0), 0, FacetOrder::Outward);
    const Surface m3 = test::grid(3, 2, 0.25 - sliver, 0.75, 0.25 - sliver, 0.75, test::plane_at(0.01), 1000,
                                  FacetOrder::Inward, true);
    // A sliver below clip_tolerance (1e-10 of a facet) is dropped.
    const double kept = sliver > 1e-10 ? sliver : 0;
    for (const auto& [slave, master, area] :
         {std::tuple{&s2, &m2, 0.3 + kept}, std::tuple{&s3, &m3, (0.5 + kept) * (0.5 + kept)}}) {
      SCOPED_TRACE(testing::Message() << slave->dim() << "D");
      const MortarCoupling c = mortar_coupling(*slave, *master, {.search_margin = 0.02});
      expect_consistent(c, *slave, *master);
      EXPECT_NEAR(c.covered_area, area, 5e-14);
      // No row extrapolates wildly: |M_jk| ≤ bound · D_jj.
      for (const auto& t : c.m) {
        const auto& n = *std::find_if(c.nodes.begin(), c.nodes.end(), [&](const auto& x) { return x.id == t.row(); });
        EXPECT_LE(std::abs(t.value()), kDualCoefficientBound * n.d) << t.row() << ", " << t.col();
      }
    }
  }
}

/// Σ D − the true length/area, and max_j |g̃_j| / D_jj, for a curved pair refined n times.
struct CurvedErrors {
  double area, gap;
};

CurvedErrors arc_errors(int level) {
  // The slave: an arc of the unit circle of length 1 on a disc (normals outward); the
  // master: a longer arc of the same circle bounding the body outside it.
  const int n_s = 8 << level, n_m = 13 << level;
  const auto arc = [](int n, double half) {
    std::vector<Point> x;
    for (int i = 0; i <= n; ++i) {
      const double t = std::numbers::pi / 2 - half + 2 * half * i / n;
      x.push_back({std::cos(t), std::sin(t), 0});
    }
    return x;
  };
  const Surface slave = test::polyline(arc(n_s, 0.5), 0, FacetOrder::Outward);
  const Surface master = test::polyline(arc(n_m, 0.6), 1000, FacetOrder::Inward);
  const MortarCoupling c = mortar_coupling(slave, master, {.search_margin = 0.05});
  expect_consistent(c, slave, master);
  CurvedErrors e{std::abs(c.covered_area - 1.0), 0};
  for (const auto& n : c.nodes) e.gap = std::max(e.gap, std::abs(n.gap) / n.d);
  return e;
}

CurvedErrors cap_errors(int level) {
  // Gnomonic grids on the unit sphere: (u, v, 1)/|(u, v, 1)|. The slave is the image of
  // [−a, a]², of area 4 atan(a² / √(1 + 2a²)); the master that of a larger square turned
  // by 0.3 rad, bounding the body outside the sphere.
  const double a = 0.4;
  const auto gnomonic = [](double u, double v) {
    const double r = std::sqrt(u * u + v * v + 1);
    return Point{u / r, v / r, 1 / r};
  };
  const int n_s = 4 << level, n_m = 7 << level;
  const Surface slave = test::grid(n_s, n_s, -a, a, -a, a, gnomonic, 0, FacetOrder::Outward);
  const Surface master =
      test::grid(n_m, n_m, -0.6, 0.6, -0.6, 0.6, test::rotated(0.3, 0, 0, gnomonic), 100000, FacetOrder::Inward, true);
  const MortarCoupling c = mortar_coupling(slave, master, {.search_margin = 0.05});
  expect_consistent(c, slave, master);
  CurvedErrors e{std::abs(c.covered_area - 4 * std::atan(a * a / std::sqrt(1 + 2 * a * a))), 0};
  for (const auto& n : c.nodes) e.gap = std::max(e.gap, std::abs(n.gap) / n.d);
  return e;
}

TEST(MortarCoupling, CurvedSurfacesConvergeAtSecondOrder) {
  // Two non-matching discretizations of one arc / sphere patch: Σ D tends to the true
  // length/area and the gap seen by each node to 0, both by ~4x when h halves.
  for (const auto& [name, errors] : {std::pair{"arc", &arc_errors}, std::pair{"sphere cap", &cap_errors}}) {
    SCOPED_TRACE(name);
    // Each halving gives 3-5x (the non-matching pattern shifts), three of them ~64x.
    const CurvedErrors first = errors(0);
    CurvedErrors last = first;
    for (int level = 1; level <= 3; ++level) {
      const CurvedErrors e = errors(level);
      SCOPED_TRACE(testing::Message() << "level " << level << ": area error " << e.area << ", gap " << e.gap);
      EXPECT_NEAR(last.area / e.area, 4, 0.3);
      EXPECT_NEAR(last.gap / e.gap, 4, 1);
      last = e;
    }
    EXPECT_NEAR(std::log2(first.area / last.area) / 3, 2, 0.05);
    EXPECT_NEAR(std::log2(first.gap / last.gap) / 3, 2, 0.1);
    EXPECT_LT(last.gap, 1e-3);
  }
}

TEST(MortarCoupling, RejectsSurfacesThatDoNotFaceEachOther) {
  // The master ordered as if its body were below it, like the slave's.
  const Surface slave = test::grid(3, 3, 0, 1, 0, 1, test::plane_at(0), 0, FacetOrder::Outward);
  const Surface wrong = test::grid(4, 4, 0, 1, 0, 1, test::plane_at(0.01), 100, FacetOrder::Outward);
  expect_error([&] { mortar_coupling(slave, wrong, {.search_margin = 0.02}); },
               "candidate pairs of slave and master facets face each other");
  const Surface line = test::polyline(test::line_points(3, 0, 1, flat), 0, FacetOrder::Inward);
  expect_error([&] { mortar_coupling(slave, line); }, "the slave surface is 3D and the master 2D");
  expect_error([&] { mortar_coupling(slave, slave, {.coefficient_bound = 2}); }, "coefficient_bound");
  expect_error([&] { mortar_coupling(slave, slave, {.search_margin = -1}); }, "margin is -1");
}

TEST(MortarCoupling, LeavesOutMasterNodesTheSlaveNormalsDoNotReach) {
  // A right-angled valley: the normal lines of each side all pass through (0, 2). A
  // master node across the valley, or at that height, is reached by none of one side's
  // normal lines; the overlap then ends at the slave node whose normal meets the master
  // (no error), and a master outside the region the normal lines sweep does not couple.
  const Surface slave = test::polyline({{-1, 1, 0}, {0, 0, 0}, {1, 1, 0}}, 0, FacetOrder::Inward);
  for (const double y : {0.5, 1.0, 1.5})
    for (const double x : {0.0, 0.3, 0.7}) {
      SCOPED_TRACE(testing::Message() << "master at (" << x << ", " << y << ")");
      const Surface master = test::polyline({{x - 0.2, y, 0}, {x + 0.2, y + 0.01, 0}}, 100, FacetOrder::Outward);
      const MortarCoupling c = mortar_coupling(slave, master, {.search_margin = 10});
      expect_consistent(c, slave, master);
      // The right side's normal lines sweep the triangle x ≥ 0, y ≥ x, x + y ≤ 2 (the
      // left side's its mirror image): a master whose middle lies there couples.
      if (std::abs(x) + y < 2) {
        EXPECT_GT(c.covered_area, 0);
      } else {
        EXPECT_EQ(c.covered_area, 0);
      }
    }
}

}  // namespace
}  // namespace vpc::mortar
