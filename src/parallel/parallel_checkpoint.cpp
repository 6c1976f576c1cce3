#include "parallel/parallel_checkpoint.hpp"

#include "parallel/collective.hpp"

#include <fmt/format.h>

#include <type_traits>

namespace vpc {

namespace {

std::vector<SymTensor> to_tensors(const double* v, size_t n) {
  std::vector<SymTensor> t(n);
  for (size_t c = 0; c < n; ++c)
    for (int j = 0; j < 6; ++j) t[c][j] = v[c * 6 + j];
  return t;
}

/// Gathers each rank's list of ids to rank 0 (counts and displacements included).
struct Gathered {
  std::vector<int> counts, displs, ids;
};
Gathered gather_ids(MPI_Comm comm, const std::vector<int>& ids) {
  const int size = comm_size(comm), rank = comm_rank(comm);
  Gathered g;
  g.counts.resize(size);
  g.displs.resize(size);
  const int n = static_cast<int>(ids.size());
  MPI_Gather(&n, 1, MPI_INT, g.counts.data(), 1, MPI_INT, 0, comm);
  if (rank == 0) {
    int total = 0;
    for (int r = 0; r < size; ++r) {
      g.displs[r] = total;
      total += g.counts[r];
    }
    g.ids.resize(total);
  }
  MPI_Gatherv(ids.data(), n, MPI_INT, g.ids.data(), g.counts.data(), g.displs.data(), MPI_INT, 0, comm);
  return g;
}

/// Rank 0 sends every rank `width` values per id, taken from `values` (width per item, by id).
std::vector<double> scatter_values(MPI_Comm comm, const Gathered& g, const std::vector<double>& values, int width,
                                   int n_mine) {
  const int rank = comm_rank(comm), size = comm_size(comm);
  std::vector<double> send;
  std::vector<int> counts(size), displs(size);
  if (rank == 0) {
    send.resize(g.ids.size() * width);
    for (size_t k = 0; k < g.ids.size(); ++k)
      for (int j = 0; j < width; ++j) send[k * width + j] = values[static_cast<size_t>(g.ids[k]) * width + j];
    for (int r = 0; r < size; ++r) {
      counts[r] = g.counts[r] * width;
      displs[r] = g.displs[r] * width;
    }
  }
  std::vector<double> mine(static_cast<size_t>(n_mine) * width);
  MPI_Scatterv(send.data(), counts.data(), displs.data(), MPI_DOUBLE, mine.data(), n_mine * width, MPI_DOUBLE, 0,
               comm);
  return mine;
}

}  // namespace

std::uint64_t problem_fingerprint(const DistributedTimeStepper& s) {
  // The key and hash of io/checkpoint.cpp's problem_fingerprint(const TimeStepper&).
  const Problem& p = s.problem();
  const auto& part = s.part();
  const std::string key =
      fmt::format("{}|{}|{}|{}|{}|{}|{}|{:.17g}|{:.17g}|{}|{}|{}", p.name, part.mesh.dim(), part.n_global_nodes,
                  part.n_global_cells, part.n_global_dofs, part.n_contact, p.n_steps, p.final_time, p.kappa,
                  p.elasticity.name(), p.law->describe(), p.source->describe());
  std::uint64_t h = 1469598103934665603ull;
  for (char c : key) h = (h ^ static_cast<unsigned char>(c)) * 1099511628211ull;
  return h;
}

void write_checkpoint(const DistributedTimeStepper& stepper, const std::filesystem::path& dir,
                      const std::string& case_name, const std::vector<std::pair<double, std::string>>& pvd,
                      const RunTotals& totals) {
  const auto& part = stepper.part();
  const MPI_Comm comm = part.comm;
  const int d = part.mesh.dim();
  const std::vector<int> owned(part.original_node.begin(), part.original_node.begin() + part.n_owned_nodes);
  const Vector u = stepper.local_u(), beta = stepper.local_beta();
  std::vector<double> clamped(part.n_owned_nodes);
  for (int i = 0; i < part.n_owned_nodes; ++i) clamped[i] = part.dofs.free_index(part.dofs.full_index(i, 0)) < 0;
  const auto& st = stepper.state();
  std::vector<double> cells;
  cells.reserve(st.sigma.size() * 18);
  for (size_t c = 0; c < st.sigma.size(); ++c)
    for (const auto* t : {&st.sigma[c], &st.eps[c], &st.z[c]}) cells.insert(cells.end(), t->c.begin(), t->c.end());
  const Vector U = gather_to_root(comm, owned, u.data(), d, part.n_global_nodes);
  const Vector B = gather_to_root(comm, owned, beta.data(), 1, part.n_global_nodes);
  const Vector C = gather_to_root(comm, owned, clamped.data(), 1, part.n_global_nodes);
  const Vector T = gather_to_root(comm, part.original_cell, cells.data(), 18, part.n_global_cells);
  const std::uint64_t fingerprint = problem_fingerprint(stepper);
  on_root(comm, [&] {
    Checkpoint ck;
    ck.case_name = case_name;
    ck.fingerprint = fingerprint;
    State& s = ck.snapshot.state;
    s.n = st.n;
    s.t = st.t;
    s.u = U;
    s.beta = B;
    s.lambda = st.lambda;
    const auto n_cells = static_cast<size_t>(part.n_global_cells);
    std::vector<double> sig(n_cells * 6), eps(n_cells * 6), z(n_cells * 6);
    for (size_t c = 0; c < n_cells; ++c)
      for (int j = 0; j < 6; ++j) {
        sig[c * 6 + j] = T[c * 18 + j];
        eps[c * 6 + j] = T[c * 18 + 6 + j];
        z[c * 6 + j] = T[c * 18 + 12 + j];
      }
    s.sigma = to_tensors(sig.data(), n_cells);
    s.eps = to_tensors(eps.data(), n_cells);
    s.z = to_tensors(z.data(), n_cells);
    // u on the free dofs of the serial numbering (node-major, clamped nodes dropped).
    ck.snapshot.u_free.resize(part.n_global_dofs);
    Eigen::Index k = 0;
    for (PetscInt i = 0; i < part.n_global_nodes; ++i)
      if (C[i] == 0)
        for (int c = 0; c < d; ++c) ck.snapshot.u_free[k++] = U[i * d + c];
    ck.pvd = pvd;
    ck.totals = totals;
    vpc::write_checkpoint(dir, ck);
  });
}

std::optional<ResumePoint> resume_from_checkpoint(DistributedTimeStepper& stepper, const std::filesystem::path& dir,
                                                  std::vector<std::string>* skipped) {
  const auto& part = stepper.part();
  const MPI_Comm comm = part.comm;
  const int d = part.mesh.dim();
  std::optional<Checkpoint> ck;
  on_root(comm, [&] {
    ck = find_checkpoint(dir, problem_fingerprint(stepper), skipped);
    if (ck) {
      const State& s = ck->snapshot.state;
      const bool fits = s.u.size() == part.n_global_nodes * d && s.beta.size() == part.n_global_nodes &&
                        static_cast<long long>(s.sigma.size()) == part.n_global_cells &&
                        s.lambda.size() == part.n_contact;
      require(fits, "resume: the checkpoint of step {} does not fit this problem", s.n);
    }
  });
  int found = ck.has_value();
  MPI_Bcast(&found, 1, MPI_INT, 0, comm);
  if (!found) return std::nullopt;

  // Node values (u, β) and cell values (σ, ε, z) to the ranks that hold them.
  std::vector<double> node_values, cell_values;
  ResumePoint rp;
  Vector lambda(part.n_contact);
  if (ck) {
    const State& s = ck->snapshot.state;
    node_values.resize(static_cast<size_t>(part.n_global_nodes) * (d + 1));
    for (PetscInt i = 0; i < part.n_global_nodes; ++i) {
      for (int c = 0; c < d; ++c) node_values[i * (d + 1) + c] = s.u[i * d + c];
      node_values[i * (d + 1) + d] = s.beta[i];
    }
    cell_values.resize(s.sigma.size() * 18);
    for (size_t c = 0; c < s.sigma.size(); ++c)
      for (int j = 0; j < 6; ++j) {
        cell_values[c * 18 + j] = s.sigma[c][j];
        cell_values[c * 18 + 6 + j] = s.eps[c][j];
        cell_values[c * 18 + 12 + j] = s.z[c][j];
      }
    rp.n = s.n;
    rp.t = s.t;
    rp.pvd = ck->pvd;
    rp.totals = ck->totals;
    lambda = s.lambda;
  }
  const std::vector<double> nodes =
      scatter_values(comm, gather_ids(comm, part.original_node), node_values, d + 1, part.n_local_nodes());
  const std::vector<double> cells =
      scatter_values(comm, gather_ids(comm, part.original_cell), cell_values, 18, part.mesh.n_cells());
  MPI_Bcast(&rp.n, 1, MPI_INT, 0, comm);
  MPI_Bcast(&rp.t, 1, MPI_DOUBLE, 0, comm);
  MPI_Bcast(lambda.data(), static_cast<int>(lambda.size()), MPI_DOUBLE, 0, comm);
  static_assert(std::is_trivially_copyable_v<RunTotals>);
  MPI_Bcast(&rp.totals, sizeof(RunTotals), MPI_BYTE, 0, comm);
  // PVD entries: count, times, then the file names joined by '\n'.
  int n_pvd = static_cast<int>(rp.pvd.size());
  MPI_Bcast(&n_pvd, 1, MPI_INT, 0, comm);
  std::vector<double> times(n_pvd);
  std::string names;
  if (comm_rank(comm) == 0)
    for (int k = 0; k < n_pvd; ++k) {
      times[k] = rp.pvd[k].first;
      names += rp.pvd[k].second + '\n';
    }
  int n_names = static_cast<int>(names.size());
  MPI_Bcast(times.data(), n_pvd, MPI_DOUBLE, 0, comm);
  MPI_Bcast(&n_names, 1, MPI_INT, 0, comm);
  names.resize(n_names);
  MPI_Bcast(names.data(), n_names, MPI_CHAR, 0, comm);
  if (comm_rank(comm) != 0) {
    rp.pvd.clear();
    size_t pos = 0;
    for (int k = 0; k < n_pvd; ++k) {
      const size_t end = names.find('\n', pos);
      rp.pvd.emplace_back(times[k], names.substr(pos, end - pos));
      pos = end + 1;
    }
  }

  const int n_local = part.n_local_nodes(), n_cells = part.mesh.n_cells();
  Vector u(static_cast<Eigen::Index>(n_local) * d), beta(n_local);
  for (int i = 0; i < n_local; ++i) {
    for (int c = 0; c < d; ++c) u[i * d + c] = nodes[static_cast<size_t>(i) * (d + 1) + c];
    beta[i] = nodes[static_cast<size_t>(i) * (d + 1) + d];
  }
  std::vector<double> sig(static_cast<size_t>(n_cells) * 6), eps(sig.size()), z(sig.size());
  for (int c = 0; c < n_cells; ++c)
    for (int j = 0; j < 6; ++j) {
      sig[c * 6 + j] = cells[c * 18 + j];
      eps[c * 6 + j] = cells[c * 18 + 6 + j];
      z[c * 6 + j] = cells[c * 18 + 12 + j];
    }
  stepper.restore(rp.n, rp.t, u, beta, to_tensors(sig.data(), n_cells), to_tensors(eps.data(), n_cells),
                  to_tensors(z.data(), n_cells), lambda);
  return rp;
}

}  // namespace vpc
