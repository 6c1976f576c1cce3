#include "material/parameters.hpp"

#include "core/error.hpp"

namespace vpc {

double Parameters::get(const std::string& key) const {
  if (discovering_) {
    used_.insert(key);
    return 1.0;
  }
  auto it = values_.find(key);
  require(it != values_.end(), "missing parameter '{}'", key);
  used_.insert(key);
  return it->second;
}

double Parameters::get(const std::string& key, double fallback) const {
  used_.insert(key);
  auto it = values_.find(key);
  return it == values_.end() ? fallback : it->second;
}

std::vector<std::string> Parameters::unused() const {
  std::vector<std::string> out;
  for (const auto& [k, v] : values_)
    if (!used_.count(k)) out.push_back(k);
  return out;
}

void Parameters::check_all_used(const std::string& where) const {
  for (const auto& [k, v] : values_)
    if (!used_.count(k)) {
      std::string known;
      for (const auto& u : used_) known += (known.empty() ? "" : ", ") + u;
      fail("{}unknown parameter '{}'; the parameters are: {}", where.empty() ? "" : where + ": ", k,
           known.empty() ? "(none)" : known);
    }
}

}  // namespace vpc
