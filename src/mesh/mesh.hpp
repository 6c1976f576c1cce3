#pragma once
// Simplicial mesh in d = 1, 2, 3 with boundary facets grouped into named parts and
// cells into named regions. The generators and the Gmsh reader both produce this; a
// part (a region) is what a Gmsh physical group of dimension d − 1 (d) is, or what a
// case file's predicate names, so the rest of the code never knows where a mesh came from.
#include "core/sym_tensor.hpp"

#include <functional>
#include <string>
#include <vector>

namespace vpc {

class Mesh {
 public:
  Mesh() = default;
  explicit Mesh(int dim) : dim_(dim) {}

  int dim() const { return dim_; }
  int nodes_per_cell() const { return dim_ + 1; }
  int nodes_per_facet() const { return dim_; }
  int n_nodes() const { return static_cast<int>(x_.size()); }
  int n_cells() const { return static_cast<int>(cells_.size()) / nodes_per_cell(); }
  int n_facets() const { return static_cast<int>(facet_part_.size()); }

  const Point& node(int i) const { return x_[i]; }
  std::vector<Point>& nodes() { return x_; }
  const std::vector<Point>& nodes() const { return x_; }
  /// Node indices of cell c (dim + 1 of them).
  const int* cell(int c) const { return &cells_[static_cast<size_t>(c) * nodes_per_cell()]; }
  const int* facet(int f) const { return &facets_[static_cast<size_t>(f) * nodes_per_facet()]; }
  const std::vector<int>& cell_array() const { return cells_; }

  int add_node(const Point& p);
  void add_cell(const int* nodes);
  /// Adds a boundary facet in part `part` (created if new).
  void add_facet(const int* nodes, const std::string& part);

  /// Part of facet f; -1 when untagged.
  int facet_part(int f) const { return facet_part_[f]; }
  /// Puts facet f into part `part` (created if new; "" untags it).
  void set_facet_part(int f, const std::string& part);
  const std::vector<std::string>& part_names() const { return part_names_; }
  /// Index of a part, -1 if absent.
  int find_part(const std::string& name) const;
  /// Index of a part, created if absent.
  int part_id(const std::string& name);
  /// Number of facets in the part.
  int part_size(const std::string& name) const;

  /// Re-tags every boundary facet whose centroid satisfies `pred` as part `name`.
  /// Facets keep their earlier tag otherwise; later calls override earlier ones.
  void tag_facets(const std::string& name, const std::function<bool(const Point&)>& pred);

  Point facet_centroid(int f) const;
  Point cell_centroid(int c) const;
  /// Region of cell c (a Gmsh physical group of dimension d, or a material's
  /// `where`); -1 when untagged.
  int cell_region(int c) const { return cell_region_.empty() ? -1 : cell_region_[c]; }
  /// Puts cell c into region `region` (created if new).
  void set_cell_region(int c, const std::string& region);
  const std::vector<std::string>& region_names() const { return region_names_; }
  /// Index of a region, -1 if absent.
  int find_region(const std::string& name) const;
  /// Index of a region, created (without cells) if absent.
  int region_id(const std::string& name);
  /// Number of cells in the region.
  int region_size(const std::string& name) const;
  /// Re-tags every cell whose centroid satisfies `pred` as region `name`.
  void tag_cells(const std::string& name, const std::function<bool(const Point&)>& pred);

  /// The body of cell c (SPEC §8): 0 for the case's [mesh], k for the k-th mesh appended (append).
  int cell_body(int c) const { return cell_body_.empty() ? 0 : cell_body_[c]; }
  /// Bodies: 1 + the meshes appended.
  int n_bodies() const { return n_bodies_; }
  /// Puts cell c into body `body` (≥ 0; the bodies then number at least body + 1): a mesh made from
  /// another's cells (a bisection forest's leaves) keeps their bodies. Bodies still share no node.
  void set_cell_body(int c, int body);
  /// Appends `other` (of the same dimension) as a further body: its nodes, cells and boundary
  /// facets, none shared with the bodies already here (bodies meet through contact pairs, not
  /// nodes); its parts named "<name>.<part>" (untagged facets stay untagged) and its cells in
  /// region "<name>.<region>" where they have one. Returns the new body's index.
  int append(const Mesh& other, const std::string& name);

  /// The cell that boundary facet f bounds (found once for every facet, then kept).
  int facet_cell(int f) const;
  /// Outward unit normal of boundary facet f (needs the owning cell for orientation).
  Point facet_normal(int f) const;
  /// Measure (length/area; 1 for a point) of boundary facet f.
  double facet_measure(int f) const;

  /// Sorted unique nodes on the facets of the given parts.
  std::vector<int> nodes_of_parts(const std::vector<std::string>& parts) const;
  /// Facets belonging to any of the given parts.
  std::vector<int> facets_of_parts(const std::vector<std::string>& parts) const;

  /// Smallest and largest cell diameter (longest edge).
  std::pair<double, double> size_range() const;
  /// The smallest box holding the nodes: its lower and upper corners (all three coordinates).
  /// Needs a node.
  std::pair<Point, Point> bounding_box() const;

  /// Builds the boundary facets of the cell complex (facets used by one cell),
  /// all untagged; called by generators and readers after cells are added. With
  /// `keep`, only those whose centroid it accepts, and only those are counted: a
  /// generated box's sides, and on a block of it not the faces where it was cut
  /// (mesh/generators.hpp).
  void build_boundary(const std::function<bool(const Point&)>& keep = {});

 private:
  void find_facet_cells() const;

  int dim_ = 0;
  std::vector<Point> x_;
  std::vector<int> cells_;
  std::vector<int> facets_;
  std::vector<int> facet_part_;
  std::vector<std::string> part_names_;
  std::vector<int> cell_region_;  // per cell once a region exists; empty: every cell untagged
  std::vector<std::string> region_names_;
  mutable std::vector<int> facet_cell_;  // owning cell per facet, computed lazily
  std::vector<int> cell_body_;  // per cell once a body is appended; empty: every cell in body 0
  int n_bodies_ = 1;
};

/// The mean of the points x[v[0]], ..., x[v[n − 1]] (Mesh::cell_centroid's; a moved surface's cells
/// take theirs the same way: scheme/pair_slider.cpp).
Point centroid(const std::vector<Point>& x, const int* v, int n);

/// Measure (length, area, volume) of the simplex with vertices x[0..dim]:
/// |det J| / dim! with J = [x1 − x0, ..., xd − x0]; the element geometry of
/// fem/cell_geometry.hpp uses it, so a reader's degeneracy check sees the same value.
double simplex_measure(int dim, const Point* x);

}  // namespace vpc
