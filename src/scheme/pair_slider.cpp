#include "scheme/pair_slider.hpp"

#include "core/error.hpp"
#include "la/comm.hpp"
#include "scheme/contact_pairs.hpp"

#include <algorithm>
#include <array>
#include <map>
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
  void slide(DiscreteSystem&, const Vector&, const SolverChoice&, SchemeSolvers&) override {}
};

/// One side of a large-sliding pair: its surface's facets (surface_facets) over a band of the mesh's
/// nodes (the surface's and those of the cells behind its facets), kept in the reference
/// configuration.
struct SlidingSide {
  SurfaceFacets facets;
  std::vector<int> node_band;  // per surface node (facets.ids): its band node
  std::vector<int> cell_band;  // per facet, its cell's nodes (band nodes, the cell's order)
};

class LargeSliding final : public PairSlider {
 public:
  explicit LargeSliding(const DiscreteSystem& sys) : slid_at_(Vector::Zero(sys.part.dofs.n_full())) {
    const Problem& p = *sys.problem;
    const MeshPart& part = sys.part;
    // Every node of a sliding pair's parts is one rank's (own_pairs_together): another has none of
    // their rows and keeps nothing here.
    if (std::ranges::none_of(part.contact, [&](const PartContactNode& n) { return sliding(p, n); })) return;
    require(p.mesh.n_nodes() > 0, "internal: the rows of a sliding pair on a rank without the whole mesh");
    const Mesh& mesh = p.mesh;
    npc_ = mesh.nodes_per_cell();
    const DirichletDofs dirichlet = dirichlet_dofs(p);
    std::map<int, int> local;  // original node -> the part's
    for (int l = 0; l < part.mesh().n_nodes(); ++l) local[part.original_node[static_cast<std::size_t>(l)]] = l;
    auto band = [&](int node) {
      const auto [it, fresh] = band_of_.emplace(node, static_cast<int>(x_.size()));
      if (fresh) {
        x_.push_back(mesh.node(node));
        const auto l = local.find(node);
        local_.push_back(l == local.end() ? -1 : l->second);  // outside the part: it stays where it was
      }
      return it->second;
    };
    for (std::size_t q = 0; q < p.contact.pairs.size(); ++q) {
      const ContactPair& pair = p.contact.pairs[q];
      if (!pair.large_sliding) continue;
      const std::string where = p.where(fmt::format("contact.pair[{}]", q));
      std::array<SlidingSide, 2> sides;
      for (int s = 0; s < 2; ++s) {
        SlidingSide& side = sides[static_cast<std::size_t>(s)];
        side.facets = located(where, [&] { return surface_facets(mesh, s == 0 ? pair.slave : pair.master); });
        for (int node : side.facets.ids) side.node_band.push_back(band(node));
        for (int c : side.facets.cells)
          for (int a = 0; a < npc_; ++a) side.cell_band.push_back(band(mesh.cell(c)[a]));
      }
      for (int node : sides[0].facets.ids) {  // the slave nodes' prescribed dofs (add_pair_rows)
        std::array<int, 3>& f = condition_[node];
        f.fill(-1);
        std::copy_n(dirichlet.condition.begin() + static_cast<std::ptrdiff_t>(node) * mesh.dim(), mesh.dim(), f.begin());
      }
      pairs_.push_back({q, std::move(sides[0]), std::move(sides[1])});
    }
  }

  void keep_stiffness(SparseMatrix& K_local) override { K_local_.swap(K_local); }

  void slide(DiscreteSystem& sys, const Vector& u, const SolverChoice& choice, SchemeSolvers& solvers) override {
    // Collective: every rank decides alike (a rank's own u may not have moved where another's has).
    if (sys.part.comm.all(slid_at_ == u)) return;
    // A moved surface that fails (a facet turned inside out) fails every rank, not the one that rebuilds.
    la::collective(sys.part.comm, [&] {
      if (!pairs_.empty()) move_rows(sys, u);
    });
    remake_contact_solver(sys, choice, solvers, K_local_);
    slid_at_ = u;
  }

 private:
  struct SlidingPair {
    std::size_t q;
    SlidingSide slave, master;
  };

  static bool sliding(const Problem& p, const ContactNode& n) {
    return n.pair >= 0 && p.contact.pairs[static_cast<std::size_t>(n.pair)].large_sliding;
  }

  /// A side's surface at x + u: its nodes moved, each facet oriented away from its moved cell's centroid.
  mortar::Surface moved_surface(int d, const SlidingSide& side, const std::vector<Point>& x) const {
    std::vector<Point> nodes, inside;
    for (int b : side.node_band) nodes.push_back(x[static_cast<std::size_t>(b)]);
    for (std::size_t f = 0; f < side.facets.cells.size(); ++f)
      inside.push_back(centroid(x, side.cell_band.data() + f * static_cast<std::size_t>(npc_), npc_));
    return oriented_surface(d, side.facets, std::move(nodes), inside);
  }

  void move_rows(DiscreteSystem& sys, const Vector& u) const {
    const Problem& p = *sys.problem;
    MeshPart& part = sys.part;
    const int d = part.mesh().dim();
    std::vector<Point> x = x_;  // the band at x + u
    for (std::size_t b = 0; b < x.size(); ++b)
      if (local_[b] >= 0)
        for (int i = 0; i < d; ++i) x[b][static_cast<std::size_t>(i)] += u[local_[b] * d + i];
    const FixedAt fixed_at = [&](int node) { return condition_.at(node).data(); };
    std::vector<ContactRow> rows;
    for (const SlidingPair& s : pairs_) {
      const std::string where = p.where(fmt::format("contact.pair[{}]", s.q));
      const mortar::Surface slave = located(where, [&] { return moved_surface(d, s.slave, x); });
      const mortar::Surface master = located(where, [&] { return moved_surface(d, s.master, x); });
      add_pair_rows(p, s.q, slave, master, fixed_at, nullptr, rows);
    }
    sort_rows_by_node(rows);
    std::map<int, const ContactRow*> row_of;  // slave node (original) -> its row in the moved configuration
    for (const ContactRow& r : rows) row_of[r.node] = &r;
    for (PartContactNode& node : part.contact) {
      if (!sliding(p, node)) continue;
      const int o = part.original_node[static_cast<std::size_t>(node.local_node)];
      const auto it = row_of.find(o);
      if (it == row_of.end()) {  // no master facet within reach: the node cannot touch this step
        node.masters.clear();
        node.gap = sys.contact.miss_gap;
        for (int i = 0; i < d; ++i) node.gap += node.direction[static_cast<std::size_t>(i)] * u[node.local_node * d + i];
        continue;
      }
      const ContactRow& r = *it->second;
      static_cast<ContactNode&>(node) = r;  // the pair's law, its obstacles (none) and index are the node's already
      node.masters.clear();
      // The bound of N u_n: g(x + u) + ν·u_j − Σ_k w_k ν·u_k (all components: a master's prescribed
      // ones join at t_n in step_data.cpp, so their increment is what moves the bound).
      double bound = r.gap;
      for (int i = 0; i < d; ++i) bound += r.direction[static_cast<std::size_t>(i)] * u[node.local_node * d + i];
      for (const auto& [k, w] : r.masters) {
        const int l = local_[static_cast<std::size_t>(band_of_.at(k))];
        require(l >= 0, "internal: master node {} of a sliding pair is not on the rank of its slave", k);
        node.masters.emplace_back(l, w);
        for (int i = 0; i < d; ++i) bound -= w * r.direction[static_cast<std::size_t>(i)] * u[l * d + i];
      }
      node.gap = bound;
    }
    sys.contact.set_rows(p, part);
  }

  Vector slid_at_;  // the displacement the rows were built at
  SparseMatrix K_local_;
  std::vector<SlidingPair> pairs_;  // the large-sliding pairs (none on a rank without their rows)
  int npc_ = 0;
  std::vector<Point> x_;                          // the band's nodes, reference positions
  std::vector<int> local_;                        // per band node: the part's node (−1: none)
  std::map<int, int> band_of_;                    // mesh node -> band node
  std::map<int, std::array<int, 3>> condition_;  // slave node -> its prescribed dofs' condition
};

}  // namespace

std::unique_ptr<PairSlider> make_pair_slider(const DiscreteSystem& sys) {
  if (std::ranges::any_of(sys.problem->contact.pairs, [](const ContactPair& q) { return q.large_sliding; }))
    return std::make_unique<LargeSliding>(sys);
  return std::make_unique<FixedPairs>();
}

}  // namespace vpc
