#pragma once
// The whole mesh's contact rows as a set-up shares them (the rows: problem/contact_rows.hpp).
#include <memory>
#include <vector>

namespace vpc {

struct ContactRow;

/// The whole mesh's contact rows of a problem (contact_rows), built once per set-up: by
/// Problem::validate, whose checks build them, and handed to what reads them (the solver plan,
/// the cut into parts, the blocks' checks and sizes) instead of being built again by each.
using ContactRows = std::shared_ptr<const std::vector<ContactRow>>;

}  // namespace vpc
