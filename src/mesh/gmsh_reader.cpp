#include "mesh/gmsh_reader.hpp"

#include "core/error.hpp"
#include "core/quote.hpp"

#include "mesh/facet_key.hpp"
#include "mesh/gmsh_model.hpp"
#include "mesh/gmsh_script.hpp"

#include <dlfcn.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <new>
#include <string_view>
#include <type_traits>
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

using namespace gmsh_model;

/// Waits for the child `pid` to end; its wait status, and the most memory it held.
int reap(pid_t pid, std::size_t* max_rss_bytes = nullptr) {
  int status = 0;
  rusage usage{};
  while (::wait4(pid, &status, 0, &usage) < 0 && errno == EINTR) {
  }
  if (max_rss_bytes) *max_rss_bytes = static_cast<std::size_t>(usage.ru_maxrss) * 1024;  // KiB on Linux
  return status;
}

/// The child's answer on `fd`, read until it closes. The child is killed (and
/// reaped) when the time limit passes.
std::string read_answer(int fd, pid_t pid, const std::string& file, const GmshOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  auto stop_child = [&] {
    ::kill(pid, SIGKILL);
    reap(pid);
    ::close(fd);
  };
  std::string out;
  char buffer[1 << 16];
  for (;;) {
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (options.time_limit > 0 && seconds > options.time_limit) {
      stop_child();
      fail("{}: Gmsh did not finish within {:g} s and was stopped (a loop that does not end, or elements far too "
           "small?); {} sets the limit",
           file, options.time_limit, options.time_limit_how);
    }
    pollfd p{fd, POLLIN, 0};
    const int ready = ::poll(&p, 1, 100);  // or a signal (EINTR): then the clock is looked at again
    if (ready <= 0) continue;
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return out;
    out.append(buffer, static_cast<std::size_t>(n));
  }
}

/// The child's exit status when Gmsh calls exit().
constexpr int kGmshCalledExit = 86;

#if defined(__SANITIZE_ADDRESS__)
#define VPC_ADDRESS_SANITIZER 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define VPC_ADDRESS_SANITIZER 1
#endif
#endif

/// The memory Gmsh may take (beyond what the process already maps) to read a
/// mesh file: some malformed .msh files make Gmsh 4.8 ask for gigabytes (a
/// 58-byte $Nodes header: 15 GB and a minute; fuzz/), while reading a real one
/// needs a small multiple of its size. A geometry is meshed within the limit of
/// the options (which may need much more). 0: no limit (also under
/// AddressSanitizer, which reserves terabytes).
std::size_t memory_budget(const std::string& file, const GmshOptions& options) {
#ifdef VPC_ADDRESS_SANITIZER
  (void)file;
  (void)options;
  return 0;
#else
  if (fs::path(file).extension() != ".msh") return options.memory_limit;
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(file, ec);
  if (ec) return 0;
  return std::max<std::uintmax_t>(std::uintmax_t{4} << 30, 100 * size);
#endif
}

/// In the child: caps its address space at what it maps now plus `budget`.
void limit_memory(std::size_t budget) {
  if (budget == 0) return;
  std::ifstream status("/proc/self/status");
  std::size_t mapped_kb = 0;
  for (std::string line; std::getline(status, line);)
    if (line.rfind("VmSize:", 0) == 0) mapped_kb = std::strtoull(line.c_str() + 7, nullptr, 10);
  if (mapped_kb == 0) return;
  rlimit r{};
  if (::getrlimit(RLIMIT_AS, &r) != 0) return;
  const rlim_t cap = static_cast<rlim_t>(mapped_kb) * 1024 + budget;
  if (r.rlim_max != RLIM_INFINITY && cap > r.rlim_max) return;
  r.rlim_cur = cap;
  ::setrlimit(RLIMIT_AS, &r);
}

/// Runs Gmsh on `file` in a child process and returns its model, or throws its
/// error. Whatever Gmsh does to a bad file stays in the child: Gmsh 4.8's .msh
/// readers crash on some malformed files (fuzz/, docs/reliability.md), `Exit;`
/// in a .geo script ends the process, and Gmsh keeps global state.
GmshModel read_in_child(const std::string& file, const GmshOptions& options) {
  const std::size_t budget = memory_budget(file, options);
  const bool script = fs::path(file).extension() != ".msh";
  int fds[2];
  require(::pipe(fds) == 0, "{}: cannot create a pipe for Gmsh: {}", file, std::strerror(errno));
  std::fflush(nullptr);  // nothing buffered is written twice
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int err = errno;
    ::close(fds[0]);
    ::close(fds[1]);
    fail("{}: cannot start a process for Gmsh: {}", file, std::strerror(err));
  }
  if (pid == 0) {  // the child: never returns
    ::close(fds[0]);
    // The child ends with this process (killed, or timed out by a fuzzer).
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(1);
    // A crash ends the child by its signal, which the parent reports (not the
    // handlers of sanitizers or fuzzers that the parent may have installed).
    for (int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) std::signal(sig, SIG_DFL);
    // Gmsh calls exit() for `Exit;` in a .geo file: the exit handlers and static
    // destructors are the parent's, so the child leaves at once, saying so.
    std::atexit([] { ::_exit(kGmshCalledExit); });
    limit_memory(budget);
    // Ctrl-C reaches the whole process group: the parent stops the child (read_answer).
    std::signal(SIGINT, SIG_IGN);
    std::signal(SIGTERM, SIG_IGN);
    // The CPU time, a second bound behind the parent's clock (SIGXCPU ends the child).
    if (options.time_limit > 0) {
      rlimit r{};
      if (::getrlimit(RLIMIT_CPU, &r) == 0) {
        r.rlim_cur = static_cast<rlim_t>(std::ceil(options.time_limit)) + 5;
        if (r.rlim_max != RLIM_INFINITY && r.rlim_cur > r.rlim_max) r.rlim_cur = r.rlim_max;
        ::setrlimit(RLIMIT_CPU, &r);
      }
    }
    // Gmsh's library is loaded here only (gmsh_module.cpp): the parent never pays for it.
    const char* module = std::getenv("VPCONTACT_GMSH_MODULE");
    if (module == nullptr || *module == '\0') module = VPC_GMSH_MODULE;
    void* handle = ::dlopen(module, RTLD_NOW | RTLD_LOCAL);
    void* entry = handle ? ::dlsym(handle, kWriteModelSymbol) : nullptr;
    if (entry == nullptr) {
      Writer w;
      w.value('E');
      w.string(fmt::format("{}: cannot load vpcontact's Gmsh module '{}': {} (set VPCONTACT_GMSH_MODULE to its path)",
                           file, module, ::dlerror()));
      w.send(fds[1]);
      ::_exit(0);
    }
    reinterpret_cast<WriteModelFunction*>(entry)(file.c_str(), options.dim, options.size_factor, budget, fds[1]);
    ::_exit(0);  // no exit handlers: they belong to the parent
  }
  ::close(fds[1]);
  const std::string bytes = read_answer(fds[0], pid, file, options);
  ::close(fds[0]);
  std::size_t max_rss = 0;
  const int status = reap(pid, &max_rss);
  const std::string how = WIFSIGNALED(status) ? fmt::format("crashed ({})", strsignal(WTERMSIG(status)))
                                              : fmt::format("ended with exit status {}", WEXITSTATUS(status));
  const std::string limit = budget > 0 ? fmt::format("{} MiB", budget >> 20) : "no limit";
  // A crash on a mesh file is most likely a malformed file (fuzz/); a script
  // that Gmsh accepts can crash Gmsh itself (issue 26: Gmsh 4.8 on some recombined meshes).
  auto crash = [&]() -> Error {
    if (WIFSIGNALED(status) && WTERMSIG(status) == SIGXCPU)
      return Error(fmt::format("{}: Gmsh used more than {:g} s of CPU time and was stopped; {} sets the limit", file,
                               options.time_limit, options.time_limit_how));
    if (!script)
      return Error(fmt::format("{}: Gmsh {} while reading the file; the file is probably malformed", file, how));
    return Error(fmt::format(
        "{}: Gmsh {} while meshing the file: a failure of Gmsh itself, which a valid script can meet too (e.g. "
        "recombined or quadrilateral meshes, which vpcontact does not take anyway){}; try other mesh options or "
        "element sizes",
        file, how,
        budget > 0 && max_rss > budget / 2  // C code that finds no memory may crash rather than throw
            ? fmt::format(", or memory beyond the limit of {} ({})", limit, options.memory_limit_how)
            : ""));
  };
  if (bytes.empty()) {
    if (WIFEXITED(status) && WEXITSTATUS(status) == kGmshCalledExit)
      fail("{}: Gmsh ended the program while reading the file (does the .geo file call Exit?)", file);
    throw crash();
  }
  try {
    Reader r(bytes);
    const char kind = r.value<char>();
    if (kind == 'E') throw Error(r.string());
    if (kind == 'O') {
      if (!script) fail("{}: Gmsh ran out of memory while reading the file ({}); the file is probably malformed", file,
                        budget > 0 ? "limit " + limit : limit);
      fail("{}: Gmsh ran out of memory while meshing the file ({}); make the elements larger, or raise the limit "
           "with {}", file, budget > 0 ? "limit " + limit : limit, options.memory_limit_how);
    }
    return r.model();
  } catch (const Reader::Truncated&) {
    throw crash();
  }
}

// ---------------------------------------------------------------------------
// In this process: check the model and build the Mesh.

/// Gmsh gives each element its number of nodes; anything else is a broken model.
void check_block(const std::string& file, const ElementBlock& b, int nodes_per_element) {
  require(b.nodes.size() == b.tags.size() * static_cast<std::size_t>(nodes_per_element),
          "{}: Gmsh returned {} node tags for {} elements of type '{}'", file, b.nodes.size(), b.tags.size(),
          b.type_name);
}

/// The nodes (used by cells only) and the cells of dimension d.
/// `index` receives the map from Gmsh node tags to mesh node indices.
void read_cells(const std::string& file, const GmshModel& model, Mesh& mesh,
                std::unordered_map<std::size_t, int>& index) {
  const int d = model.dim;
  require(!model.cells.empty(),
          "{}: no elements of dimension {} (a .msh file written with physical groups holds only "
          "the elements of physical groups: give the domain a physical group too, or save with "
          "Mesh.SaveAll = 1)",
          file, d);
  for (const auto& b : model.cells)
    require(b.type == simplex_type(d),
            "{}: found elements of type '{}' (Gmsh type {}) of dimension {}; only linear simplices "
            "are supported ({}D: {}, Gmsh type {})",
            file, b.type_name, b.type, d, d, simplex_name(d), simplex_type(d));
  const int npc = d + 1;
  check_block(file, model.cells.front(), npc);
  const std::vector<std::size_t>& cell_tags = model.cells.front().tags;
  const std::vector<std::size_t>& cell_nodes = model.cells.front().nodes;
  const std::vector<std::size_t>& node_tags = model.node_tags;
  const std::vector<double>& coord = model.coord;
  require(coord.size() == 3 * node_tags.size(), "{}: Gmsh returned {} coordinates for {} nodes", file,
          coord.size(), node_tags.size());

  // Nodes used by the cells, in increasing Gmsh tag.
  std::vector<std::size_t> used(cell_nodes);
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());

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
    measure[c] = simplex_measure(d, xc);
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
void read_parts(const std::string& file, const GmshModel& model, Mesh& mesh,
                const std::unordered_map<std::size_t, int>& index) {
  struct Tagged {
    std::string part;
    bool on_boundary = false;
  };
  std::map<FacetKey, Tagged> tagged;
  const int d = model.dim, fd = d - 1, npf = d;

  for (const auto& group : model.groups) {
    // An unnamed physical group (e.g. `Physical Curve(3) = {1};`) is called "group<tag>".
    const std::string part = group.name.empty() ? fmt::format("group{}", group.tag) : group.name;
    mesh.part_id(part);  // parts in the order of the groups, even an empty one

    for (const auto& b : group.blocks) {
      require(b.type == simplex_type(fd),
              "{}: physical group {} holds elements of type '{}' (Gmsh type {}); the facets of "
              "a {}D mesh must be {} (Gmsh type {})",
              file, quote(part), b.type_name, b.type, d, simplex_name(fd), simplex_type(fd));
      check_block(file, b, npf);
      for (std::size_t e = 0; e < b.tags.size(); ++e) {
        int v[3];
        for (int a = 0; a < npf; ++a) {
          auto it = index.find(b.nodes[e * npf + a]);
          require(it != index.end(),
                  "{}: physical group {} holds Gmsh element {}, which is not on the boundary of the "
                  "mesh (one of its nodes belongs to no cell)",
                  file, quote(part), b.tags[e]);
          v[a] = it->second;
        }
        auto [it, inserted] = tagged.emplace(facet_key(v, npf), Tagged{part});
        require(inserted || it->second.part == part,
                "{}: Gmsh element {} is in the physical groups {} and {}; a boundary facet can "
                "belong to one part only",
                file, b.tags[e], quote(it->second.part), quote(part));
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
      fail("{}: physical group {} holds a facet (at node ({}, {}, {})) that is not on the "
           "boundary of the mesh; only boundary facets can form a part",
           file, quote(t.part), p[0], p[1], p[2]);
    }
}

/// Puts the cells into the regions named by the physical groups of dimension d
/// (the materials' regions); cells of no group stay untagged.
void read_regions(const std::string& file, const GmshModel& model, Mesh& mesh) {
  if (model.regions.empty()) return;
  const int d = model.dim;
  std::unordered_map<std::size_t, int> cell_of_tag;  // Gmsh element tag -> cell (read_cells keeps the order)
  const std::vector<std::size_t>& tags = model.cells.front().tags;
  cell_of_tag.reserve(tags.size());
  for (std::size_t c = 0; c < tags.size(); ++c) cell_of_tag.emplace(tags[c], static_cast<int>(c));
  std::vector<std::string> region_of(tags.size());
  for (const auto& group : model.regions) {
    const std::string region = group.name.empty() ? fmt::format("group{}", group.tag) : group.name;
    for (const auto& b : group.blocks) {
      if (b.type != simplex_type(d)) continue;  // reported by read_cells for the cells themselves
      for (std::size_t tag : b.tags) {
        const auto it = cell_of_tag.find(tag);
        if (it == cell_of_tag.end()) continue;
        std::string& r = region_of[static_cast<std::size_t>(it->second)];
        require(r.empty() || r == region,
                "{}: Gmsh element {} is in the physical groups {} and {}; a cell can belong to one "
                "region (material) only",
                file, tag, quote(r), quote(region));
        if (r.empty()) {
          r = region;
          mesh.set_cell_region(it->second, region);
        }
      }
    }
  }
}

Mesh build_mesh(const std::string& file, const GmshModel& model) {
  const int d = model.dim;
  require(d >= 1 && d <= 3, "{}: the file holds no curve, surface or volume (model dimension {})", file, d);
  Mesh mesh(d);
  std::unordered_map<std::size_t, int> index;
  read_cells(file, model, mesh, index);
  mesh.build_boundary();
  read_parts(file, model, mesh, index);
  read_regions(file, model, mesh);
  return mesh;
}

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
  if (!options.trust_script) check_gmsh_script(file, options.trust_how);
  return build_mesh(name, read_in_child(name, options));
}

std::string describe_parts(const Mesh& mesh) {
  std::string out;
  for (const auto& part : mesh.part_names()) {
    const int n = mesh.part_size(part);
    out += fmt::format("{}{} ({} facet{})", out.empty() ? "" : ", ", part, n, n == 1 ? "" : "s");
  }
  return out.empty() ? "no parts" : printable(out, 300);
}

}  // namespace vpc
