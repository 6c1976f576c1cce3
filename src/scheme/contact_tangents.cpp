#include "scheme/contact_tangents.hpp"

#include "solvers/contact_solver.hpp"

namespace vpc {

std::vector<Point> contact_tangents(const MeshPart& part, int block) {
  if (block <= 1 || part.contact.empty()) return {};
  const DofMap& dofs = part.dofs;
  const int d = dofs.dim();
  const auto rows = part.contact.size();
  // N over the contact nodes' free dofs alone (numbered compactly, node after node, in
  // component order: the order of the part's free dofs within a node), one row per contact
  // node, ghosts included, and each node's free dofs: set_tangents then gives each row the
  // solver's tangents (the frame of a row uses only its own entries and dofs), at a cost of
  // the contact nodes only.
  ContactConstraints c;
  c.block = block;
  c.rows.assign(rows, 0);
  std::vector<Eigen::Triplet<double>> entries;
  std::vector<std::vector<int>> node_dofs(rows);
  std::vector<int> component;  // per compact dof
  for (std::size_t k = 0; k < rows; ++k) {
    const PartContactNode& node = part.contact[k];
    for (int i = 0; i < d; ++i) {
      if (dofs.free_index(dofs.full_index(node.local_node, i)) < 0) continue;
      const auto dof = static_cast<int>(component.size());
      component.push_back(i);
      node_dofs[k].push_back(dof);
      if (node.direction[i] != 0) entries.emplace_back(static_cast<int>(k), dof, node.direction[i]);
    }
  }
  c.N.resize(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(component.size()));
  c.N.setFromTriplets(entries.begin(), entries.end());
  set_tangents(c, node_dofs);
  // Row k(b − 1) + j of T is tangent j of entry k: its entries by component.
  const SparseMatrix Tt = c.T.transpose();
  std::vector<Point> out(rows * static_cast<std::size_t>(block - 1), Point{0, 0, 0});
  for (int row = 0; row < Tt.outerSize(); ++row)
    for (SparseMatrix::InnerIterator it(Tt, row); it; ++it)
      out[static_cast<std::size_t>(row)][static_cast<std::size_t>(component[static_cast<std::size_t>(it.row())])] =
          it.value();
  return out;
}

Point along_tangents(std::span<const Point> tangents, std::size_t k, int block, const double* x) {
  Point v{0, 0, 0};
  const auto t = static_cast<std::size_t>(block - 1);
  for (std::size_t j = 0; j < t; ++j)
    for (std::size_t i = 0; i < 3; ++i) v[i] += x[j] * tangents[k * t + j][i];
  return v;
}

}  // namespace vpc
