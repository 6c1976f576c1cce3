#include "adapt/adaptation_json.hpp"

#include "core/error.hpp"

namespace vpc {

nlohmann::ordered_json adaptation_json(const AdaptationRecord& a) {
  return {{"step", a.step},
          {"t", a.t},
          {"pass", a.pass},
          {"cells_before", a.cells_before},
          {"cells_after", a.cells_after},
          {"unknowns_before", a.unknowns_before},
          {"unknowns_after", a.unknowns_after},
          {"marked", a.marked},
          {"bisected", a.bisected},
          {"forecast_passes", a.forecast_passes},
          {"removed_nodes", a.removed_nodes},
          {"max_level", a.max_level},
          {"min_angle_degrees", a.min_angle_degrees},
          {"h_min", a.h_min},
          {"stress_estimate", a.stress_relative},
          {"coarsening_change",
           {{"z", a.change_z}, {"sigma", a.change_sigma}, {"beta", a.change_beta}, {"damage_integral", a.change_damage_integral}}},
          {"dirichlet_mismatch", a.dirichlet_mismatch},
          {"penetration", a.penetration},
          {"truncated", a.truncated},
          {"seconds_adapt", a.seconds_adapt},
          {"seconds_rebuild", a.seconds_rebuild},
          {"resident_bytes", a.resident_bytes},
          {"linear_solver", a.linear_solver}};
}

AdaptationRecord adaptation_record(const nlohmann::ordered_json& j) {
  try {
    AdaptationRecord a;
    a.step = j.at("step").get<int>();
    a.t = j.at("t").get<double>();
    a.pass = j.at("pass").get<int>();
    a.cells_before = j.at("cells_before").get<long long>();
    a.cells_after = j.at("cells_after").get<long long>();
    a.unknowns_before = j.at("unknowns_before").get<long long>();
    a.unknowns_after = j.at("unknowns_after").get<long long>();
    a.marked = j.at("marked").get<int>();
    a.bisected = j.at("bisected").get<int>();
    a.forecast_passes = j.value("forecast_passes", 0);  // (not in the histories of checkpoints before it)
    a.removed_nodes = j.at("removed_nodes").get<int>();
    a.max_level = j.at("max_level").get<int>();
    a.min_angle_degrees = j.at("min_angle_degrees").get<double>();
    a.h_min = j.at("h_min").get<double>();
    a.stress_relative = j.at("stress_estimate").get<double>();
    const auto& c = j.at("coarsening_change");
    a.change_z = c.at("z").get<double>();
    a.change_sigma = c.at("sigma").get<double>();
    a.change_beta = c.at("beta").get<double>();
    a.change_damage_integral = c.at("damage_integral").get<double>();
    a.dirichlet_mismatch = j.at("dirichlet_mismatch").get<double>();
    a.penetration = j.at("penetration").get<double>();
    a.truncated = j.at("truncated").get<bool>();
    a.seconds_adapt = j.at("seconds_adapt").get<double>();
    a.seconds_rebuild = j.at("seconds_rebuild").get<double>();
    a.resident_bytes = j.at("resident_bytes").get<double>();
    a.linear_solver = j.value("linear_solver", std::string());  // (not in the histories of checkpoints before it)
    return a;
  } catch (const nlohmann::json::exception& e) {
    fail("an adaptation record: {}", e.what());
  }
}

}  // namespace vpc
