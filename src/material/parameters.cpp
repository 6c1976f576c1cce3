#include "material/parameters.hpp"

#include "core/error.hpp"

namespace vpc {

double Parameters::get(const std::string& key) const {
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

void Parameters::check_all_used(const std::string& where) const {
  for (const auto& [k, v] : values_)
    require(used_.count(k) > 0, "{}: unknown parameter '{}'", where, k);
}

}  // namespace vpc
