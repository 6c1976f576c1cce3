// The mortar set-up of a contact pair against the number of slave facets (issue 29,
// docs/performance.md "Mortar set-up"): the shipped contact-patch-3d (or -2d) with both blocks
// refined, the slave and master surfaces cut from the mesh (part_surface) and their coupling
// D, M, g̃ (mortar_coupling: facet search, clipping, dual basis), timed as a pair's rows are made.
//   vpcontact-mortar-bench [--dim 3] [--n 10,20,40,80] [--repeat 3]
#include "cases/builtin_cases.hpp"
#include "mortar/mortar_coupling.hpp"
#include "problem/contact_pairs.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <vector>

int main(int argc, char** argv) {
  CLI::App app{"vpcontact-mortar-bench: the mortar integrals of a contact pair against the slave facets"};
  int dim = 3, repeat = 3;
  std::vector<int> ns = {10, 20, 40, 80};
  app.add_option("--dim", dim, "2 or 3 (contact-patch-2d or -3d)")->capture_default_str();
  app.add_option("--n", ns, "lower block cells per edge; the upper (slave) block has 1.4 n")->delimiter(',');
  app.add_option("--repeat", repeat, "timings per size (the fastest is reported)")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  try {
    fmt::print("{:>6} {:>14} {:>14} {:>14} {:>12} {:>16}\n", "n", "slave facets", "master facets", "slave nodes",
               "seconds", "us/slave facet");
    for (const int n : ns) {
      const int m = (7 * n + 4) / 5;
      vpc::CaseOverrides o;
      o.sets = dim == 3 ? std::vector<std::string>{fmt::format("mesh.cells=[{}, {}, 2]", n, n),
                                                   fmt::format("body[0].mesh.cells=[{}, {}, 2]", m, m)}
                        : std::vector<std::string>{fmt::format("mesh.cells=[{}, 2]", n),
                                                   fmt::format("body[0].mesh.cells=[{}, 2]", m)};
      const vpc::Case c = vpc::load_case(fmt::format("contact-patch-{}d", dim), o);
      const vpc::Mesh& mesh = c.problem->mesh;
      double best = 1e300;
      std::size_t slave_nodes = 0;
      int slave_facets = 0, master_facets = 0;
      for (int r = 0; r < repeat; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        const vpc::mortar::Surface slave = vpc::part_surface(mesh, "upper.bottom");
        const vpc::mortar::Surface master = vpc::part_surface(mesh, "top");
        vpc::mortar::MortarOptions options;
        options.search_margin = slave.longest_edge();  // a pair's default search, as pair_rows takes it
        const vpc::mortar::MortarCoupling coupling = vpc::mortar::mortar_coupling(slave, master, options);
        best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        slave_nodes = coupling.nodes.size();
        slave_facets = slave.n_facets();
        master_facets = master.n_facets();
      }
      fmt::print("{:>6} {:>14} {:>14} {:>14} {:>12.4g} {:>16.3g}\n", n, slave_facets, master_facets, slave_nodes, best,
                 1e6 * best / slave_facets);
      std::fflush(stdout);
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "vpcontact-mortar-bench: error: {}\n", e.what());
    return 1;
  }
  return 0;
}
