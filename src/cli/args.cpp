#include "cli/args.h"

#include <cctype>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <stdexcept>

#include <CLI/CLI.hpp>

#include "core/error.h"

namespace acq::cli {

namespace {

const char* g_usage = nullptr;

// Whether `usage` names --name (or -name, for one letter) as a whole option.
bool NamesOption(const std::string& usage, const std::string& option) {
  for (std::size_t at = usage.find(option); at != std::string::npos;
       at = usage.find(option, at + 1)) {
    const std::size_t end = at + option.size();
    const bool starts =
        at == 0 || !std::isalnum(static_cast<unsigned char>(usage[at - 1])) && usage[at - 1] != '-';
    const bool ends = end == usage.size() ||
                      !(std::isalnum(static_cast<unsigned char>(usage[end])) || usage[end] == '-');
    if (starts && ends) return true;
  }
  return false;
}

bool Names(const std::string& usage, const std::string& name) {
  return NamesOption(usage, "--" + name) || (name.size() == 1 && NamesOption(usage, "-" + name));
}

}  // namespace

void SetCommandUsage(const char* usage) {
  g_usage = usage;
}

Args::Args(std::string command, const std::vector<std::string>& argv, std::set<std::string> valued,
           std::set<std::string> flags)
    : command_(std::move(command)) {
  if (g_usage) {
    std::string missing;
    for (const std::set<std::string>* names : {&valued, &flags})
      for (const std::string& name : *names)
        if (!Names(g_usage, name)) missing += " --" + name;
    if (!missing.empty())
      throw std::logic_error(command_ + " accepts" + missing + " but its help does not say so");
  }
  const std::string help = "see `" + command_ + " --help`";
  // The tokens are CLI11's to split (--name value, --name=value, -n value, flags, positionals,
  // "--"); the options' meanings and the messages stay this file's.
  CLI::App app{command_};
  app.set_help_flag();  // --help is acq_main's, before an Args is made
  app.allow_extras();   // an unknown option: our message below, naming it
  std::map<std::string, std::vector<std::string>> given;
  std::map<std::string, std::int64_t> counted;
  // A one-letter name is also -n (acq's -o); every name is --name.
  auto spelling = [](const std::string& name) {
    return name.size() == 1 ? "-" + name + ",--" + name : "--" + name;
  };
  for (const std::string& name : valued)
    app.add_option(spelling(name), given[name])
        ->expected(1)
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
        ->allow_extra_args(false);
  for (const std::string& name : flags) app.add_flag(spelling(name), counted[name]);
  for (const std::string& a : argv)  // a flag given a value: refused, not read as a count
    for (const std::string& name : flags)
      if (a.rfind("--" + name + "=", 0) == 0)
        throw UserError(command_ + " --" + name, "takes no value", help);
  std::vector<std::string> reversed(argv.rbegin(), argv.rend());  // CLI11 takes them reversed
  try {
    app.parse(reversed);
  } catch (const CLI::ArgumentMismatch& e) {
    throw UserError(command_, std::string(e.what()) + ": an option needs a value", help);
  } catch (const CLI::ParseError& e) {
    throw UserError(command_, e.what(), help);
  }
  for (const std::string& extra : app.remaining()) {
    if (extra.size() > 1 && extra[0] == '-' && !std::isdigit(static_cast<unsigned char>(extra[1])))
      throw UserError(command_, "unknown option " + extra.substr(0, extra.find('=')), help);
    positionals_.push_back(extra);
  }
  for (auto& [name, values] : given)
    if (!values.empty()) values_[name] = std::move(values);
  for (const auto& [name, count] : counted)
    if (count > 0) values_[name] = std::vector<std::string>(std::size_t(count), "1");
}

std::string Args::Get(const std::string& name, const std::string& fallback) const {
  const auto it = values_.find(name);
  return it == values_.end() ? fallback : it->second.back();
}

std::string Args::Required(const std::string& name) const {
  if (!Has(name))
    throw UserError(command_, "missing required option --" + name, "see `" + command_ + " --help`");
  return Get(name);
}

std::vector<std::string> Args::Values(const std::string& name) const {
  const auto it = values_.find(name);
  return it == values_.end() ? std::vector<std::string>() : it->second;
}

std::vector<std::string> Args::All(const std::string& name) const {
  std::vector<std::string> out;
  const auto it = values_.find(name);
  if (it == values_.end()) return out;
  for (const std::string& v : it->second) {
    std::istringstream s(v);
    for (std::string part; std::getline(s, part, ',');)
      if (!part.empty()) out.push_back(part);
  }
  // Given but naming nothing (`--materials ,`) is a slip, not a request for the default.
  if (out.empty())
    throw UserError(command_ + " --" + name, "the list given is empty",
                    "name at least one value, separated by commas");
  return out;
}

namespace {

// Throws when `x` (given as `v`) lies outside [lo, hi].
template <class T>
void CheckRange(const std::string& option, const std::string& command, const std::string& v, T x,
                T lo, T hi) {
  if (x >= lo && x <= hi) return;
  std::ostringstream range;
  range << lo << " to " << hi;
  throw UserError(option, v + " is outside " + range.str(), "see `" + command + " --help`");
}

}  // namespace

int Args::GetInt(const std::string& name, int fallback, int lo, int hi) const {
  if (!Has(name)) return fallback;
  const std::string v = Get(name);
  std::size_t used = 0;
  int x = 0;
  try {
    x = std::stoi(v, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != v.size() || v.empty())
    throw UserError(command_ + " --" + name, "expected an integer, got '" + v + "'");
  CheckRange(command_ + " --" + name, command_, v, x, lo, hi);
  return x;
}

double Args::GetDouble(const std::string& name, double fallback, double lo, double hi) const {
  if (!Has(name)) return fallback;
  const std::string v = Get(name);
  std::size_t used = 0;
  double x = 0;
  try {
    x = std::stod(v, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != v.size() || v.empty())
    throw UserError(command_ + " --" + name, "expected a number, got '" + v + "'");
  if (!std::isfinite(x))
    throw UserError(command_ + " --" + name, "expected a finite number, got '" + v + "'");
  CheckRange(command_ + " --" + name, command_, v, x, lo, hi);
  return x;
}

}  // namespace acq::cli
