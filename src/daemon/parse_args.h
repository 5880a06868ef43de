// acqd's and acqctl's arguments through CLI11, with the messages and exit status the tools have
// always had: --help prints the usage and exits 0; a wrong argument is "TOOL: what is wrong"
// and a pointer to --help on stderr, exit status 1.
#pragma once

#include <CLI/CLI.hpp>

#include <cstdio>
#include <optional>

namespace acq {

// The exit status to return now (help shown or an error), or nullopt to go on.
inline std::optional<int> ParseArgs(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::fputs(app.help().c_str(), stdout);
    return 0;
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "%s: %s\nrun %s --help for the usage\n", app.get_name().c_str(), e.what(),
                 app.get_name().c_str());
    return 1;
  }
  return std::nullopt;
}

}  // namespace acq
