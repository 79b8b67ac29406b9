// The `wedge` command: `wedge run script.lua [args...]`, `wedge --version`, `wedge --help`.
// CLI11 parses the command line (a Debian package; it gives subcommands, help text and error
// messages that we would otherwise write and test by hand).
#include <CLI/CLI.hpp>

#include <iostream>

#include "kernel/kernel.h"
#include "lua/wedge_lua.h"

int main(int argc, char** argv) {
  CLI::App app{"wedge: a solid-modelling kernel with a Lua 5.4 front end"};
  app.set_version_flag("--version", std::string("wedge ") + wedge::version() + " (" LUA_RELEASE ")");
  app.require_subcommand(1);

  std::string script;
  auto* run = app.add_subcommand("run", "run a Lua script with the wedge API as globals");
  run->add_option("script", script, "the Lua script to run")->required();
  // Everything after the script name belongs to the script, even words that look like options.
  run->prefix_command();

  CLI11_PARSE(app, argc, argv);

  if (*run) {
    std::vector<std::string> args = run->remaining();
    return wedge::lua::run_file(script, args, std::cerr);
  }
  return 0;
}
