#pragma once
// Named numeric parameters of a law, as given on the command line or in a case
// file. Every key must be consumed: an unknown key is an error, never ignored.
#include <map>
#include <set>
#include <string>

namespace vpc {

class Parameters {
 public:
  Parameters() = default;
  Parameters(std::initializer_list<std::pair<const std::string, double>> init) : values_(init) {}

  void set(const std::string& key, double v) { values_[key] = v; }
  bool has(const std::string& key) const { return values_.count(key) > 0; }
  /// Value of a required key; throws naming `where` and the key if missing.
  double get(const std::string& key) const;
  double get(const std::string& key, double fallback) const;
  /// Throws if a key was never read: `where` names the law for the message.
  void check_all_used(const std::string& where) const;
  const std::map<std::string, double>& values() const { return values_; }

 private:
  std::map<std::string, double> values_;
  mutable std::set<std::string> used_;
};

}  // namespace vpc
