#pragma once
// Named numeric parameters of a law, as given on the command line or in a case
// file. Every key must be consumed: an unknown key is an error, never ignored.
#include <map>
#include <set>
#include <string>
#include <vector>

namespace vpc {

class Parameters {
 public:
  Parameters() = default;
  Parameters(std::initializer_list<std::pair<const std::string, double>> init) : values_(init) {}

  /// Parameters that answer every get() with 1 (or its fallback) and record the
  /// key: building a law with them lists the law's parameter names.
  static Parameters discovering() {
    Parameters p;
    p.discovering_ = true;
    return p;
  }

  void set(const std::string& key, double v) { values_[key] = v; }
  bool has(const std::string& key) const { return values_.count(key) > 0; }
  /// Value of a required key; throws naming `where` and the key if missing.
  double get(const std::string& key) const;
  double get(const std::string& key, double fallback) const;
  /// Throws if a key was never read: `where` names the law for the message.
  void check_all_used(const std::string& where) const;
  const std::map<std::string, double>& values() const { return values_; }
  /// Keys given but never read, and keys read (the ones the law knows).
  std::vector<std::string> unused() const;
  const std::set<std::string>& used() const { return used_; }

 private:
  std::map<std::string, double> values_;
  mutable std::set<std::string> used_;
  bool discovering_ = false;
};

}  // namespace vpc
