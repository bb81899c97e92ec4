// sinew: the command-line front end; without arguments it opens the editor (`sinew edit`).
#include <iostream>
#include <string>
#include <vector>

#include "cli/commands.h"

int main(int argc, char** argv) {
  CLI::App app{"Sinew: measure, edit and physically correct rhythmic character motion"};
  app.set_version_flag("--version", "sinew 0.1.0");
  app.require_subcommand(0, 1);
  int exit_code = 0;
  sinew::app::addInfoCommand(app, exit_code);
  sinew::app::addConvertCommand(app, exit_code);
  sinew::app::addAnalyzeCommand(app, exit_code);
  sinew::app::addStyleCommand(app, exit_code);
  sinew::app::addSimulateCommand(app, exit_code);
  sinew::app::addEvolveCommand(app, exit_code);
  sinew::app::addEditCommand(app, exit_code);
  sinew::app::addRenderCommand(app, exit_code);
  sinew::app::addCreatureCommand(app, exit_code);
  try {
    if (argc == 1) {
      app.parse(std::vector<std::string>{"edit"});  // no arguments: open the editor
    } else {
      app.parse(argc, argv);
    }
  } catch (const CLI::ParseError& error) {
    if (error.get_exit_code() == 0) return app.exit(error);  // --help, --version
    // Bad input on the command line is bad input: one line and exit 1 (docs/cli.md).
    const std::string command =
        app.get_subcommands().empty() ? "" : " " + app.get_subcommands().front()->get_name();
    std::cerr << "sinew: " << error.what() << " (see sinew" << command << " --help)\n";
    return 1;
  } catch (const std::exception& error) {
    // The last boundary: a library exception a command did not turn into a message (nlohmann's
    // on text it cannot write, an allocation failure) is one line and exit 1, never an abort.
    const std::string command =
        app.get_subcommands().empty() ? "sinew" : app.get_subcommands().front()->get_name();
    std::cerr << "sinew: " << command << ": " << error.what() << '\n';
    return 1;
  }
  if (app.get_subcommands().empty()) {
    std::cout << app.help();
    return 0;
  }
  return exit_code;
}
