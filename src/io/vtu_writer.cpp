#include "io/vtu_writer.hpp"

#include "io/atomic_file.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <cstring>

namespace vpc {

namespace {

/// Collects appended-data blocks: each is a UInt64 byte count then the raw bytes.
class Appended {
 public:
  template <typename T>
  std::size_t add(const std::vector<T>& v) {
    const std::size_t offset = data_.size();
    const std::uint64_t n = v.size() * sizeof(T);
    append(&n, sizeof n);
    append(v.data(), n);
    return offset;
  }
  const std::string& data() const { return data_; }

 private:
  void append(const void* p, std::size_t n) { data_.append(static_cast<const char*>(p), n); }
  std::string data_;
};

void field_xml(std::string& xml, Appended& app, const VtuField& f) {
  const std::size_t off = app.add(f.values);
  xml += fmt::format(
      "        <DataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"appended\" "
      "offset=\"{}\"/>\n",
      f.name, f.n_components, off);
}

}  // namespace

void write_vtu(const std::filesystem::path& path, const Mesh& mesh, const std::vector<VtuField>& point_data,
               const std::vector<VtuField>& cell_data) {
  static const std::uint8_t vtk_type[4] = {1, 3, 5, 10};  // vertex, line, triangle, tetra
  const int npc = mesh.nodes_per_cell();
  Appended app;
  std::vector<double> xyz;
  xyz.reserve(static_cast<std::size_t>(mesh.n_nodes()) * 3);
  for (const auto& p : mesh.nodes()) xyz.insert(xyz.end(), p.begin(), p.end());
  std::vector<std::int64_t> conn(mesh.cell_array().begin(), mesh.cell_array().end()), offsets(mesh.n_cells());
  for (int c = 0; c < mesh.n_cells(); ++c) offsets[c] = static_cast<std::int64_t>(c + 1) * npc;
  std::vector<std::uint8_t> types(mesh.n_cells(), vtk_type[mesh.dim()]);

  std::string xml = "<?xml version=\"1.0\"?>\n";
  xml += "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n";
  xml += "  <UnstructuredGrid>\n";
  xml += fmt::format("    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", mesh.n_nodes(), mesh.n_cells());
  xml += "      <PointData>\n";
  for (const auto& f : point_data) field_xml(xml, app, f);
  xml += "      </PointData>\n      <CellData>\n";
  for (const auto& f : cell_data) field_xml(xml, app, f);
  xml += "      </CellData>\n      <Points>\n";
  xml += fmt::format(
      "        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"appended\" offset=\"{}\"/>\n",
      app.add(xyz));
  xml += "      </Points>\n      <Cells>\n";
  xml += fmt::format("        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"appended\" offset=\"{}\"/>\n",
                     app.add(conn));
  xml += fmt::format("        <DataArray type=\"Int64\" Name=\"offsets\" format=\"appended\" offset=\"{}\"/>\n",
                     app.add(offsets));
  xml += fmt::format("        <DataArray type=\"UInt8\" Name=\"types\" format=\"appended\" offset=\"{}\"/>\n",
                     app.add(types));
  xml += "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n";
  xml += "  <AppendedData encoding=\"raw\">\n   _";
  xml += app.data();
  xml += "\n  </AppendedData>\n</VTKFile>\n";
  write_file_atomic(path, xml);
}

void write_pvd(const std::filesystem::path& path, const std::vector<std::pair<double, std::string>>& entries) {
  std::string xml = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n";
  for (const auto& [t, file] : entries)
    xml += fmt::format("    <DataSet timestep=\"{:.17g}\" group=\"\" part=\"0\" file=\"{}\"/>\n", t, file);
  xml += "  </Collection>\n</VTKFile>\n";
  write_file_atomic(path, xml);
}

}  // namespace vpc
