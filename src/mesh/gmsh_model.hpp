#pragma once
// What vpcontact takes from Gmsh's model of a file, and its byte form. The Gmsh
// module (gmsh_module.cpp, the only code linked with Gmsh's library) fills it in
// a child process and sends it as bytes; gmsh_reader.cpp checks it and builds the Mesh.
#include <unistd.h>

#include <cerrno>
#include <cstddef>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace vpc::gmsh_model {

/// Elements of one Gmsh type.
struct ElementBlock {
  int type = 0;
  std::string type_name;           // Gmsh's name of the type, e.g. "Triangle 6", for messages
  std::vector<std::size_t> tags;   // element tags
  std::vector<std::size_t> nodes;  // node tags, element after element
};

/// A physical group of dimension d − 1 (a boundary part) or d (a region of cells)
/// with the elements of its entities.
struct PhysicalGroup {
  int tag = 0;
  std::string name;
  std::vector<ElementBlock> blocks;
};

struct GmshModel {
  int dim = 0;
  std::vector<ElementBlock> cells;     // the elements of dimension d, one block per type
  std::vector<std::size_t> node_tags;  // every node of the model
  std::vector<double> coord;           // x, y, z of each
  std::vector<PhysicalGroup> groups;   // dimension d − 1
  std::vector<PhysicalGroup> regions;  // dimension d
};

/// The model as bytes, from the child to this process.
class Writer {
 public:
  template <typename T>
  void value(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    out_.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  template <typename T>
  void array(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    value(v.size());
    if (!v.empty()) out_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  void string(const std::string& s) {
    value(s.size());
    out_ += s;
  }
  void block(const ElementBlock& b) {
    value(b.type);
    string(b.type_name);
    array(b.tags);
    array(b.nodes);
  }
  void model(const GmshModel& m) {
    value(m.dim);
    value(m.cells.size());
    for (const auto& b : m.cells) block(b);
    array(m.node_tags);
    array(m.coord);
    groups(m.groups);
    groups(m.regions);
  }
  void groups(const std::vector<PhysicalGroup>& list) {
    value(list.size());
    for (const auto& g : list) {
      value(g.tag);
      string(g.name);
      value(g.blocks.size());
      for (const auto& b : g.blocks) block(b);
    }
  }
  const std::string& bytes() const { return out_; }
  /// Writes the bytes to `fd` (the pipe to the parent); a short write is reported
  /// by the parent, which finds the model truncated.
  void send(int fd) const {
    std::size_t done = 0;
    while (done < out_.size()) {
      const ssize_t n = ::write(fd, out_.data() + done, out_.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) return;
      done += static_cast<std::size_t>(n);
    }
  }

 private:
  std::string out_;
};

class Reader {
 public:
  struct Truncated {};
  explicit Reader(std::string_view in) : in_(in) {}

  template <typename T>
  T value() {
    static_assert(std::is_trivially_copyable_v<T>);
    T v;
    take(&v, sizeof v);
    return v;
  }
  template <typename T>
  std::vector<T> array() {
    const auto n = value<std::size_t>();
    if (n > in_.size() / sizeof(T)) throw Truncated{};
    std::vector<T> v(n);
    take(v.data(), n * sizeof(T));
    return v;
  }
  std::string string() {
    const auto n = value<std::size_t>();
    if (n > in_.size()) throw Truncated{};
    std::string s(in_.substr(0, n));
    in_.remove_prefix(n);
    return s;
  }
  ElementBlock block() {
    ElementBlock b;
    b.type = value<int>();
    b.type_name = string();
    b.tags = array<std::size_t>();
    b.nodes = array<std::size_t>();
    return b;
  }
  GmshModel model() {
    GmshModel m;
    m.dim = value<int>();
    for (auto n = count(); n > 0; --n) m.cells.push_back(block());
    m.node_tags = array<std::size_t>();
    m.coord = array<double>();
    m.groups = groups();
    m.regions = groups();
    return m;
  }
  std::vector<PhysicalGroup> groups() {
    std::vector<PhysicalGroup> list;
    for (auto n = count(); n > 0; --n) {
      PhysicalGroup g;
      g.tag = value<int>();
      g.name = string();
      for (auto k = count(); k > 0; --k) g.blocks.push_back(block());
      list.push_back(std::move(g));
    }
    return list;
  }

 private:
  std::size_t count() {
    const auto n = value<std::size_t>();
    if (n > in_.size()) throw Truncated{};  // every item takes at least a byte
    return n;
  }
  void take(void* p, std::size_t n) {
    if (n > in_.size()) throw Truncated{};
    if (n > 0) std::memcpy(p, in_.data(), n);
    in_.remove_prefix(n);
  }
  std::string_view in_;
};


/// The module's entry point, looked up with dlsym in the child process: reads
/// (or meshes) `file` and writes 'M' + the model, or 'E' + an error message, to `fd`.
/// `dim` and `size_factor` are those of GmshOptions; `budget` is the memory
/// limit that was set (for the message when Gmsh runs out of it).
using WriteModelFunction = void(const char* file, int dim, double size_factor, std::size_t budget, int fd);
inline constexpr const char* kWriteModelSymbol = "vpcontact_gmsh_write_model";

}  // namespace vpc::gmsh_model
