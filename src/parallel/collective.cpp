#include "parallel/collective.hpp"

namespace vpc {

void throw_if_failed_anywhere(MPI_Comm comm, bool failed, std::string message) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const int mine = failed ? rank : size;
  int first = size;
  MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm);
  if (first == size) return;
  int n = static_cast<int>(message.size());
  MPI_Bcast(&n, 1, MPI_INT, first, comm);
  message.resize(static_cast<std::size_t>(n));
  MPI_Bcast(message.data(), n, MPI_CHAR, first, comm);
  throw CollectiveError(message);
}

}  // namespace vpc
