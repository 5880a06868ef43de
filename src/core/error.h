// Errors a user can cause (bad files, bad arguments, bad plans) are reported as acq::UserError:
// what is wrong, where (a file, file:line, or an argument), and what to do about it.
// Programmer errors are assertions, not UserErrors.
#pragma once

#include <stdexcept>
#include <string>

namespace acq {

class UserError : public std::runtime_error {
 public:
  UserError(std::string where, std::string what, std::string fix = {})
      : std::runtime_error(Format(where, what, fix)),
        where_(std::move(where)),
        what_(std::move(what)),
        fix_(std::move(fix)) {}

  const std::string& where() const { return where_; }
  const std::string& problem() const { return what_; }
  const std::string& fix() const { return fix_; }

 private:
  static std::string Format(const std::string& where, const std::string& what,
                            const std::string& fix) {
    std::string s = where.empty() ? what : where + ": " + what;
    if (!fix.empty()) s += " (" + fix + ")";
    return s;
  }
  std::string where_, what_, fix_;
};

}  // namespace acq
