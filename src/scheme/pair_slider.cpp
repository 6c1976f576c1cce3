#include "scheme/pair_slider.hpp"

#include "core/error.hpp"
#include "la/comm.hpp"
#include "problem/contact_pairs.hpp"

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace vpc {

namespace {

/// No pair slides large: the set-up's rows stay, and K_local goes.
class FixedPairs final : public PairSlider {
 public:
  void keep_stiffness(SparseMatrix& K_local) override {
    // Swapped out, not assigned an empty matrix: Eigen keeps a sparse matrix's storage through
    // assignment (0.29 GB a rank at foundation-3d n = 70).
    SparseMatrix().swap(K_local);
  }
  std::shared_ptr<const ContactSet> slide(const DiscreteSystem&, const Vector&) override { return nullptr; }
  const SparseMatrix& stiffness() const override { return none_; }

 private:
  SparseMatrix none_;
};

class LargeSliding final : public PairSlider {
 public:
  explicit LargeSliding(const DiscreteSystem& sys) : slid_at_(Vector::Zero(sys.part.dofs.n_full())) {}

  void keep_stiffness(SparseMatrix& K_local) override { K_local_.swap(K_local); }

  std::shared_ptr<const ContactSet> slide(const DiscreteSystem& sys, const Vector& u) override {
    // Collective: every rank decides alike (a rank's own u may not have moved where another's has).
    if (sys.part.comm.all(slid_at_ == u)) return nullptr;
    auto moved = std::make_shared<const ContactSet>(
        sys.contact->moved(*sys.problem, sys.part, moved_nodes(sys, u)));
    slid_at_ = u;
    return moved;
  }
  const SparseMatrix& stiffness() const override { return K_local_; }

 private:
  static bool sliding(const Problem& p, const ContactNode& n) {
    return n.pair >= 0 && p.contact.pairs[static_cast<std::size_t>(n.pair)].large_sliding;
  }

  /// The rows of the part's sliding pieces (MeshPart::sliding) at x + u, by slave node (the part's).
  /// Collective: a moved surface that fails (a facet turned inside out) fails every rank, and a
  /// pair's default search distance is its whole slave side's longest edge, over every rank's piece.
  static std::map<int, ContactRow> moved_rows(const DiscreteSystem& sys, const Vector& u) {
    const Problem& p = *sys.problem;
    const MeshPart& part = sys.part;
    const Mesh& mesh = part.mesh();
    const int d = mesh.dim();
    const auto x = [&](int l) {
      Point y = mesh.node(l);
      for (int i = 0; i < d; ++i) y[static_cast<std::size_t>(i)] += u[l * d + i];
      return y;
    };
    std::vector<std::pair<mortar::Surface, mortar::Surface>> moved;  // per piece: slave, master
    std::map<int, double> longest;                                    // per large-sliding pair
    for (const std::size_t q : p.contact.sliding_pairs(true)) longest[static_cast<int>(q)] = 0;
    la::collective(part.comm, [&] {
      for (const SlidingPairPiece& s : part.sliding)
        located(p.where(fmt::format("contact.pair[{}]", s.pair)), [&] {
          moved.emplace_back(sliding_surface(d, mesh.nodes_per_cell(), s.slave, x),
                             sliding_surface(d, mesh.nodes_per_cell(), s.master, x));
          longest[s.pair] = moved.back().first.longest_edge();
        });
    });
    for (auto& [q, h] : longest) h = part.comm.max(h);
    std::vector<ContactRow> rows;
    la::collective(part.comm, [&] {
      const FixedAt fixed_at = [&](int l) { return part.dirichlet.data() + static_cast<std::size_t>(l) * d; };
      for (std::size_t k = 0; k < moved.size(); ++k) {
        const int q = part.sliding[k].pair;
        const double search = search_margin(p.contact.pairs[static_cast<std::size_t>(q)], longest.at(q));
        add_pair_rows(p, static_cast<std::size_t>(q), moved[k].first, moved[k].second, fixed_at, nullptr, search, rows);
      }
    });
    sort_rows_by_node(rows);
    std::map<int, ContactRow> row_of;
    for (ContactRow& r : rows) row_of[r.node] = std::move(r);
    return row_of;
  }

  /// sys.contact's nodes with the owned sliding nodes' rows at x + u, their bounds written on u_n.
  static std::vector<PartContactNode> moved_nodes(const DiscreteSystem& sys, const Vector& u) {
    const Problem& p = *sys.problem;
    const int d = sys.part.mesh().dim();
    const std::map<int, ContactRow> row_of = moved_rows(sys, u);
    std::vector<PartContactNode> nodes = sys.contact->nodes;
    for (PartContactNode& node : nodes) {
      if (!node.owned || !sliding(p, node)) continue;  // a ghost row is its owner's to move
      const auto it = row_of.find(node.local_node);
      if (it == row_of.end()) {  // no master facet within reach: the node cannot touch this step
        node.masters.clear();
        node.gap = sys.contact->miss_gap;
        for (int i = 0; i < d; ++i) node.gap += node.direction[static_cast<std::size_t>(i)] * u[node.local_node * d + i];
        continue;
      }
      const ContactRow& r = it->second;
      static_cast<ContactNode&>(node) = r;  // the pair's law, its obstacles (none) and index are the node's already
      // The bound of N u_n: g(x + u) + ν·u_j − Σ_k w_k ν·u_k (all components: a master's prescribed
      // ones join at t_n in step_data.cpp, so their increment is what moves the bound). The row's
      // nodes are the part's already.
      double bound = r.gap;
      for (int i = 0; i < d; ++i) bound += r.direction[static_cast<std::size_t>(i)] * u[node.local_node * d + i];
      for (const auto& [l, w] : r.masters)
        for (int i = 0; i < d; ++i) bound -= w * r.direction[static_cast<std::size_t>(i)] * u[l * d + i];
      node.gap = bound;
    }
    return nodes;
  }

  Vector slid_at_;  // the displacement the rows were built at
  SparseMatrix K_local_;
};

}  // namespace

std::unique_ptr<PairSlider> make_pair_slider(const DiscreteSystem& sys) {
  if (!sys.problem->contact.sliding_pairs(true).empty()) return std::make_unique<LargeSliding>(sys);
  return std::make_unique<FixedPairs>();
}

}  // namespace vpc
