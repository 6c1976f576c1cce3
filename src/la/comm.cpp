#include "la/comm.hpp"

#include "core/error.hpp"

namespace vpc::la {

void Comm::throw_if_any(bool failed, const std::string& message) const {
  if (!b_) {
    if (failed) throw CollectiveError(message);
    return;
  }
  const std::string first = b_->first_failure(failed, message.empty() ? "an error on another rank" : message);
  if (!first.empty()) throw CollectiveError(first);
}

}  // namespace vpc::la
