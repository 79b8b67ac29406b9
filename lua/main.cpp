// The `wedge` command: `wedge run [--quiet] [--stats] [--sandbox] script.lua [args...]`,
// `wedge --version`, `wedge --help`. CLI11 parses the command line (a Debian package; it gives
// subcommands, help text and error messages that we would otherwise write and test by hand).
#include <CLI/CLI.hpp>

#include <iostream>

#include "kernel/kernel.h"
#include "lua/wedge_lua.h"
#include "kernel/memory.h"

int main(int argc, char** argv) {
  wedge::tune_malloc(argv);  // first: it may execute the program again
  CLI::App app{"wedge: a solid-modelling kernel with a Lua 5.4 front end"};
  app.set_version_flag("--version", std::string("wedge ") + wedge::version() + " (" LUA_RELEASE ")");
  app.require_subcommand(1);

  std::string script;
  wedge::lua::RunOptions options;
  auto* run = app.add_subcommand("run", "run a Lua script with the wedge API as globals; key=value arguments "
                                        "also become params.key");
  run->add_flag("--quiet", options.quiet, "the script's print() writes nothing; only errors are reported");
  run->add_flag("--stats", options.stats, "report the time spent per stage on stderr");
  run->add_flag("--sandbox", options.sandbox, "run a stranger's script confined (see README)");
  run->add_option("script", script, "the Lua script to run")->required();
  // Everything after the script name belongs to the script, even words that look like options,
  // except the runner's own three flags (so that `wedge run model.lua --sandbox` is never run
  // unconfined); after "--" every word is the script's.
  run->prefix_command();

  // CLI11 sees the words before the first "--"; the words after it are the script's, verbatim.
  int cli_argc = argc;
  std::vector<std::string> verbatim;
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--") {
      cli_argc = i;
      verbatim.assign(argv + i + 1, argv + argc);
      break;
    }
  // A first word that is no option and no subcommand is named: CLI11 said only "A subcommand is
  // required" for `wedge frobnicate`, as if nothing had been given.
  if (cli_argc > 1 && argv[1][0] != '-' && argv[1] != run->get_name())
    return app.exit(CLI::Error("UnknownSubcommand",
                               "unknown subcommand '" + std::string(argv[1]) + "' (the subcommand is run: wedge run script.lua)",
                               CLI::ExitCodes::RequiredError));
  CLI11_PARSE(app, cli_argc, argv);

  if (*run) {
    std::vector<std::string> args;
    for (const std::string& a : run->remaining()) {
      if (a == "--quiet") options.quiet = true;
      else if (a == "--stats") options.stats = true;
      else if (a == "--sandbox") options.sandbox = true;
      else args.push_back(a);
    }
    args.insert(args.end(), verbatim.begin(), verbatim.end());
    return wedge::lua::run_file(script, args, std::cerr, options);
  }
  return 0;
}
