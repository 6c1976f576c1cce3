// [mesh] and the meshes of [[body]]: generated (interval, rectangle, box) or read from a Gmsh file
// (refined `refine` times), whole or a rank's block (MeshRequest::block), with [[mesh.part]].
#include "io/case_readers.hpp"

#include "io/case.hpp"
#include "core/error.hpp"
#include "core/quote.hpp"
#include "la/memory_estimate.hpp"
#include "mesh/generators.hpp"
#include "mesh/gmsh_reader.hpp"
#include "mesh/mesh_block.hpp"
#include "mesh/mesh_extent.hpp"
#include "mesh/refine.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <set>
#include <tuple>

namespace vpc::case_file {

namespace fs = std::filesystem;

namespace {

/// `memory_limit`: --memory-limit, the default limit of meshing a script.
/// [mesh] file's path and Gmsh's options, every key of them read.
std::pair<fs::path, GmshOptions> mesh_file_options(Section& m, const fs::path& base_dir,
                                                   const std::string& memory_limit_option) {
  const fs::path path = base_dir / m.string("file");
  GmshOptions g;
  g.size_factor = m.positive("size_factor", 1.0);
  g.trust_script = m.boolean("trust_geo", false);
  g.trust_how = "[mesh] trust_geo = true";
  // Meshing a script is bounded in time and memory (a loop without end, a tiny size factor).
  g.time_limit = m.number("time_limit", 600.0);
  if (!(g.time_limit >= 0))
    fail("{}: expected a number of seconds >= 0 (0: no limit), got {}", m.where("time_limit"), g.time_limit);
  g.time_limit_how = "[mesh] time_limit";
  const MemoryLimit limit = m.has("memory_limit")
                                ? MemoryLimit{parse_memory_size(m.string("memory_limit"), m.where("memory_limit")),
                                              "[mesh] memory_limit"}
                                : memory_limit(memory_limit_option);
  // At least 1 GiB: the limit is on address space, of which Gmsh's libraries alone map hundreds of MiB.
  g.memory_limit =
      std::isfinite(limit.bytes) ? static_cast<std::size_t>(std::max(limit.bytes, 1024.0 * 1024 * 1024)) : 0;
  g.memory_limit_how =
      m.has("memory_limit") ? limit.source : limit.source + "; [mesh] memory_limit sets it for meshing";
  return {path, g};
}

Mesh read_mesh_file(Section& m, const fs::path& base_dir, const std::string& memory_limit_option) {
  const auto [path, options] = mesh_file_options(m, base_dir, memory_limit_option);
  return located(m.where("file"), [&] { return read_gmsh(path, options); });
}

/// The cells per direction of a generated mesh: one number for all, or one each;
/// `cells_multiple_of` (with `cells_reason`) states what the case's geometry needs.
std::vector<int> read_cells(Section& m, int d) {
  std::vector<int> n;
  const toml::node* c = m.get("cells");
  if (c && c->is_integer()) {
    n.assign(d, m.integer("cells"));
  } else {
    for (double v : m.numbers("cells", d)) {
      if (v != std::floor(v)) fail("{}: expected whole numbers of cells", m.where("cells"));
      if (v < 1 || v > 100000) fail("{}: expected between 1 and 100000 cells per direction, got {}", m.where("cells"), v);
      n.push_back(static_cast<int>(v));
    }
  }
  const int multiple = m.integer("cells_multiple_of", 1);
  if (multiple < 1) fail("{}: expected an integer >= 1", m.where("cells_multiple_of"));
  const std::string reason = m.string("cells_reason", "");
  for (int a = 0; a < d; ++a) {
    if (n[a] < 1 || n[a] > 100000)
      fail("{}: expected between 1 and 100000 cells per direction, got {}", m.where("cells"), n[a]);
    if (n[a] % multiple != 0)
      fail("{}: the number of cells per edge n must be a multiple of {}{}; got {}", m.where("cells"), multiple,
           reason.empty() ? "" : " (" + reason + ")", n[a]);
  }
  return n;
}

/// The rank's block of the grid (split_grid) and a layer of cells around it (MeshBlock).
std::pair<GridBlock, std::vector<GridBlock>> block_with_layer(const std::array<int, 3>& n, int d,
                                                              const MeshRequest::Block& request) {
  std::vector<GridBlock> parts = split_grid(whole_grid(n, d), d, request.ranks);
  GridBlock b = parts[static_cast<std::size_t>(request.rank)];
  for (int a = 0; a < d; ++a) {
    b.lo[a] = std::max(b.lo[a] - 1, 0);
    b.hi[a] = std::min(b.hi[a] + 1, n[a]);
  }
  return {b, std::move(parts)};
}

/// Each cell's rank: the part of the grid (`parts`) holding its segment, square or cube.
std::vector<int> cell_ranks(const BlockMesh& bm, const std::array<int, 3>& n, int d, const GridBlock& block,
                            const std::vector<GridBlock>& parts) {
  std::vector<int> near;  // the parts that the block meets
  for (std::size_t r = 0; r < parts.size(); ++r) {
    bool meets = true;
    for (int a = 0; a < d; ++a) meets = meets && parts[r].lo[a] < block.hi[a] && block.lo[a] < parts[r].hi[a];
    if (meets) near.push_back(static_cast<int>(r));
  }
  long long boxes = 1;
  for (int a = 0; a < d; ++a) boxes *= n[a];
  const long long per_box = bm.whole_cells / boxes;
  std::vector<int> rank(bm.cell_id.size(), -1);
  for (std::size_t c = 0; c < rank.size(); ++c) {
    long long box = bm.cell_id[c] / per_box;
    int at[3] = {0, 0, 0};
    for (int a = 0; a < d; ++a) {
      at[a] = static_cast<int>(box % n[a]);
      box /= n[a];
    }
    for (const int r : near) {
      bool in = true;
      for (int a = 0; a < d; ++a) in = in && parts[static_cast<std::size_t>(r)].lo[a] <= at[a] && at[a] < parts[static_cast<std::size_t>(r)].hi[a];
      if (in) {
        rank[c] = r;
        break;
      }
    }
    require(rank[c] >= 0, "internal: cell {} of the generated mesh is in no rank's part of the grid", bm.cell_id[c]);
  }
  return rank;
}

/// [mesh] with a generator: the whole mesh, or with `block` a rank's block (MeshBlock) into `*out`.
Mesh generate_mesh(Section& m, const std::optional<MeshRequest::Block>& block = std::nullopt,
                   std::shared_ptr<MeshBlock>* out = nullptr) {
  const std::string gen = m.choice("generator", {"interval", "rectangle", "box"});
  if (m.has("refine"))
    fail("{}: refine applies to a mesh read from a file; a generated mesh is refined by its cells per edge (cells)",
         m.where("refine"));
  const int d = gen == "interval" ? 1 : (gen == "rectangle" ? 2 : 3);
  const auto lo = m.numbers("lower", d), hi = m.numbers("upper", d);
  const std::vector<int> n = read_cells(m, d);
  for (int a = 0; a < d; ++a)
    if (!(hi[a] > lo[a])) fail("{}: expected upper > lower in every direction", m.where("upper"));
  // How squares and cubes are cut (generators.hpp); an interval has nothing to cut.
  if (d == 1 && m.has("diagonal"))
    fail("{}: diagonal applies to the rectangle and box generators only", m.where("diagonal"));
  const Diagonal diagonal = d == 1 ? Diagonal::right : diagonal_from_name(m.choice("diagonal", diagonal_names(), "right"));
  // The generators check the mesh size (check_mesh_size) before allocating; the
  // other checks above make the size the only thing they can refuse.
  const std::array<int, 3> n3{n[0], d > 1 ? n[1] : 0, d > 2 ? n[2] : 0};
  const Point box_lo{lo[0], d > 1 ? lo[1] : 0, d > 2 ? lo[2] : 0}, box_hi{hi[0], d > 1 ? hi[1] : 0, d > 2 ? hi[2] : 0};
  if (!block) return located(m.where("cells"), [&] { return generate(d, box_lo, box_hi, n3, diagonal); });
  return located(m.where("cells"), [&] {
    const auto [b, parts] = block_with_layer(n3, d, *block);
    BlockMesh bm = generate_block(d, box_lo, box_hi, n3, diagonal, b);
    auto info = std::make_shared<MeshBlock>();
    info->rank = block->rank;
    info->ranks = block->ranks;
    info->cell_rank = cell_ranks(bm, n3, d, b, parts);
    info->node_id = std::move(bm.node_id);
    info->cell_id = std::move(bm.cell_id);
    info->whole_nodes = bm.whole_nodes;
    info->whole_cells = bm.whole_cells;
    info->lo = box_lo;
    info->hi = box_hi;
    info->cells = n3;
    info->diagonal = diagonal;
    *out = std::move(info);
    return std::move(bm.mesh);
  });
}

/// [mesh] file with `refine` uniform refinements (mesh/refine.hpp): the whole refined mesh, or with
/// a block request the rank's block into `*out`: the children of its coarse cells (split_cells) and
/// a layer of fine cells around them, which every rank refines from the file's mesh (rank 0's,
/// MeshRequest::coarse, where given; else read here).
Mesh read_refined_mesh(Section& m, const fs::path& base_dir, const std::string& memory_limit_option,
                       const MeshRequest& request, std::shared_ptr<MeshBlock>* out) {
  const std::optional<MeshRequest::Block>& block = request.block;
  const int levels = m.integer("refine", 0);
  if (levels < 0 || levels > 10)
    fail("{}: expected a number of uniform refinements from 0 to 10 (each cuts every cell into 2^d), got {}",
         m.where("refine"), levels);
  std::shared_ptr<const Mesh> coarse = request.coarse;
  if (coarse && block)
    (void)mesh_file_options(m, base_dir, memory_limit_option);  // its keys read and checked, as by rank 0
  else
    coarse = std::make_shared<const Mesh>(read_mesh_file(m, base_dir, memory_limit_option));
  if (levels == 0) return *coarse;
  return located(m.where("refine"), [&] {
    const MeshRefinement refinement(*coarse, levels);
    if (!block) return refinement.refine_all().mesh;
    const std::vector<int> coarse_rank = split_cells(*coarse, block->ranks);
    std::vector<int> own;
    for (int c = 0; c < coarse->n_cells(); ++c)
      if (coarse_rank[static_cast<std::size_t>(c)] == block->rank) own.push_back(c);
    BlockMesh bm = refinement.refine(own, layer_cells(*coarse, coarse_rank, block->rank));
    auto info = std::make_shared<MeshBlock>();
    info->rank = block->rank;
    info->ranks = block->ranks;
    const int shift = coarse->dim() * levels;  // 2^(d·levels) children a coarse cell
    for (const int id : bm.cell_id) info->cell_rank.push_back(coarse_rank[static_cast<std::size_t>(id >> shift)]);
    info->node_id = std::move(bm.node_id);
    info->cell_id = std::move(bm.cell_id);
    info->whole_nodes = bm.whole_nodes;
    info->whole_cells = bm.whole_cells;
    std::tie(info->lo, info->hi) = coarse->bounding_box();  // the refined mesh's: its corners are coarse nodes
    info->coarse = coarse;
    info->levels = levels;
    *out = std::move(info);
    return std::move(bm.mesh);
  });
}

/// [[mesh.part]]: re-tag the boundary facets whose centroid satisfies a predicate.
/// `check`: whether a part must have facets here (not in a block, whose MeshBlock::checks keeps
/// the check for all ranks together).
void read_mesh_parts(Section& m, Mesh& mesh, const Origins& origins, bool check, MeshBlock* block) {
  if (!m.has("part")) return;
  const toml::node* parts = m.get("part");
  if (!parts->is_array_of_tables()) m.expected("part", "an array of tables [[mesh.part]] with name and where");
  int i = 0;
  for (const auto& node : *parts->as_array()) {
    Section p(node.as_table(), fmt::format("mesh.part[{}]", i++), origins);
    const std::string name = p.string("name");
    const auto where = p.expression("where", Expression::Kind::Space);
    p.finish();
    mesh.tag_facets(name, [&](const Point& x) { return (*where)(x) != 0.0; });
    const std::string none = fmt::format("{}: the predicate {} selects no boundary facet", p.where("where"),
                                         quote_formula(where->text()));
    if (check && mesh.part_size(name) == 0) fail("{}", none);
    if (block) block->checks.push_back({MeshBlock::Check::Of::part, name, none});
  }
}

}  // namespace

/// [mesh], built, or an empty mesh of the requested dimension (a rank that does not build it),
/// or with a block request (only for a generator: parse_case) the rank's block into `*block`.
Mesh read_mesh(Section m, const fs::path& base_dir, const Origins& origins, const MeshRequest& request,
               const std::string& memory_limit_option, std::shared_ptr<MeshBlock>* block) {
  if (!m.exists()) fail("{}: missing section [mesh]", origins.file);
  if (!request.build && !request.block) {
    require(request.dim >= 1 && request.dim <= 3, "{}: the mesh dimension must be 1, 2 or 3", origins.file);
    return Mesh(request.dim);  // [mesh] is read by the rank that builds the mesh
  }
  Mesh mesh = m.has("file") ? read_refined_mesh(m, base_dir, memory_limit_option, request, block)
                             : generate_mesh(m, request.block, block);
  // Coordinates such as 1e120 overflow the method's products (issue 26): refused here, at check.
  located(m.has("file") ? fmt::format("{}: {}", m.where("file"), quote(m.string("file"))) : m.where("upper"),
          [&] { check_mesh_extent(mesh); });
  read_mesh_parts(m, mesh, origins, !request.block, block ? block->get() : nullptr);
  m.finish();
  return mesh;
}

// ---------------------------------------------------------------- [[body]]

/// [[body]] (SPEC §8): each further body's name and [body.mesh] (as [mesh]), appended to
/// p.mesh: its parts become "<name>.<part>" and its regions "<name>.<region>" for the rest
/// of the case. Returns the bodies' sections, whose other tables read_body_data reads once
/// the case's own material is known.
std::vector<Section> read_body_meshes(Section& top, Problem& p, const fs::path& base_dir, const Origins& origins,
                                      const MeshRequest& request, const std::string& memory_limit_option) {
  std::vector<Section> bodies;
  if (!top.has("body")) return bodies;
  const toml::node* list = top.get("body");
  if (!list->is_array_of_tables()) top.expected("body", "an array of tables [[body]] with name and [body.mesh]");
  std::set<std::string> names{"body"};
  for (const auto& node : *list->as_array()) {
    Section s(node.as_table(), fmt::format("body[{}]", bodies.size()), origins);
    const std::string name = s.string("name");
    const bool plain = !name.empty() && name.size() <= 100 && std::all_of(name.begin(), name.end(), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_';
    });
    if (!plain || names.count(name))
      fail("{}: expected a new body name of letters, digits, '-' and '_' (at most 100; \"body\" is the case's own "
           "[mesh]){}; its parts are then named \"<name>.<part>\"",
           s.where("name"), names.count(name) ? fmt::format("; {} is taken", quote(name)) : "");
    names.insert(name);
    if (request.build) {
      const std::string prefix = name + ".";
      for (const auto& list_of : {p.mesh.part_names(), p.mesh.region_names()})
        for (const auto& taken : list_of)
          if (taken.starts_with(prefix))
            fail("{}: the mesh already has a part or region {}, which the body's own parts would be confused with; "
                 "name the body otherwise",
                 s.where("name"), quote(taken));
    }
    Section m = s.table("mesh");
    if (!m.exists()) fail("{}: missing section [body.mesh] of body {} (a generator or a file, as [mesh])", s.where_section(), quote(name));
    const Mesh mesh = read_mesh(m, base_dir, origins, {request.build, request.dim, std::nullopt, std::nullopt, nullptr}, memory_limit_option);
    if (request.build) p.mesh.append(mesh, name);
    bodies.push_back(std::move(s));
  }
  return bodies;
}

}  // namespace vpc::case_file
