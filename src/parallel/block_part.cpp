#include "parallel/block_part.hpp"

#include "core/quote.hpp"
#include "io/case_file.hpp"
#include "io/run_output.hpp"
#include "la/petsc.hpp"
#include "mesh/node_cells.hpp"
#include "mesh/refine.hpp"
#include "part/part_cut.hpp"
#include "solvers/contact_capabilities.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <bit>
#include <climits>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace vpc {

namespace {

/// A node's owner: the lowest rank among its cells (as distribute_mesh's). Exact at the nodes of
/// the rank's own cells, whose cells are all in the block; the others are not the rank's.
std::vector<int> node_owners(const Mesh& mesh, const std::vector<int>& cell_rank) {
  std::vector<int> owner(static_cast<std::size_t>(mesh.n_nodes()), INT_MAX);
  for (int c = 0; c < mesh.n_cells(); ++c)
    for (int a = 0; a < mesh.nodes_per_cell(); ++a) {
      int& o = owner[static_cast<std::size_t>(mesh.cell(c)[a])];
      o = std::min(o, cell_rank[static_cast<std::size_t>(c)]);
    }
  return owner;
}

/// The nodes of the rank's cells: those it owns, and the others (its ghost layer), each in the
/// block's order.
struct PartNodes {
  std::vector<int> own, ghosts;
  PartNodes(const Mesh& mesh, const std::vector<int>& cell_rank, const std::vector<int>& owner, int me) {
    std::vector<char> in_part(static_cast<std::size_t>(mesh.n_nodes()), 0);
    for (int c = 0; c < mesh.n_cells(); ++c)
      if (cell_rank[static_cast<std::size_t>(c)] == me)
        for (int a = 0; a < mesh.nodes_per_cell(); ++a) in_part[static_cast<std::size_t>(mesh.cell(c)[a])] = 1;
    for (int v = 0; v < mesh.n_nodes(); ++v)
      if (in_part[static_cast<std::size_t>(v)]) (owner[static_cast<std::size_t>(v)] == me ? own : ghosts).push_back(v);
  }
};

/// The values of every rank, in rank order (each rank's `mine` sent to all). Collective.
std::vector<long long> gather_all(const la::Comm& comm, const std::vector<long long>& mine) {
  const std::vector<std::vector<long long>> from = comm.exchange(std::vector<std::vector<long long>>(comm.size(), mine));
  std::vector<long long> all;
  for (const auto& v : from) all.insert(all.end(), v.begin(), v.end());
  return all;
}

/// FNV-1a over the nodes' coordinates (their bits) and the cells' nodes.
std::uint64_t mesh_fingerprint(const Mesh& mesh) {
  std::uint64_t h = 14695981039346656037ULL;
  auto mix = [&](std::uint64_t v) {
    for (int k = 0; k < 8; ++k, v >>= 8) h = (h ^ (v & 0xff)) * 1099511628211ULL;
  };
  for (const Point& x : mesh.nodes())
    for (const double c : x) mix(std::bit_cast<std::uint64_t>(c));
  for (const int v : mesh.cell_array()) mix(static_cast<std::uint64_t>(static_cast<std::uint32_t>(v)));
  return h;
}

}  // namespace

ContactRows validate_blocks(const la::Comm& comm, const Problem& p) {
  const MeshBlock& b = *p.block;
  const Mesh& mesh = p.mesh;
  const int me = comm.rank(), d = mesh.dim();

  // A refined file's mesh, rank 0's sent to the others (MeshRequest::coarse) or read by each: the
  // same mesh everywhere, or the blocks are not of one mesh.
  if (b.coarse) {
    const std::uint64_t h = mesh_fingerprint(*b.coarse);
    const double high = static_cast<double>(h >> 32), low = static_cast<double>(h & 0xffffffffULL);
    const bool same = comm.max(high) == comm.min(high) && comm.max(low) == comm.min(low);
    la::collective(comm, [&] {
      require(same, "{}: the mesh file gave a different mesh on some ranks (each read it, or meshed a script, itself); "
              "mesh it once into a .msh file (gmsh -{} FILE.geo) and read that", b.source, d);
    });
  }

  // The loader's checks first, as on one process (it makes them as it reads the case).
  // The parts' facets over the whole mesh, each counted by the rank of its cell (the part names
  // are the same on every rank: the generator's sides, then the case's [[mesh.part]]s).
  const std::vector<std::string>& names = mesh.part_names();
  std::vector<long long> facets(names.size(), 0);
  for (int f = 0; f < mesh.n_facets(); ++f)
    if (mesh.facet_part(f) >= 0 && b.cell_rank[static_cast<std::size_t>(mesh.facet_cell(f))] == me)
      ++facets[static_cast<std::size_t>(mesh.facet_part(f))];
  comm.sum(facets.data(), static_cast<int>(facets.size()));
  auto facets_of = [&](const std::string& name) {
    const int k = mesh.find_part(name);
    return k < 0 ? 0LL : facets[static_cast<std::size_t>(k)];
  };
  std::string parts;  // as describe_parts on the whole mesh
  for (std::size_t k = 0; k < names.size(); ++k)
    parts += fmt::format("{}{} ({} facet{})", parts.empty() ? "" : ", ", names[k], facets[k], facets[k] == 1 ? "" : "s");
  parts = parts.empty() ? "no parts" : printable(parts, 300);
  // The cells of each material region the loader left to check, each counted by its rank.
  std::vector<long long> region_cells;
  for (const MeshBlock::Check& check : b.checks) {
    const int r = check.of == MeshBlock::Check::Of::region ? mesh.find_region(check.name) : -1;
    long long n = 0;
    for (int c = 0; c < mesh.n_cells() && r >= 0; ++c)
      n += mesh.cell_region(c) == r && b.cell_rank[static_cast<std::size_t>(c)] == me;
    region_cells.push_back(n);
  }
  comm.sum(region_cells.data(), static_cast<int>(region_cells.size()));
  // A probe lies in some rank's block (where none does, each rank's message is the same).
  std::vector<std::string> outside;
  for (const auto& [x, where] : b.probes) {
    std::string why;
    try {
      (void)locate_point(mesh, x);
    } catch (const Error& e) {
      why = e.what();
    }
    outside.push_back(comm.all(!why.empty()) ? fmt::format("{}: {}", where, why) : std::string());
  }
  // Every rank has the same sums: each finds the same error (thrown as one, la::collective).
  la::collective(comm, [&] {
    for (std::size_t k = 0; k < b.checks.size(); ++k) {
      const MeshBlock::Check& check = b.checks[k];
      const bool found = check.of == MeshBlock::Check::Of::part ? facets_of(check.name) > 0 : region_cells[k] > 0;
      require(found, "{}{}", check.message, check.list_parts ? parts : std::string());
    }
    for (const std::string& why : outside) require(why.empty(), "{}", why);
  });

  ContactRows rows;
  la::collective(comm, [&] { rows = validate_case(p, b.source); });  // each block's own checks (Problem::validate)

  // A symmetry part lies in one plane x_i = const: each block has checked its share; the axes agree.
  std::vector<bool> one_axis;
  for (const std::string& part : p.symmetry) {
    const int axis = mesh.part_size(part) > 0 ? symmetry_axis(mesh, part, &b) : -1;
    one_axis.push_back(comm.max(axis) == comm.min(axis >= 0 ? axis : 3));
  }
  const DirichletDofs dirichlet = dirichlet_dofs(p);
  const std::vector<int> owner = node_owners(mesh, b.cell_rank);
  const std::vector<int> own = PartNodes(mesh, b.cell_rank, owner, me).own;
  long long own_rows = 0;
  for (const ContactRow& r : *rows) own_rows += owner[static_cast<std::size_t>(r.node)] == me;
  own_rows = comm.sum(own_rows);
  la::collective(comm, [&] {
    for (std::size_t k = 0; k < p.symmetry.size(); ++k)
      require(one_axis[k], "{}: symmetry part '{}' does not lie in a plane x = const, y = const{}: a symmetry plane "
              "(roller) prescribes the displacement component normal to an axis-aligned plane",
              p.where("boundary.symmetry"), p.symmetry[k], d == 3 ? " or z = const" : "");
    // Γ3 has a free node somewhere; else each rank with contact nodes names the keys that hold its own.
    if (own_rows == 0 && !p.contact.parts.empty() && !mesh.nodes_of_parts(p.contact.parts).empty())
      fail_no_free_contact_node(p, dirichlet.condition);
  });
  // The body is held: its prescribed dofs summed over the ranks' own nodes (every rank reaches the
  // sum, and then throws alike).
  la::collective(comm, [&] {
    check_block_held(p, dirichlet.condition, own, *rows, [&](double* v, int n) { comm.sum(v, n); });
  });
  return rows;
}

ProblemSize block_problem_size(const la::Comm& comm, const Problem& p, const ContactRows& built) {
  const MeshBlock& b = *p.block;
  const Mesh& mesh = p.mesh;
  const int me = comm.rank(), d = mesh.dim();
  const DirichletDofs dirichlet = dirichlet_dofs(p);
  const std::vector<int> owner = node_owners(mesh, b.cell_rank);
  auto mine = [&](int v) { return owner[static_cast<std::size_t>(v)] == me; };  // exact: see node_owners
  // Over the rank's own nodes: free dofs, contact rows, rows only the dual solves, node graph entries (its rows).
  double own[4] = {0, 0, 0, 0};
  for (int v = 0; v < mesh.n_nodes(); ++v)
    if (mine(v)) own[0] += free_components(dirichlet, v, d);
  const auto laws = p.contact.laws();
  for (const ContactRow& r : *contact_rows_of(p, dirichlet.condition, built))
    if (mine(r.node)) {
      own[1] += 1;
      own[2] += dual_only(*laws[static_cast<std::size_t>(r.law)]);
    }
  // The node graph's entries in the rank's rows: each own node's distinct neighbours (itself too),
  // found through its cells (CSR, 4 bytes a cell's node) and marked, not as sorted pairs of every
  // cell's nodes (16 a cell in 3D at 8 bytes: 0.8 GB a rank at foundation-3d n = 126).
  const int npc = d + 1, n = mesh.n_nodes();
  const NodeCells around(mesh);
  std::vector<int> seen(static_cast<std::size_t>(n), -1);
  for (int v = 0; v < n; ++v) {
    if (!mine(v)) continue;
    for (int k = around.start[static_cast<std::size_t>(v)]; k < around.start[static_cast<std::size_t>(v) + 1]; ++k)
      for (int a = 0; a < npc; ++a)
        if (int& w = seen[static_cast<std::size_t>(mesh.cell(around.list[static_cast<std::size_t>(k)])[a])]; w != v) {
          w = v;
          own[3] += 1;
        }
  }
  comm.sum(own, 4);
  ProblemSize s;
  s.nodes = static_cast<double>(b.whole_nodes);
  s.cells = static_cast<double>(b.whole_cells);
  s.unknowns = own[0];
  s.contact_nodes = own[1];
  s.contact_unknowns = own[1] * p.contact.block_size(d);
  s.dual_only = own[2] > 0;
  s.node_nonzeros = own[3];
  const double free_share = s.nodes > 0 ? s.unknowns / (d * s.nodes) : 0;  // as problem_size
  s.K_nonzeros = d * d * s.node_nonzeros * free_share;
  if (me == 0) {
    constexpr double kCoarseNodes = 30000;
    if (b.coarse) {  // the file's mesh refined as far as it stays within that (itself where larger)
      int levels = 0;
      while (levels < b.levels && MeshRefinement(*b.coarse, levels + 1).whole_nodes() <= kCoarseNodes) ++levels;
      scale_factors(s, refine_mesh(*b.coarse, levels), d);
      return s;
    }
    const double f = std::max(1.0, std::ceil(std::pow(s.nodes / kCoarseNodes, 1.0 / d)));
    std::array<int, 3> n = b.cells;
    for (int a = 0; a < d; ++a) n[static_cast<std::size_t>(a)] = std::max(1, static_cast<int>(std::lround(n[static_cast<std::size_t>(a)] / f)));
    scale_factors(s, generate(d, b.lo, b.hi, n, b.diagonal), d);
  }
  return s;
}

PartPieces block_part_pieces(MPI_Comm mpi_comm, const Problem& p, ContactRows rows) {
  const la::Comm comm = la::make_mpi_comm(mpi_comm);
  const MeshBlock& b = *p.block;
  const Mesh& mesh = p.mesh;
  const int me = comm.rank(), ranks = comm.size(), d = mesh.dim(), n = mesh.n_nodes();
  require(b.ranks == ranks && b.rank == me, "internal: rank {} of {} holds block {} of {}", me, ranks, b.rank, b.ranks);
  const WholeMeshData whole(p, std::move(rows));  // on the block: its own nodes' values are the whole mesh's
  const std::vector<int> owner = node_owners(mesh, b.cell_rank);
  std::vector<int> cells;
  for (int c = 0; c < mesh.n_cells(); ++c)
    if (b.cell_rank[static_cast<std::size_t>(c)] == me) cells.push_back(c);
  PartNodes part_nodes(mesh, b.cell_rank, owner, me);
  const std::vector<int>& own = part_nodes.own;
  std::vector<int>& ghosts = part_nodes.ghosts;

  // Own nodes and free dofs numbered after the lower ranks', each in the whole mesh's order
  // (the block's is the same): WholeNumbering from the lower ranks' counts.
  long long own_dofs = 0;
  for (const int v : own) own_dofs += free_components(whole.dirichlet, v, d);
  const std::vector<long long> node_counts = comm.all_gather(static_cast<long long>(own.size()));
  const std::vector<long long> dof_counts = comm.all_gather(own_dofs);
  long long next_node = 0, next_dof = 0, all_dofs = 0;
  for (int r = 0; r < me; ++r) {
    next_node += node_counts[static_cast<std::size_t>(r)];
    next_dof += dof_counts[static_cast<std::size_t>(r)];
  }
  for (const long long k : dof_counts) all_dofs += k;
  WholeNumbering numbering({own}, whole.dirichlet, d, next_node, next_dof);
  numbering.n_dofs = all_dofs;

  // The ghost layer, their numbers asked of their owners.
  std::vector<std::vector<long long>> ask(static_cast<std::size_t>(ranks));
  for (const int v : ghosts)
    ask[static_cast<std::size_t>(owner[static_cast<std::size_t>(v)])].push_back(b.node_id[static_cast<std::size_t>(v)]);
  const std::vector<std::vector<long long>> asked = comm.exchange(ask);
  std::vector<std::vector<long long>> answer(static_cast<std::size_t>(ranks));
  std::string missing;
  for (int r = 0; r < ranks; ++r)
    for (const long long id : asked[static_cast<std::size_t>(r)]) {
      const auto it = std::lower_bound(b.node_id.begin(), b.node_id.end(), id);
      const auto v = static_cast<std::size_t>(it - b.node_id.begin());
      if (it == b.node_id.end() || *it != id || owner[v] != me) {
        missing = fmt::format("internal: rank {} asked rank {} for node {}, which it does not own", r, me, id);
        answer[static_cast<std::size_t>(r)].insert(answer[static_cast<std::size_t>(r)].end(), {-1, -1});
        continue;
      }
      answer[static_cast<std::size_t>(r)].insert(answer[static_cast<std::size_t>(r)].end(),
                                                 {numbering.node[v], numbering.first_dof[v]});
    }
  const std::vector<std::vector<long long>> answered = comm.exchange(answer);
  comm.throw_if_any(!missing.empty(), missing);
  std::vector<std::size_t> next(static_cast<std::size_t>(ranks), 0);
  for (const int v : ghosts) {
    const auto r = static_cast<std::size_t>(owner[static_cast<std::size_t>(v)]);
    numbering.node[static_cast<std::size_t>(v)] = answered[r][next[r]++];
    numbering.first_dof[static_cast<std::size_t>(v)] = answered[r][next[r]++];
  }
  std::sort(ghosts.begin(), ghosts.end(), [&](int x, int y) {
    return numbering.node[static_cast<std::size_t>(x)] < numbering.node[static_cast<std::size_t>(y)];
  });
  std::vector<int> nodes = own;
  nodes.insert(nodes.end(), ghosts.begin(), ghosts.end());

  PartPieces piece = cut_part(p, whole, numbering, nodes, static_cast<int>(own.size()), cells);
  // The block's numbers to the whole mesh's.
  for (std::size_t k = 0; k < nodes.size(); ++k) piece.original_node[k] = b.node_id[static_cast<std::size_t>(nodes[k])];
  for (std::size_t k = 0; k < cells.size(); ++k) piece.original_cell[k] = b.cell_id[static_cast<std::size_t>(cells[k])];
  piece.n_global_nodes = b.whole_nodes;
  piece.n_global_cells = b.whole_cells;
  // Contact rows are numbered in the whole mesh's node order (WholeMeshData::rows): by the
  // whole-mesh numbers of every rank's own contact nodes.
  std::vector<long long> own_rows;
  for (const int v : own)
    if (whole.row_of[static_cast<std::size_t>(v)] >= 0) own_rows.push_back(b.node_id[static_cast<std::size_t>(v)]);
  std::vector<long long> all_rows = gather_all(comm, own_rows);
  std::sort(all_rows.begin(), all_rows.end());
  piece.n_contact = static_cast<int>(all_rows.size());
  for (PartContactNode& c : piece.contact) {
    const long long id = piece.original_node[static_cast<std::size_t>(c.local_node)];
    const auto it = std::lower_bound(all_rows.begin(), all_rows.end(), id);
    if (it == all_rows.end() || *it != id) missing = fmt::format("internal: rank {}: contact node {} has no row on its owner", me, id);
    c.row = static_cast<int>(it - all_rows.begin());
  }
  comm.throw_if_any(!missing.empty(), missing);
  // A symmetry plane's component, known where the part meets the block (dirichlet_dofs).
  for (unsigned& mask : piece.dirichlet_components) mask = static_cast<unsigned>(comm.max(static_cast<double>(mask)));

  // The part's mesh: its nodes, its cells and their loaded facets, in distribute_mesh's order.
  auto part_mesh = std::make_shared<Mesh>(d);
  std::vector<int> local(static_cast<std::size_t>(n), -1);
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    local[static_cast<std::size_t>(nodes[k])] = static_cast<int>(k);
    part_mesh->add_node(mesh.node(nodes[k]));
  }
  int v[4];
  for (const int c : cells) {
    for (int a = 0; a <= d; ++a) v[a] = local[static_cast<std::size_t>(mesh.cell(c)[a])];
    part_mesh->add_cell(v);
  }
  piece.pressure_facets.resize(whole.pressure_facets.size());
  auto add_facets = [&](const std::vector<int>& facets, int load) {
    for (const int f : facets) {
      if (b.cell_rank[static_cast<std::size_t>(mesh.facet_cell(f))] != me) continue;
      for (int a = 0; a < d; ++a) v[a] = local[static_cast<std::size_t>(mesh.facet(f)[a])];
      add_loaded_facet(piece, *part_mesh, v, load);
    }
  };
  add_facets(whole.traction_facets, 0);
  for (std::size_t k = 0; k < whole.pressure_facets.size(); ++k) add_facets(whole.pressure_facets[k], static_cast<int>(k) + 1);
  piece.mesh_ptr = std::move(part_mesh);
  piece.comm = comm;
  return piece;
}

}  // namespace vpc
