// Minimal command-line parsing for the acq subcommands: --name value, --name=value, flags
// without values, and positionals. Unknown options and missing values are UserErrors that name
// the command and the option.
#pragma once

#include <map>
#include <set>
#include <string>
#include <vector>

namespace acq::cli {

class Args {
 public:
  // `valued` options take a value (repeatable: all values are kept); `flags` take none.
  Args(std::string command, const std::vector<std::string>& argv, std::set<std::string> valued,
       std::set<std::string> flags);

  bool Has(const std::string& name) const { return values_.count(name) > 0; }
  std::string Get(const std::string& name, const std::string& fallback = {}) const;
  std::string Required(const std::string& name) const;
  std::vector<std::string> All(const std::string& name) const;  // every value, comma-split too
  int GetInt(const std::string& name, int fallback) const;
  double GetDouble(const std::string& name, double fallback) const;
  const std::vector<std::string>& positionals() const { return positionals_; }

 private:
  std::string command_;
  std::map<std::string, std::vector<std::string>> values_;
  std::vector<std::string> positionals_;
};

}  // namespace acq::cli
