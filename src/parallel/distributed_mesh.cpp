#include "parallel/distributed_mesh.hpp"

#include "la/petsc.hpp"
#include "mesh/node_cells.hpp"
#include "part/part_cut.hpp"

#include <petscmat.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <unordered_map>
#include <utility>

namespace vpc {

namespace {

/// Cell partition by PTScotch on the dual graph (cells sharing a facet, i.e. d nodes).
std::vector<int> partition_cells(const Mesh& mesh, const NodeCells& nc, int n_parts) {
  const int n_cells = mesh.n_cells(), npc = mesh.nodes_per_cell(), d = mesh.dim();
  std::vector<int> part(n_cells, 0);
  if (n_parts == 1 || n_cells == 0) return part;
  std::vector<PetscInt> ia(n_cells + 1, 0), ja;
  std::vector<int> cand;
  for (int c = 0; c < n_cells; ++c) {
    cand.clear();
    for (int a = 0; a < npc; ++a) {
      const int v = mesh.cell(c)[a];
      for (int k = nc.start[v]; k < nc.start[v + 1]; ++k)
        if (nc.list[k] != c) cand.push_back(nc.list[k]);
    }
    std::sort(cand.begin(), cand.end());
    for (size_t i = 0; i < cand.size();) {
      size_t j = i;
      while (j < cand.size() && cand[j] == cand[i]) ++j;
      if (static_cast<int>(j - i) >= d) ja.push_back(cand[i]);
      i = j;
    }
    ia[c + 1] = static_cast<PetscInt>(ja.size());
  }
  // MatCreateMPIAdj takes ownership of arrays allocated with PetscMalloc.
  PetscInt *pia = nullptr, *pja = nullptr;
  VPC_PETSC(PetscMalloc1(ia.size(), &pia));
  VPC_PETSC(PetscMalloc1(std::max<size_t>(ja.size(), 1), &pja));
  std::copy(ia.begin(), ia.end(), pia);
  std::copy(ja.begin(), ja.end(), pja);
  PMat adj;
  VPC_PETSC(MatCreateMPIAdj(PETSC_COMM_SELF, n_cells, n_cells, pia, pja, nullptr, adj.out()));
  MatPartitioning mp = nullptr;
  VPC_PETSC(MatPartitioningCreate(PETSC_COMM_SELF, &mp));
  VPC_PETSC(MatPartitioningSetAdjacency(mp, adj));
  VPC_PETSC(MatPartitioningSetNParts(mp, n_parts));
  VPC_PETSC(MatPartitioningSetType(mp, MATPARTITIONINGPTSCOTCH));
  VPC_PETSC(MatPartitioningSetFromOptions(mp));  // -mat_partitioning_type ...
  // Scotch 7 partitions with threads (as Debian builds it), and their races changed the partition
  // from run to run, and with it the last bits of a run's results and its Krylov iteration counts
  // (foundation-pair-3d n = 40: rank 0 owned 36,982 to 37,101 nodes in three runs). One thread makes
  // it the same every run; this graph is partitioned once, on rank 0, while the other ranks wait.
  setenv("SCOTCH_PTHREAD_NUMBER", "1", 1);
  PIs is;
  VPC_PETSC(MatPartitioningApply(mp, is.out()));
  const PetscInt* idx = nullptr;
  VPC_PETSC(ISGetIndices(is, &idx));
  for (int c = 0; c < n_cells; ++c) part[c] = static_cast<int>(idx[c]);
  VPC_PETSC(ISRestoreIndices(is, &idx));
  VPC_PETSC(MatPartitioningDestroy(&mp));
  return part;
}

/// A node's owner: the lowest rank among its cells (0 for a node no cell has).
int lowest_rank(const NodeCells& nc, const std::vector<int>& part, int n_parts, int node) {
  int o = n_parts;
  for (int k = nc.start[node]; k < nc.start[node + 1]; ++k) o = std::min(o, part[nc.list[k]]);
  return o == n_parts ? 0 : o;
}

/// A contact pair's row (problem/contact_pairs.hpp) is ν·u_j − Σ_k w_k ν·u_k on its slave node j
/// and master nodes k. The solvers take each rank's rows of N over that rank's own dofs (so that
/// Nᵀλ and S = N K⁻¹Nᵀ sum over the ranks exactly, with no ghost columns): every node of a row
/// must have the row's owner. Rows sharing a master node chain along the interface, so each
/// connected set of pair nodes goes to one rank, the one that owns most of it already (ties:
/// the lowest). The primal solver writes a slave node's dofs in its masters' (K_rot = Pᵀ K P,
/// solvers/contact_frame.hpp), which a rank can form from its cells only if it holds the masters of
/// every slave node its cells touch: so the cells at a slave node go to its owner too, and no other
/// rank holds a slave node. The cells at a master node go there as well, so that every rank holds a
/// cell at each node it owns, as off the pairs: what a rank knows of a node from its cells (its body,
/// and so its β0 and whether its β can change) would be missing otherwise. Pair nodes sharing a cell
/// join one set, so no cell has two owners. The other nodes of a moved cell are owned as before
/// (the lowest rank among their cells, now). `on_rank_0`: nodes that join one set owned by rank 0
/// (a large-sliding pair's parts, whose rows rank 0 builds again at every step). Not called with
/// --spread-pairs, where a row goes with its slave node's owner, which holds its masters as ghosts
/// (pack_parts), and the pairs' nodes are owned as any other.
void own_pairs_together(const std::vector<ContactRow>& rows, const Mesh& mesh, const NodeCells& nc, int n_parts,
                        const std::vector<int>& on_rank_0, std::vector<int>& part, std::vector<int>& owner) {
  std::vector<int> root(owner.size(), -1);  // union–find over the pair rows' nodes
  auto find = [&](int i) {
    while (root[i] != i) i = root[i] = root[root[i]];
    return i;
  };
  auto join = [&](int a, int b) {
    if (root[a] < 0) root[a] = a;
    if (root[b] < 0) root[b] = b;
    a = find(a), b = find(b);
    if (a != b) root[std::max(a, b)] = std::min(a, b);
  };
  for (const ContactRow& r : rows)
    if (r.pair >= 0) {
      join(r.node, r.node);  // a slave node with no master (off the master side) too
      for (const auto& [k, w] : r.masters) join(r.node, k);
    }
  for (const int v : on_rank_0) join(on_rank_0.front(), v);
  // A node is a pair node (slave or master) where it has a set (root ≥ 0); the joins below only
  // merge such sets.
  const auto n = static_cast<int>(owner.size());
  for (int i = 0; i < n; ++i)
    if (root[i] >= 0)
      for (int k = nc.start[i]; k < nc.start[i + 1]; ++k)
        for (int a = 0; a < mesh.nodes_per_cell(); ++a)
          if (const int v = mesh.cell(nc.list[k])[a]; root[v] >= 0) join(i, v);
  std::unordered_map<int, std::vector<int>> count;  // per set's root: its nodes per rank
  for (std::size_t i = 0; i < owner.size(); ++i)
    if (root[i] >= 0) {
      std::vector<int>& c = count[find(static_cast<int>(i))];
      c.resize(n_parts, 0);
      ++c[owner[i]];
    }
  const int sliding = on_rank_0.empty() ? -1 : find(on_rank_0.front());
  for (std::size_t i = 0; i < owner.size(); ++i)
    if (root[i] >= 0) {
      const int set = find(static_cast<int>(i));
      const std::vector<int>& c = count.at(set);
      owner[i] = set == sliding ? 0 : static_cast<int>(std::max_element(c.begin(), c.end()) - c.begin());
    }
  for (int i = 0; i < n; ++i)
    if (root[i] >= 0)
      for (int k = nc.start[i]; k < nc.start[i + 1]; ++k) part[nc.list[k]] = owner[i];
  for (int i = 0; i < n; ++i)
    if (root[i] < 0) owner[i] = lowest_rank(nc, part, n_parts, i);
}

struct Message {
  std::vector<long long> ints;
  std::vector<double> reals;
};

// A contact node travels as 7 integers and 6 reals, then a pair row's masters: a local node and a weight each.
void pack_contact_node(const PartContactNode& c, Message& m) {
  m.ints.insert(m.ints.end(), {c.row, c.local_node, c.owned ? 1 : 0, static_cast<long long>(c.obstacles), c.law, c.pair,
                               static_cast<long long>(c.masters.size())});
  m.reals.insert(m.reals.end(), {c.direction[0], c.direction[1], c.direction[2], c.gap, c.measure, c.datum});
  for (const auto& [k, w] : c.masters) {
    m.ints.push_back(k);
    m.reals.push_back(w);
  }
}

PartContactNode unpack_contact_node(const long long*& in, const double*& x) {
  PartContactNode c;
  c.row = static_cast<int>(*in++);
  c.local_node = static_cast<int>(*in++);
  c.owned = *in++ != 0;
  c.obstacles = static_cast<ObstacleMask>(*in++);
  c.law = static_cast<int>(*in++);
  c.pair = static_cast<int>(*in++);
  const long long n_masters = *in++;
  c.direction = {x[0], x[1], x[2]};
  c.gap = x[3];
  c.measure = x[4];
  c.datum = x[5];
  x += 6;
  for (long long a = 0; a < n_masters; ++a) c.masters.emplace_back(static_cast<int>(*in++), *x++);
  return c;
}

// A large-sliding pair's piece travels as its pair, then each side's three arrays, each after its size.
void pack_sliding(const std::vector<SlidingPairPiece>& pieces, Message& m) {
  m.ints.push_back(static_cast<long long>(pieces.size()));
  for (const SlidingPairPiece& s : pieces) {
    m.ints.push_back(s.pair);
    for (const SlidingSurface* side : {&s.slave, &s.master})
      for (const std::vector<int>* a : {&side->nodes, &side->facets, &side->cell_nodes}) {
        m.ints.push_back(static_cast<long long>(a->size()));
        m.ints.insert(m.ints.end(), a->begin(), a->end());
      }
  }
}

std::vector<SlidingPairPiece> unpack_sliding(const long long*& in) {
  std::vector<SlidingPairPiece> pieces(static_cast<std::size_t>(*in++));
  for (SlidingPairPiece& s : pieces) {
    s.pair = static_cast<int>(*in++);
    for (SlidingSurface* side : {&s.slave, &s.master})
      for (std::vector<int>* a : {&side->nodes, &side->facets, &side->cell_nodes}) {
        const long long n = *in++;
        a->assign(in, in + n);
        in += n;
      }
  }
  return pieces;
}

constexpr int kHeader = 13;

/// The master nodes of rank r's spread pair rows (the rows of its `owned` slave nodes; a row of Γ3
/// has none) that another rank owns, into r's `ghosts`: ghosts with no cell of r's, which give r's
/// rows their masters' u (u's ghost update) and their columns, whose entries go to the masters'
/// owners as remote pieces (remote_pieces, part/contact_matrix.hpp).
void add_master_ghosts(const WholeMeshData& whole, const std::vector<int>& owned, const std::vector<int>& owner, int r,
                       std::vector<int>& ghosts) {
  for (const int v : owned)
    if (const int k = whole.row_of[static_cast<std::size_t>(v)]; k >= 0)
      for (const auto& [m, w] : whole.rows[static_cast<std::size_t>(k)].masters)
        if (owner[static_cast<std::size_t>(m)] != r) ghosts.push_back(m);
}

/// Rank 0: the part of every rank, cut from the whole problem (cut_part, with its contact `rows`) and packed
/// with its mesh: its nodes, its cells and their loaded facets.
std::vector<Message> pack_parts(const Problem& p, int n_parts, const std::vector<int>& cell_rank, ContactRows rows,
                                bool spread_pairs) {
  const Mesh& mesh = p.mesh;
  const int d = mesh.dim(), npc = mesh.nodes_per_cell(), n_nodes = mesh.n_nodes();
  const NodeCells nc(mesh);
  std::vector<int> part = cell_rank.empty() ? partition_cells(mesh, nc, n_parts) : cell_rank;
  require(part.size() == static_cast<std::size_t>(mesh.n_cells()), "internal: {} cell ranks for {} cells", part.size(),
          mesh.n_cells());

  const WholeMeshData whole(p, std::move(rows));
  // A node belongs to the lowest rank among its cells, except on contact pairs (own_pairs_together).
  std::vector<int> owner(n_nodes, 0);
  for (int i = 0; i < n_nodes; ++i) owner[i] = lowest_rank(nc, part, n_parts, i);
  // Large-sliding pairs (scheme/pair_slider.hpp) couple a slave node to whichever master facets it
  // reaches. Kept together, every node of their slave and master parts is rank 0's, which moves all
  // their rows. Spread (--spread-pairs), each slave node's owner moves its row, from the slave facets
  // near its nodes and the whole master side, which it holds as ghosts where it does not own them
  // (sliding_band, cut_part's MeshPart::sliding).
  if (!spread_pairs) {
    std::vector<int> sliding;
    for (const std::size_t q : p.contact.sliding_pairs(true))
      for (const std::string& side : {p.contact.pairs[q].slave, p.contact.pairs[q].master})
        for (const int v : mesh.nodes_of_parts({side})) sliding.push_back(v);
    own_pairs_together(whole.rows, mesh, nc, n_parts, sliding, part, owner);
  }
  std::vector<std::vector<int>> owned(n_parts);
  for (int i = 0; i < n_nodes; ++i) owned[owner[i]].push_back(i);
  // Global numbers: the nodes of rank 0, then of rank 1, ...; each in its original order.
  const WholeNumbering numbering(owned, whole.dirichlet, d);

  std::vector<std::vector<int>> cells_of(n_parts);
  for (int c = 0; c < mesh.n_cells(); ++c) cells_of[part[c]].push_back(c);
  // Loaded facets, each with the part of its cell: (facet, 0) on Γ2, (facet, k) under pressure load k − 1.
  std::vector<std::vector<std::pair<int, int>>> facets_of(n_parts);
  for (int f : whole.traction_facets) facets_of[part[mesh.facet_cell(f)]].push_back({f, 0});
  for (std::size_t k = 0; k < whole.pressure_facets.size(); ++k)
    for (int f : whole.pressure_facets[k]) facets_of[part[mesh.facet_cell(f)]].push_back({f, static_cast<int>(k) + 1});

  std::vector<Message> out(n_parts);
  std::vector<int> local(n_nodes, -1);
  for (int r = 0; r < n_parts; ++r) {
    std::vector<int> nodes = owned[r], ghosts;
    for (int c : cells_of[r])
      for (int a = 0; a < npc; ++a) {
        const int v = mesh.cell(c)[a];
        if (owner[v] != r) ghosts.push_back(v);
      }
    if (spread_pairs) {  // its rows' masters and its pieces of the sliding surfaces, as ghosts where not owned
      add_master_ghosts(whole, owned[r], owner, r, ghosts);
      for (const int v : sliding_band(mesh, whole, [&](int v) { return owner[static_cast<std::size_t>(v)] == r; }))
        if (owner[static_cast<std::size_t>(v)] != r) ghosts.push_back(v);
    }
    std::sort(ghosts.begin(), ghosts.end(), [&](int a, int b) { return numbering.node[a] < numbering.node[b]; });
    ghosts.erase(std::unique(ghosts.begin(), ghosts.end()), ghosts.end());
    nodes.insert(nodes.end(), ghosts.begin(), ghosts.end());
    for (size_t k = 0; k < nodes.size(); ++k) local[nodes[k]] = static_cast<int>(k);
    const PartPieces piece = cut_part(p, whole, numbering, nodes, static_cast<int>(owned[r].size()), cells_of[r]);

    Message& m = out[r];
    m.ints = {d,
              static_cast<long long>(nodes.size()),
              piece.n_owned_nodes,
              static_cast<long long>(cells_of[r].size()),
              static_cast<long long>(facets_of[r].size()),
              static_cast<long long>(piece.contact.size()),
              piece.n_contact,
              piece.n_global_nodes,
              piece.n_global_dofs,
              piece.n_global_cells,
              static_cast<long long>(piece.dirichlet_components.size()),
              static_cast<long long>(whole.pressure_facets.size()),
              p.contact.spreads_pairs(spread_pairs) ? 1 : 0};
    m.ints.insert(m.ints.end(), piece.dirichlet_components.begin(), piece.dirichlet_components.end());
    m.ints.reserve(m.ints.size() + (4 + d) * nodes.size() + (npc + 3) * cells_of[r].size() +
                   (d + 1) * facets_of[r].size() + 7 * piece.contact.size());
    m.reals.reserve(3 * nodes.size() + 6 * piece.contact.size());
    for (size_t k = 0; k < nodes.size(); ++k) {
      m.ints.insert(m.ints.end(), {piece.global_node[k], piece.original_node[k], piece.first_dof[k],
                                   static_cast<long long>(piece.dirichlet_on_parts[k])});
      m.ints.insert(m.ints.end(), piece.dirichlet.begin() + static_cast<std::ptrdiff_t>(k) * d,
                    piece.dirichlet.begin() + static_cast<std::ptrdiff_t>(k + 1) * d);
      m.reals.insert(m.reals.end(), mesh.node(nodes[k]).begin(), mesh.node(nodes[k]).end());
    }
    for (size_t k = 0; k < cells_of[r].size(); ++k) {
      for (int a = 0; a < npc; ++a) m.ints.push_back(local[mesh.cell(cells_of[r][k])[a]]);
      m.ints.insert(m.ints.end(), {piece.original_cell[k], piece.cell_material[k], piece.cell_body[k]});
    }
    for (auto [f, load] : facets_of[r]) {
      for (int a = 0; a < d; ++a) m.ints.push_back(local[mesh.facet(f)[a]]);
      m.ints.push_back(load);
    }
    for (const PartContactNode& c : piece.contact) pack_contact_node(c, m);
    pack_sliding(piece.sliding, m);
    for (int v : nodes) local[v] = -1;
  }
  return out;
}

/// A rank: its part's pieces and mesh from rank 0's message.
PartPieces unpack_part(MPI_Comm comm, const Message& m) {
  PartPieces dm;
  dm.comm = la::make_mpi_comm(comm);
  auto mesh = std::make_shared<Mesh>();
  const auto* h = m.ints.data();
  const int d = static_cast<int>(h[0]), n_local = static_cast<int>(h[1]);
  dm.n_owned_nodes = static_cast<int>(h[2]);
  const int n_cells = static_cast<int>(h[3]), n_facets = static_cast<int>(h[4]), n_contacts = static_cast<int>(h[5]);
  dm.n_contact = static_cast<int>(h[6]);
  dm.n_global_nodes = h[7];
  dm.n_global_dofs = h[8];
  dm.n_global_cells = h[9];
  const long long* in = h + kHeader;
  dm.dirichlet_components.assign(in, in + h[10]);  // per Dirichlet part
  in += h[10];
  dm.pressure_facets.resize(h[11]);  // every load, even one with no facet in this part
  dm.pairs_spread = h[12] != 0;
  const double* x = m.reals.data();
  *mesh = Mesh(d);
  dm.dirichlet.resize(static_cast<std::size_t>(n_local) * d);
  dm.global_node.resize(n_local);
  dm.original_node.resize(n_local);
  dm.first_dof.resize(n_local);
  dm.dirichlet_on_parts.resize(n_local);
  for (int i = 0; i < n_local; ++i) {
    dm.global_node[i] = *in++;
    dm.original_node[i] = static_cast<int>(*in++);
    dm.first_dof[i] = *in++;
    dm.dirichlet_on_parts[i] = static_cast<std::uint64_t>(*in++);
    for (int c = 0; c < d; ++c) dm.dirichlet[static_cast<std::size_t>(i) * d + c] = static_cast<int>(*in++);
    mesh->add_node({x[0], x[1], x[2]});
    x += 3;
  }
  int nodes[4];
  dm.original_cell.resize(n_cells);
  dm.cell_material.resize(n_cells);
  dm.cell_body.resize(n_cells);
  for (int c = 0; c < n_cells; ++c) {
    for (int a = 0; a <= d; ++a) nodes[a] = static_cast<int>(*in++);
    mesh->add_cell(nodes);
    dm.original_cell[c] = static_cast<int>(*in++);
    dm.cell_material[c] = static_cast<int>(*in++);
    dm.cell_body[c] = static_cast<int>(*in++);
  }
  for (int f = 0; f < n_facets; ++f) {
    for (int a = 0; a < d; ++a) nodes[a] = static_cast<int>(*in++);
    add_loaded_facet(dm, *mesh, nodes, static_cast<int>(*in++));
  }
  dm.mesh_ptr = std::move(mesh);
  for (int k = 0; k < n_contacts; ++k) dm.contact.push_back(unpack_contact_node(in, x));
  dm.sliding = unpack_sliding(in);
  return dm;
}

}  // namespace

MeshPart distribute_mesh(MPI_Comm comm, const Problem& problem, const std::vector<int>& cell_rank, ContactRows rows,
                         bool spread_pairs) {
  const int rank = comm_rank(comm), size = comm_size(comm);
  Message mine;
  // Rank 0 packs every part; a failure there (e.g. a bad gap) is every rank's.
  std::vector<Message> parts;
  la::on_root(la::make_mpi_comm(comm), [&] {
    if (!rows) rows = problem.validate();
    parts = pack_parts(problem, size, cell_rank, std::move(rows), spread_pairs);
  });
  if (rank == 0) {
    for (int r = 1; r < size; ++r) {
      long long sizes[2] = {static_cast<long long>(parts[r].ints.size()), static_cast<long long>(parts[r].reals.size())};
      require(sizes[0] < (1LL << 31) && sizes[1] < (1LL << 31), "mesh part {} is too large for one MPI message", r);
      MPI_Send(sizes, 2, MPI_LONG_LONG, r, 1, comm);
      MPI_Send(parts[r].ints.data(), static_cast<int>(sizes[0]), MPI_LONG_LONG, r, 2, comm);
      MPI_Send(parts[r].reals.data(), static_cast<int>(sizes[1]), MPI_DOUBLE, r, 3, comm);
      parts[r] = Message{};
    }
    mine = std::move(parts[0]);
  } else {
    long long sizes[2];
    MPI_Recv(sizes, 2, MPI_LONG_LONG, 0, 1, comm, MPI_STATUS_IGNORE);
    mine.ints.resize(sizes[0]);
    mine.reals.resize(sizes[1]);
    MPI_Recv(mine.ints.data(), static_cast<int>(sizes[0]), MPI_LONG_LONG, 0, 2, comm, MPI_STATUS_IGNORE);
    MPI_Recv(mine.reals.data(), static_cast<int>(sizes[1]), MPI_DOUBLE, 0, 3, comm, MPI_STATUS_IGNORE);
  }
  return make_mesh_part(unpack_part(comm, mine));
}

}  // namespace vpc
