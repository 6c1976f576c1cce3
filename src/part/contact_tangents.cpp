#include "part/contact_tangents.hpp"

#include "part/contact_matrix.hpp"
#include "solvers/contact_solver.hpp"

#include <utility>

namespace vpc {

std::vector<Point> contact_tangents(const DofMap& dofs, std::span<const PartContactNode> nodes, int block) {
  if (block <= 1 || nodes.empty()) return {};
  // The part's contact rows over their own free dofs alone (ContactColumns::compact), ghosts
  // included: set_tangents then gives each row the solver's tangents (the frame of a row uses
  // only its own entries and dofs), at a cost of the contact nodes only.
  ContactMatrix rows = contact_matrix(dofs, nodes, ContactColumns::compact);
  ContactConstraints c;
  c.block = block;
  c.rows.assign(nodes.size(), 0);
  c.N = std::move(rows.N);
  set_tangents(c, rows.node_dofs);
  // Row k(b − 1) + j of T is tangent j of entry k: its entries by component.
  const SparseMatrix Tt = c.T.transpose();
  std::vector<Point> out(nodes.size() * static_cast<std::size_t>(block - 1), Point{0, 0, 0});
  for (int row = 0; row < Tt.outerSize(); ++row)
    for (SparseMatrix::InnerIterator it(Tt, row); it; ++it) {
      const int i = rows.component[static_cast<std::size_t>(it.row())];
      out[static_cast<std::size_t>(row)][static_cast<std::size_t>(i)] = it.value();
    }
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
