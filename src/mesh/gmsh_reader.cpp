#include "mesh/gmsh_reader.hpp"

#include "core/error.hpp"
#include "fem/cell_geometry.hpp"

#include <gmsh.h>

#include <algorithm>
#include <array>
#include <clocale>
#include <cmath>
#include <fstream>
#include <map>
#include <mutex>
#include <unordered_map>
#include <vector>

namespace vpc {

namespace {

namespace fs = std::filesystem;

/// Gmsh's type of the linear simplex of dimension d (point, line, triangle, tetrahedron).
int simplex_type(int d) {
  static const int types[4] = {15, 1, 2, 4};
  return types[d];
}

const char* simplex_name(int d) {
  static const char* names[4] = {"points", "2-node lines", "3-node triangles", "4-node tetrahedra"};
  return names[d];
}

/// Gmsh's own name of an element type, e.g. "Quadrilateral 4" or "Triangle 6".
std::string element_name(int type) {
  std::string name;
  int dim = 0, order = 0, n_nodes = 0, n_primary = 0;
  std::vector<double> local;
  gmsh::model::mesh::getElementProperties(type, name, dim, order, n_nodes, local, n_primary);
  return name.empty() ? "unknown" : name;
}

/// Restores the process's C locale on exit: gmsh::initialize sets LC_ALL from the
/// environment (keeping LC_NUMERIC = "C") and finalize leaves it so.
class LocaleGuard {
 public:
  LocaleGuard() {
    const char* current = std::setlocale(LC_ALL, nullptr);
    if (current) saved_ = current;
  }
  ~LocaleGuard() {
    if (!saved_.empty()) std::setlocale(LC_ALL, saved_.c_str());
  }
  LocaleGuard(const LocaleGuard&) = delete;
  LocaleGuard& operator=(const LocaleGuard&) = delete;

 private:
  std::string saved_;
};

/// One Gmsh API session, initialized and finalized around each read so that
/// repeated reads start from a clean state. Gmsh prints nothing; its messages go
/// to its logger, and check() turns a logged error into a vpc::Error.
class GmshSession {
 public:
  explicit GmshSession(std::string file) : file_(std::move(file)) {
    // No argc/argv, and no user configuration files: a ~/.gmsh-options must not
    // change the meshes a run gets.
    gmsh::initialize(0, nullptr, /*readConfigFiles=*/false);
    gmsh::option::setNumber("General.Terminal", 0);
    // The API's default (2) makes an error throw a std::string; thrown out of the
    // .geo parser it leaves the parser broken, and every later .geo read in the
    // process fails with a bogus "syntax error" (Gmsh 4.8.4). With 0 errors are
    // only logged, and the parser cleans up after itself.
    gmsh::option::setNumber("General.AbortOnError", 0);
    gmsh::logger::start();
  }
  ~GmshSession() {
    gmsh::logger::stop();
    gmsh::finalize();
  }
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;

  /// Throws vpc::Error with Gmsh's first error message if it has logged any.
  void check(const char* doing) const {
    std::vector<std::string> log;
    gmsh::logger::get(log);  // everything since start(): the first error is the cause
    const std::string prefix = "Error";
    std::vector<std::string> errors;
    for (const auto& line : log)
      if (line.compare(0, prefix.size(), prefix) == 0) errors.push_back(line);
    if (errors.empty()) return;
    std::string first = errors.front();
    const auto colon = first.find(": ");
    if (colon != std::string::npos) first.erase(0, colon + 2);
    fail("{}: Gmsh failed while {}: {}{}", file_, doing, first,
         errors.size() > 1 ? fmt::format(" (and {} more errors)", errors.size() - 1) : "");
  }

 private:
  std::string file_;
};

/// Sorted node indices of a facet (unused entries -1), to match facets with groups.
using FacetKey = std::array<int, 3>;

FacetKey facet_key(const int* nodes, int n) {
  FacetKey k{-1, -1, -1};
  for (int i = 0; i < n; ++i) k[i] = nodes[i];
  // Insertion sort (std::sort on three entries trips g++ 12's -Warray-bounds).
  for (int i = 1; i < n; ++i)
    for (int j = i; j > 0 && k[j - 1] > k[j]; --j) std::swap(k[j - 1], k[j]);
  return k;
}

/// The nodes (used by cells only) and the cells of dimension d.
/// `index` receives the map from Gmsh node tags to mesh node indices.
void read_cells(const std::string& file, int d, Mesh& mesh,
                std::unordered_map<std::size_t, int>& index) {
  std::vector<int> types;
  std::vector<std::vector<std::size_t>> elem_tags, elem_nodes;
  gmsh::model::mesh::getElements(types, elem_tags, elem_nodes, d, -1);
  require(!types.empty(),
          "{}: no elements of dimension {} (a .msh file written with physical groups holds only "
          "the elements of physical groups: give the domain a physical group too, or save with "
          "Mesh.SaveAll = 1)",
          file, d);
  for (int type : types)
    require(type == simplex_type(d),
            "{}: found elements of type '{}' (Gmsh type {}) of dimension {}; only linear simplices "
            "are supported ({}D: {}, Gmsh type {})",
            file, element_name(type), type, d, d, simplex_name(d), simplex_type(d));
  const std::vector<std::size_t>& cell_tags = elem_tags.front();
  const std::vector<std::size_t>& cell_nodes = elem_nodes.front();

  // Nodes used by the cells, in increasing Gmsh tag.
  std::vector<std::size_t> used(cell_nodes);
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());

  std::vector<std::size_t> node_tags;
  std::vector<double> coord, parametric;
  gmsh::model::mesh::getNodes(node_tags, coord, parametric, -1, -1, false, false);
  std::unordered_map<std::size_t, std::size_t> position;  // Gmsh tag -> entry in node_tags
  position.reserve(node_tags.size());
  for (std::size_t i = 0; i < node_tags.size(); ++i) position.emplace(node_tags[i], i);

  std::vector<Point> x(used.size());
  Point lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (std::size_t i = 0; i < used.size(); ++i) {
    auto it = position.find(used[i]);
    require(it != position.end(), "{}: an element refers to Gmsh node {}, which the file does not define",
            file, used[i]);
    for (int a = 0; a < 3; ++a) {
      x[i][a] = coord[3 * it->second + a];
      lo[a] = std::min(lo[a], x[i][a]);
      hi[a] = std::max(hi[a], x[i][a]);
    }
  }
  // In d < 3 the unused coordinates must vanish (up to round-off of the CAD kernel).
  double extent = 0;
  for (int a = 0; a < 3; ++a) extent = std::max(extent, hi[a] - lo[a]);
  static const char* axis[3] = {"x", "y", "z"};
  static const char* where[4] = {"", "on the x axis (y = z = 0)", "in the plane z = 0", ""};
  for (std::size_t i = 0; i < used.size(); ++i)
    for (int a = d; a < 3; ++a) {
      require(std::abs(x[i][a]) <= 1e-10 * extent,
              "{}: Gmsh node {} has {} = {}; a {}D mesh must lie {}", file, used[i], axis[a], x[i][a], d,
              where[d]);
      x[i][a] = 0;
    }

  index.reserve(used.size());
  for (std::size_t i = 0; i < used.size(); ++i) index.emplace(used[i], mesh.add_node(x[i]));

  const int npc = d + 1;
  const std::size_t n_cells = cell_tags.size();
  std::vector<double> measure(n_cells);
  double max_measure = 0;
  for (std::size_t c = 0; c < n_cells; ++c) {
    int v[4];
    Point xc[4];
    for (int a = 0; a < npc; ++a) {
      v[a] = index.at(cell_nodes[c * npc + a]);
      xc[a] = mesh.node(v[a]);
    }
    mesh.add_cell(v);
    measure[c] = cell_geometry(d, xc).volume;
    max_measure = std::max(max_measure, measure[c]);
  }
  // Degenerate cells are reported here, with Gmsh's element tag, rather than later
  // by compute_geometry (same relative threshold, so that it cannot fail afterwards).
  for (std::size_t c = 0; c < n_cells; ++c)
    require(measure[c] > 1e-14 * max_measure, "{}: Gmsh element {} is degenerate (measure {:.3e})", file,
            cell_tags[c], measure[c]);
}

/// Tags the boundary facets (already built, untagged) with the names of the
/// physical groups of dimension d − 1 that hold them.
void read_parts(const std::string& file, int d, Mesh& mesh,
                const std::unordered_map<std::size_t, int>& index) {
  struct Tagged {
    std::string part;
    bool on_boundary = false;
  };
  std::map<FacetKey, Tagged> tagged;
  const int fd = d - 1, npf = d;

  gmsh::vectorpair groups;
  gmsh::model::getPhysicalGroups(groups, fd);
  for (const auto& [dim, tag] : groups) {
    std::string part;
    gmsh::model::getPhysicalName(dim, tag, part);
    // An unnamed physical group (e.g. `Physical Curve(3) = {1};`) is called "group<tag>".
    if (part.empty()) part = fmt::format("group{}", tag);
    mesh.part_id(part);  // parts in the order of the groups, even an empty one

    std::vector<int> entities;
    gmsh::model::getEntitiesForPhysicalGroup(dim, tag, entities);
    for (int entity : entities) {
      std::vector<int> types;
      std::vector<std::vector<std::size_t>> elem_tags, elem_nodes;
      gmsh::model::mesh::getElements(types, elem_tags, elem_nodes, fd, entity);
      for (std::size_t t = 0; t < types.size(); ++t) {
        require(types[t] == simplex_type(fd),
                "{}: physical group '{}' holds elements of type '{}' (Gmsh type {}); the facets of "
                "a {}D mesh must be {} (Gmsh type {})",
                file, part, element_name(types[t]), types[t], d, simplex_name(fd), simplex_type(fd));
        const auto& nodes = elem_nodes[t];
        for (std::size_t e = 0; e < elem_tags[t].size(); ++e) {
          int v[3];
          for (int a = 0; a < npf; ++a) {
            auto it = index.find(nodes[e * npf + a]);
            require(it != index.end(),
                    "{}: physical group '{}' holds Gmsh element {}, which is not on the boundary of the "
                    "mesh (one of its nodes belongs to no cell)",
                    file, part, elem_tags[t][e]);
            v[a] = it->second;
          }
          auto [it, inserted] = tagged.emplace(facet_key(v, npf), Tagged{part});
          require(inserted || it->second.part == part,
                  "{}: Gmsh element {} is in the physical groups '{}' and '{}'; a boundary facet can "
                  "belong to one part only",
                  file, elem_tags[t][e], it->second.part, part);
        }
      }
    }
  }

  for (int f = 0; f < mesh.n_facets(); ++f) {
    auto it = tagged.find(facet_key(mesh.facet(f), npf));
    if (it == tagged.end()) continue;
    mesh.set_facet_part(f, it->second.part);
    it->second.on_boundary = true;
  }
  for (const auto& [key, t] : tagged)
    if (!t.on_boundary) {
      const Point& p = mesh.node(key[0]);
      fail("{}: physical group '{}' holds a facet (at node ({}, {}, {})) that is not on the "
           "boundary of the mesh; only boundary facets can form a part",
           file, t.part, p[0], p[1], p[2]);
    }
}

Mesh read_model(const std::string& file, const GmshOptions& options, const GmshSession& session) {
  gmsh::open(file);
  session.check("reading the file");

  const int d = options.dim > 0 ? options.dim : gmsh::model::getDimension();
  require(d >= 1, "{}: the file holds no curve, surface or volume (model dimension {})", file, d);

  std::vector<int> types;
  gmsh::model::mesh::getElementTypes(types, d);
  if (types.empty()) {  // a geometry (.geo, or a .msh without cells of dimension d): mesh it
    double factor = 1;
    gmsh::option::getNumber("Mesh.MeshSizeFactor", factor);  // alias: CharacteristicLengthFactor
    gmsh::option::setNumber("Mesh.MeshSizeFactor", factor * options.size_factor);
    gmsh::model::mesh::generate(d);
    session.check("generating the mesh");
  }

  Mesh mesh(d);
  std::unordered_map<std::size_t, int> index;
  read_cells(file, d, mesh, index);
  mesh.build_boundary();
  read_parts(file, d, mesh, index);
  session.check("reading the mesh");
  return mesh;
}

/// Gmsh keeps global state: one read at a time in the process.
std::mutex gmsh_mutex;

}  // namespace

Mesh read_gmsh(const fs::path& file, const GmshOptions& options) {
  const std::string name = file.string();
  require(options.dim >= 0 && options.dim <= 3,
          "{}: mesh dimension must be 1, 2, 3 or 0 (the highest present); got {}", name, options.dim);
  require(options.size_factor > 0 && std::isfinite(options.size_factor),
          "{}: mesh size factor must be a positive number; got {}", name, options.size_factor);
  // Gmsh silently opens nothing for a missing file: check first.
  std::error_code ec;
  require(fs::exists(file, ec), "mesh file '{}' does not exist", name);
  require(fs::is_regular_file(file, ec), "mesh file '{}' is not a regular file", name);
  require(std::ifstream(file).good(), "mesh file '{}' cannot be opened for reading", name);

  // A .geo file is a script: `Exit;` in it ends the process, as in the gmsh program.
  std::lock_guard<std::mutex> lock(gmsh_mutex);
  LocaleGuard locale;
  try {
    GmshSession session(name);
    return read_model(name, options, session);
  } catch (const Error&) {
    throw;
  } catch (const std::string& what) {  // Gmsh throws std::string, not std::exception
    fail("{}: Gmsh failed: {}", name, what);
  } catch (const std::exception& e) {
    fail("{}: Gmsh failed: {}", name, e.what());
  }
}

std::string describe_parts(const Mesh& mesh) {
  std::string out;
  for (const auto& part : mesh.part_names()) {
    const int n = mesh.part_size(part);
    out += fmt::format("{}{} ({} facet{})", out.empty() ? "" : ", ", part, n, n == 1 ? "" : "s");
  }
  return out.empty() ? "no parts" : out;
}

}  // namespace vpc
