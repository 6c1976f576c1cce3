#include "io/vtu_writer.hpp"

#include "io/atomic_file.hpp"

#include <fmt/format.h>

#include "core/error.hpp"

#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <ostream>

namespace vpc {

VtuCompression vtu_compression(const std::string& name) {
  if (name == "zlib") return VtuCompression::zlib;
  if (name == "none") return VtuCompression::none;
  fail("unknown VTU compression '{}'; expected \"zlib\" or \"none\"", name);
}

const char* vtk_type(const VtuField& f) { return f.integer ? "Int32" : "Float64"; }

const char* vtu_compression_name(VtuCompression c) { return c == VtuCompression::zlib ? "zlib" : "none"; }

std::vector<char> encode_vtu_block(const void* data, std::size_t bytes, const VtuEncoding& e) {
  const auto* in = static_cast<const unsigned char*>(data);
  // The block is sized once and filled with memcpy: appending with vector::insert
  // made GCC 12 print a page of -Wstringop-overflow false positives on every build.
  auto copy = [](char*& to, const void* from, std::size_t n) {
    if (n > 0) std::memcpy(to, from, n);
    to += n;
  };
  if (e.compression == VtuCompression::none) {
    const std::uint64_t n = bytes;
    std::vector<char> out(sizeof n + bytes);
    char* w = out.data();
    copy(w, &n, sizeof n);
    copy(w, in, bytes);
    return out;
  }
  require(e.block_size > 0 && e.level >= 0 && e.level <= 9, "VTU: bad zlib block size {} or level {}", e.block_size,
          e.level);
  const std::size_t B = e.block_size, nb = (bytes + B - 1) / B;
  // The blocks are independent zlib streams: compressed side by side.
  std::vector<std::vector<unsigned char>> z(nb);
  int failures = 0;
#pragma omp parallel for schedule(dynamic) reduction(+ : failures) if (nb > 1)
  for (std::size_t i = 0; i < nb; ++i) {
    const std::size_t n = std::min(B, bytes - i * B);
    uLongf len = compressBound(static_cast<uLong>(n));
    z[i].resize(len);
    if (compress2(z[i].data(), &len, in + i * B, static_cast<uLong>(n), e.level) != Z_OK) ++failures;
    z[i].resize(len);
  }
  require(failures == 0, "VTU: zlib failed to compress an array of {} bytes", bytes);
  std::vector<std::uint64_t> header = {nb, B, nb == 0 ? 0 : bytes - (nb - 1) * B};
  std::size_t total = 0;
  for (const auto& b : z) {
    header.push_back(b.size());
    total += b.size();
  }
  std::vector<char> out(header.size() * sizeof(std::uint64_t) + total);
  char* w = out.data();
  copy(w, header.data(), header.size() * sizeof(std::uint64_t));
  for (const auto& b : z) copy(w, b.data(), b.size());
  return out;
}

namespace {

/// The appended data of a VTU file: one encoded block per array, in the order
/// of the DataArray elements, and the offset of each.
class Appended {
 public:
  explicit Appended(const VtuEncoding& encoding) : encoding_(encoding) {}
  template <typename T>
  std::size_t add(const std::vector<T>& v) {
    const std::size_t offset = size_;
    blocks_.push_back(encode_vtu_block(v.data(), v.size() * sizeof(T), encoding_));
    size_ += blocks_.back().size();
    return offset;
  }
  void write(std::ostream& out) const {
    for (const auto& b : blocks_) out.write(b.data(), static_cast<std::streamsize>(b.size()));
  }

 private:
  VtuEncoding encoding_;
  std::vector<std::vector<char>> blocks_;
  std::size_t size_ = 0;
};

void field_xml(std::string& xml, Appended& app, const VtuField& f) {
  const std::size_t off =
      f.integer ? app.add(std::vector<std::int32_t>(f.values.begin(), f.values.end())) : app.add(f.values);
  xml += fmt::format(
      "        <DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\" format=\"appended\" "
      "offset=\"{}\"/>\n",
      vtk_type(f), f.name, f.n_components, off);
}

/// The mesh part of a VTU file, cached: the mesh does not change during a run.
struct MeshArrays {
  const Mesh* mesh = nullptr;
  int n_nodes = -1, n_cells = -1;
  std::vector<double> xyz;
  std::vector<std::int64_t> connectivity, offsets;
  std::vector<std::uint8_t> types;
};

const MeshArrays& mesh_arrays(const Mesh& mesh) {
  thread_local MeshArrays a;
  if (a.mesh == &mesh && a.n_nodes == mesh.n_nodes() && a.n_cells == mesh.n_cells() &&
      a.xyz.size() == static_cast<std::size_t>(mesh.n_nodes()) * 3 &&
      std::equal(mesh.nodes().begin(), mesh.nodes().end(), reinterpret_cast<const Point*>(a.xyz.data())))
    return a;
  static const std::uint8_t vtk_type[4] = {1, 3, 5, 10};  // vertex, line, triangle, tetra
  const int npc = mesh.nodes_per_cell();
  a.mesh = &mesh;
  a.n_nodes = mesh.n_nodes();
  a.n_cells = mesh.n_cells();
  a.xyz.clear();
  a.xyz.reserve(static_cast<std::size_t>(mesh.n_nodes()) * 3);
  for (const auto& p : mesh.nodes()) a.xyz.insert(a.xyz.end(), p.begin(), p.end());
  a.connectivity.assign(mesh.cell_array().begin(), mesh.cell_array().end());
  a.offsets.resize(mesh.n_cells());
  for (int c = 0; c < mesh.n_cells(); ++c) a.offsets[c] = static_cast<std::int64_t>(c + 1) * npc;
  a.types.assign(mesh.n_cells(), vtk_type[mesh.dim()]);
  return a;
}

}  // namespace

void write_vtu(const std::filesystem::path& path, const Mesh& mesh, const std::vector<VtuField>& point_data,
               const std::vector<VtuField>& cell_data, const VtuEncoding& encoding) {
  const MeshArrays& m = mesh_arrays(mesh);
  Appended app(encoding);
  std::string xml = "<?xml version=\"1.0\"?>\n";
  xml += fmt::format("<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\"{}>\n",
                     encoding.compression == VtuCompression::zlib ? " compressor=\"vtkZLibDataCompressor\"" : "");
  xml += "  <UnstructuredGrid>\n";
  xml += fmt::format("    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", mesh.n_nodes(), mesh.n_cells());
  xml += "      <PointData>\n";
  for (const auto& f : point_data) field_xml(xml, app, f);
  xml += "      </PointData>\n      <CellData>\n";
  for (const auto& f : cell_data) field_xml(xml, app, f);
  xml += "      </CellData>\n      <Points>\n";
  xml += fmt::format(
      "        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"appended\" offset=\"{}\"/>\n",
      app.add(m.xyz));
  xml += "      </Points>\n      <Cells>\n";
  xml += fmt::format("        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"appended\" offset=\"{}\"/>\n",
                     app.add(m.connectivity));
  xml += fmt::format("        <DataArray type=\"Int64\" Name=\"offsets\" format=\"appended\" offset=\"{}\"/>\n",
                     app.add(m.offsets));
  xml += fmt::format("        <DataArray type=\"UInt8\" Name=\"types\" format=\"appended\" offset=\"{}\"/>\n",
                     app.add(m.types));
  xml += "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n";
  xml += "  <AppendedData encoding=\"raw\">\n   _";
  write_file_atomic(path, [&](std::ostream& out) {
    out.write(xml.data(), static_cast<std::streamsize>(xml.size()));
    app.write(out);
    static const char tail[] = "\n  </AppendedData>\n</VTKFile>\n";
    out.write(tail, sizeof tail - 1);
  });
}

void write_pvd(const std::filesystem::path& path, const std::vector<std::pair<double, std::string>>& entries) {
  std::string xml = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n";
  for (const auto& [t, file] : entries)
    xml += fmt::format("    <DataSet timestep=\"{:.17g}\" group=\"\" part=\"0\" file=\"{}\"/>\n", t, file);
  xml += "  </Collection>\n</VTKFile>\n";
  write_file_atomic(path, xml);
}

VtuField tensor_field(const std::string& name, const std::vector<SymTensor>& t) {
  VtuField f{name, 6, {}};
  f.values.reserve(t.size() * 6);
  for (const auto& s : t) {
    // VTK's symmetric-tensor order: XX, YY, ZZ, XY, YZ, XZ.
    const double v[6] = {s[0], s[1], s[2], s[5], s[3], s[4]};
    f.values.insert(f.values.end(), v, v + 6);
  }
  return f;
}

}  // namespace vpc
