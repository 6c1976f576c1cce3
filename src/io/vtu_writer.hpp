#pragma once
// VTK XML unstructured grid (.vtu) with appended binary data (no per-value
// formatting), zlib-compressed by default, and the ParaView collection (.pvd)
// that indexes them over time.
//
// The appended data (the layout VTK itself writes; scripts/vpcontact_plot.py
// reads it): VTKFile header_type="UInt64", AppendedData encoding="raw", and per
// DataArray, at its offset after the '_' marker,
//   none: a UInt64 byte count, then the bytes;
//   zlib (VTKFile compressor="vtkZLibDataCompressor"): a UInt64 header
//         [n_blocks, block size, size of the last block, compressed size of
//         block 1 .. n_blocks], then the zlib streams of the blocks; every block
//         but the last holds `block size` bytes of the array when uncompressed.
#include "mesh/mesh.hpp"

#include <cstddef>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace vpc {

struct VtuField {
  std::string name;
  int n_components = 1;       // 1 scalar, 3 vector, 6 symmetric tensor (XX YY ZZ XY YZ XZ)
  std::vector<double> values;  // n_components per node or per cell
  bool integer = false;        // an index (material, rank): written as Int32, so that readers see whole numbers
};

/// The VTK type a field is written as: "Int32" for an integer field, else "Float64".
const char* vtk_type(const VtuField& f);

enum class VtuCompression { zlib, none };

/// How the appended data is written. The defaults were chosen by measurement
/// (docs/cases.md, [output] compression): level 1 is within 1–2 % of level 9's
/// size at a fraction of its time; 256 KiB blocks are up to 4 % smaller than
/// VTK's 32 KiB and no slower.
struct VtuEncoding {
  VtuCompression compression = VtuCompression::zlib;
  std::size_t block_size = 256 * 1024;  // bytes of uncompressed data per block
  int level = 1;                       // zlib level, 1 (fast) to 9 (small)
};

/// "zlib" / "none", as in the case file's [output] compression; throws vpc::Error otherwise.
VtuCompression vtu_compression(const std::string& name);
const char* vtu_compression_name(VtuCompression c);

/// A cell field of symmetric tensors, in VTK's component order (XX, YY, ZZ, XY, YZ, XZ).
VtuField tensor_field(const std::string& name, const std::vector<SymTensor>& t);

/// The appended-data block of one array (with its header) in the given encoding.
std::vector<char> encode_vtu_block(const void* data, std::size_t bytes, const VtuEncoding& encoding);

/// Writes mesh + point and cell fields atomically.
void write_vtu(const std::filesystem::path& path, const Mesh& mesh, const std::vector<VtuField>& point_data,
               const std::vector<VtuField>& cell_data, const VtuEncoding& encoding = {});

/// The .pvd collection: (time, file name relative to the .pvd) pairs, rewritten atomically.
void write_pvd(const std::filesystem::path& path, const std::vector<std::pair<double, std::string>>& entries);

}  // namespace vpc
