// Command-line parsing for the acq subcommands: --name value, --name=value, flags without
// values, and positionals, split by CLI11 (issue 21); the typed, range-checked reading of the
// values and the messages are here. Unknown options and missing values are UserErrors that name
// the command and the option.
#pragma once

#include <climits>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace acq::cli {

// The usage text of the command being run (acq_main sets it): every option an Args accepts
// must appear in it as --name, or the command is a programmer's error (std::logic_error, acq's
// "internal error"), found by any test that runs the command (issue 22: help lists every option).
void SetCommandUsage(const char* usage);

class Args {
 public:
  // `valued` options take a value (repeatable: all values are kept); `flags` take none.
  Args(std::string command, const std::vector<std::string>& argv, std::set<std::string> valued,
       std::set<std::string> flags);

  bool Has(const std::string& name) const { return values_.count(name) > 0; }
  std::string Get(const std::string& name, const std::string& fallback = {}) const;
  std::string Required(const std::string& name) const;
  std::vector<std::string> All(const std::string& name) const;     // every value, comma-split too
  std::vector<std::string> Values(const std::string& name) const;  // every value, as given
  // Numbers are range-checked here, in one place (issue 22): every double must be finite (nan,
  // inf and 1e999 are refused), and each value given must lie in [lo, hi].
  int GetInt(const std::string& name, int fallback, int lo = INT_MIN, int hi = INT_MAX) const;
  double GetDouble(const std::string& name, double fallback, double lo = -1e300,
                   double hi = 1e300) const;
  const std::vector<std::string>& positionals() const { return positionals_; }

 private:
  std::string command_;
  std::map<std::string, std::vector<std::string>> values_;
  std::vector<std::string> positionals_;
};

}  // namespace acq::cli
