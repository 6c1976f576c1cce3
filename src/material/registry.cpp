// The registry: one line per law maps its name to its class.
#include "core/error.hpp"
#include "material/damage_source.hpp"
#include "material/laws/elastic.hpp"
#include "material/laws/maxwell_damage.hpp"
#include "material/laws/perzyna.hpp"
#include "material/sources/damage_sources.hpp"
#include "material/viscoplastic_law.hpp"

#include <fmt/ranges.h>

#include <functional>
#include <map>

namespace vpc {

namespace {

template <typename Base>
using Factory = std::function<std::unique_ptr<Base>(const Parameters&)>;

template <typename Base, typename T>
Factory<Base> entry() {
  return [](const Parameters& p) -> std::unique_ptr<Base> { return std::make_unique<T>(p); };
}

const std::map<std::string, Factory<ViscoplasticLaw>>& law_table() {
  static const std::map<std::string, Factory<ViscoplasticLaw>> t = {
      {"elastic", entry<ViscoplasticLaw, ElasticLaw>()},
      {"perzyna", entry<ViscoplasticLaw, PerzynaLaw>()},
      {"perzyna-von-mises", entry<ViscoplasticLaw, PerzynaVonMisesLaw>()},
      {"maxwell-damage", entry<ViscoplasticLaw, MaxwellDamageLaw>()},
  };
  return t;
}

const std::map<std::string, Factory<DamageSource>>& source_table() {
  static const std::map<std::string, Factory<DamageSource>> t = {
      {"zero", entry<DamageSource, ZeroSource>()},
      {"strain", entry<DamageSource, StrainSource>()},
      {"von-mises", entry<DamageSource, VonMisesSource>()},
  };
  return t;
}

template <typename Base>
std::unique_ptr<Base> build(const std::map<std::string, Factory<Base>>& table, const char* what,
                            const std::string& name, const Parameters& p) {
  auto it = table.find(name);
  if (it == table.end()) {
    std::vector<std::string> names;
    for (const auto& [k, v] : table) names.push_back(k);
    fail("unknown {} '{}'; expected one of: {}", what, name, fmt::join(names, ", "));
  }
  try {
    auto law = it->second(p);
    p.check_all_used("");
    return law;
  } catch (const Error& e) {
    fail("{} '{}': {}", what, name, e.what());
  }
}

template <typename Map>
std::vector<std::string> keys(const Map& m) {
  std::vector<std::string> out;
  for (const auto& [k, v] : m) out.push_back(k);
  return out;
}

template <typename Base>
std::vector<std::string> parameter_names(const std::map<std::string, Factory<Base>>& table, const std::string& name) {
  auto it = table.find(name);
  if (it == table.end()) return {};
  const Parameters probe = Parameters::discovering();
  it->second(probe);
  return {probe.used().begin(), probe.used().end()};
}

}  // namespace

std::vector<std::string> viscoplastic_law_parameters(const std::string& name) {
  return parameter_names(law_table(), name);
}
std::vector<std::string> damage_source_parameters(const std::string& name) {
  return parameter_names(source_table(), name);
}

std::unique_ptr<ViscoplasticLaw> make_viscoplastic_law(const std::string& name, const Parameters& p) {
  return build(law_table(), "viscoplastic law", name, p);
}
std::vector<std::string> viscoplastic_law_names() { return keys(law_table()); }

std::unique_ptr<DamageSource> make_damage_source(const std::string& name, const Parameters& p) {
  return build(source_table(), "damage source", name, p);
}
std::vector<std::string> damage_source_names() { return keys(source_table()); }

}  // namespace vpc
