// The only code linked with Gmsh's library, built as a module that the mesh
// reader loads (dlopen) in its child process. Gmsh 4.8 pulls in about a hundred
// shared libraries (OpenCASCADE, VTK, ...) whose loading costs every start of a
// program linked with it ~0.15 s; loaded here, only runs that read a Gmsh file pay.
#include "core/error.hpp"
#include "core/quote.hpp"
#include "mesh/gmsh_model.hpp"

#include <gmsh.h>

#include <new>

namespace vpc {

namespace {

using namespace gmsh_model;

/// Gmsh's own name of an element type, e.g. "Quadrilateral 4" or "Triangle 6".
std::string element_name(int type) {
  std::string name;
  int dim = 0, order = 0, n_nodes = 0, n_primary = 0;
  std::vector<double> local;
  gmsh::model::mesh::getElementProperties(type, name, dim, order, n_nodes, local, n_primary);
  return name.empty() ? "unknown" : name;
}

/// One Gmsh API session. Gmsh prints nothing; its messages go to its logger,
/// and check() turns a logged error into a vpc::Error.
class GmshSession {
 public:
  explicit GmshSession(std::string file) : file_(std::move(file)) {
    // No argc/argv, and no user configuration files: a ~/.gmsh-options must not
    // change the meshes a run gets.
    gmsh::initialize(0, nullptr, /*readConfigFiles=*/false);
    gmsh::option::setNumber("General.Terminal", 0);
    // With the API's default (2) an error throws a std::string; with 0 errors
    // are only logged, and check() reports the first.
    gmsh::option::setNumber("General.AbortOnError", 0);
    gmsh::logger::start();
  }
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;
  // No destructor: the child process ends without finalizing Gmsh.

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
    fail("{}: Gmsh failed while {}: {}{}", file_, doing, printable(first, 200),
         errors.size() > 1 ? fmt::format(" (and {} more errors)", errors.size() - 1) : "");
  }

 private:
  std::string file_;
};

std::vector<ElementBlock> element_blocks(int dim, int entity) {
  std::vector<int> types;
  std::vector<std::vector<std::size_t>> tags, nodes;
  gmsh::model::mesh::getElements(types, tags, nodes, dim, entity);
  std::vector<ElementBlock> out;
  for (std::size_t t = 0; t < types.size(); ++t)
    out.push_back({types[t], element_name(types[t]), std::move(tags[t]), std::move(nodes[t])});
  return out;
}

/// The physical groups of dimension `dim` with the elements of their entities.
std::vector<PhysicalGroup> physical_groups(int dim) {
  std::vector<PhysicalGroup> out;
  gmsh::vectorpair groups;
  gmsh::model::getPhysicalGroups(groups, dim);
  for (const auto& [group_dim, tag] : groups) {
    PhysicalGroup g;
    g.tag = tag;
    gmsh::model::getPhysicalName(group_dim, tag, g.name);
    std::vector<int> entities;
    gmsh::model::getEntitiesForPhysicalGroup(group_dim, tag, entities);
    for (int entity : entities)
      for (auto& b : element_blocks(group_dim, entity)) g.blocks.push_back(std::move(b));
    out.push_back(std::move(g));
  }
  return out;
}

/// Opens `file` with Gmsh, meshes it if it holds no cells of dimension d, and
/// takes the cells, the nodes and the physical groups of dimensions d − 1 and d.
GmshModel extract_model(const std::string& file, int dim, double size_factor) {
  GmshSession session(file);
  gmsh::open(file);
  session.check("reading the file");

  GmshModel m;
  m.dim = dim > 0 ? dim : gmsh::model::getDimension();
  if (m.dim < 1) return m;  // reported by build_mesh

  std::vector<int> types;
  gmsh::model::mesh::getElementTypes(types, m.dim);
  if (types.empty()) {  // a geometry (.geo, or a .msh without cells of dimension d): mesh it
    double factor = 1;
    gmsh::option::getNumber("Mesh.MeshSizeFactor", factor);  // alias: CharacteristicLengthFactor
    gmsh::option::setNumber("Mesh.MeshSizeFactor", factor * size_factor);
    gmsh::model::mesh::generate(m.dim);
    session.check("generating the mesh");
  }

  m.cells = element_blocks(m.dim, -1);
  std::vector<double> parametric;
  gmsh::model::mesh::getNodes(m.node_tags, m.coord, parametric, -1, -1, false, false);

  m.groups = physical_groups(m.dim - 1);
  m.regions = physical_groups(m.dim);
  session.check("reading the mesh");
  return m;
}

}  // namespace

}  // namespace vpc

/// See gmsh_model::WriteModelFunction. Exceptions never leave the module.
extern "C" __attribute__((visibility("default"))) void vpcontact_gmsh_write_model(const char* file_name, int dim,
                                                                                   double size_factor,
                                                                                   std::size_t budget, int fd) {
  using namespace vpc;
  const std::string file = file_name;
  gmsh_model::Writer w;
  std::string error;
  try {
    w.value('M');
    w.model(extract_model(file, dim, size_factor));
  } catch (const Error& e) {
    error = e.what();
  } catch (const std::string& what) {  // Gmsh throws std::string, not std::exception
    error = fmt::format("{}: Gmsh failed: {}", file, what);
  } catch (const std::bad_alloc&) {  // the reader says why (a malformed .msh, a script's mesh beyond the limit)
    w = gmsh_model::Writer();
    w.value('O');
    w.send(fd);
    (void)budget;
    return;
  } catch (const std::exception& e) {
    error = fmt::format("{}: Gmsh failed: {}", file, e.what());
  } catch (...) {
    error = fmt::format("{}: Gmsh failed with an unknown exception", file);
  }
  if (!error.empty()) {
    w = gmsh_model::Writer();
    w.value('E');
    w.string(error);
  }
  w.send(fd);
}
