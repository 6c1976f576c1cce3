#pragma once
// Contact surfaces for the mortar tests: polylines (2D) and triangulated grids mapped
// onto a surface (3D), with node ids from a chosen first id.
#include "mortar/surface.hpp"

#include <cmath>
#include <functional>
#include <vector>

namespace vpc::mortar::test {

/// Segments between consecutive points; `order` says where the body is (Outward: on
/// the left walking from point i to i + 1).
inline Surface polyline(const std::vector<Point>& x, int first_id, FacetOrder order) {
  std::vector<int> ids, facets;
  for (int i = 0; i < static_cast<int>(x.size()); ++i) ids.push_back(first_id + i);
  for (int i = 0; i + 1 < static_cast<int>(x.size()); ++i) facets.insert(facets.end(), {i, i + 1});
  return Surface(2, x, ids, facets, order);
}

/// n + 1 points from x0 to x1 on y = f(x); `jitter` moves the inner points by up to
/// that share of a segment (deterministically), for irregular meshes.
inline std::vector<Point> line_points(int n, double x0, double x1, const std::function<double(double)>& f,
                                      double jitter = 0) {
  std::vector<Point> x;
  for (int i = 0; i <= n; ++i) {
    double s = x0 + (x1 - x0) * i / n;
    if (i > 0 && i < n) s += jitter * (x1 - x0) / n * std::sin(7.3 * i + 1.1);
    x.push_back({s, f(s), 0});
  }
  return x;
}

/// An nx × ny grid of (u, v) ∈ [u0, u1] × [v0, v1] mapped to 3D by `map`, each cell
/// split into two triangles (along the diagonal (i, j)-(i+1, j+1), or the other one
/// when `other_diagonal`), counter-clockwise in (u, v). `jitter` moves inner grid points
/// by up to that share of a cell.
inline Surface grid(int nx, int ny, double u0, double u1, double v0, double v1,
                    const std::function<Point(double, double)>& map, int first_id, FacetOrder order,
                    bool other_diagonal = false, double jitter = 0) {
  std::vector<Point> x;
  std::vector<int> ids, facets;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      double u = u0 + (u1 - u0) * i / nx, v = v0 + (v1 - v0) * j / ny;
      if (i > 0 && i < nx && j > 0 && j < ny) {
        u += jitter * (u1 - u0) / nx * std::sin(3.7 * i + 5.3 * j + 0.3);
        v += jitter * (v1 - v0) / ny * std::cos(4.1 * i - 2.9 * j + 0.7);
      }
      x.push_back(map(u, v));
      ids.push_back(first_id + static_cast<int>(ids.size()));
    }
  const auto node = [&](int i, int j) { return j * (nx + 1) + i; };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int a = node(i, j), b = node(i + 1, j), c = node(i + 1, j + 1), d = node(i, j + 1);
      if (other_diagonal)
        facets.insert(facets.end(), {a, b, d, b, c, d});
      else
        facets.insert(facets.end(), {a, b, c, a, c, d});
    }
  return Surface(3, x, ids, facets, order);
}

/// The plane z = h: (u, v) -> (u, v, h).
inline std::function<Point(double, double)> plane_at(double h) {
  return [h](double u, double v) { return Point{u, v, h}; };
}

/// (u, v) rotated by angle about (cu, cv), then mapped by `map`.
inline std::function<Point(double, double)> rotated(double angle, double cu, double cv,
                                                    std::function<Point(double, double)> map) {
  return [=](double u, double v) {
    const double c = std::cos(angle), s = std::sin(angle);
    return map(cu + c * (u - cu) - s * (v - cv), cv + s * (u - cu) + c * (v - cv));
  };
}

}  // namespace vpc::mortar::test
