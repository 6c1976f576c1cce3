#pragma once
// An adaptive run's records as JSON (nlohmann): summary.json's "adaptations" entries and the
// refinement history a checkpoint keeps beside it (adapt/mesh_adaptivity.hpp), one conversion each way.
#include "adapt/mesh_adaptivity.hpp"

#include <nlohmann/json.hpp>

namespace vpc {

/// One adaptation as summary.json writes it (numbers round-trip exactly).
nlohmann::ordered_json adaptation_json(const AdaptationRecord& a);
/// Back (throws vpc::Error naming the key for a malformed entry).
AdaptationRecord adaptation_record(const nlohmann::ordered_json& j);

}  // namespace vpc
