/// The stcweave command-line program: parses the command line, runs one subcommand, and
/// maps library exceptions to exit codes (0 success, 1 usage, 2 invalid input, 3 internal
/// failure, 4 inverted hexes left with `mesh --fail-on-inverted`) with a one-line message on
/// stderr.

#include <iostream>
#include <string>
#include <vector>

#include "allocator.hpp"
#include "commands.hpp"
#include "stcweave/stc/errors.hpp"

namespace {

int run(int argc, char** argv) {
  using namespace stcweave;
  CLI::App app{
      "stcweave: fill a closed quad surface with hexahedra by weaving its Spatial Twist "
      "Continuum.\nExit codes: 0 success, 1 usage, 2 invalid input, 3 internal failure, 4 "
      "inverted hexes left (mesh --fail-on-inverted)."};
  app.require_subcommand(1);
  app.set_version_flag("--version", "stcweave 0.1.0");

  std::vector<std::pair<CLI::App*, cli::Action>> commands;
  const auto add = [&](auto&& factory) {
    const std::size_t before = app.get_subcommands({}).size();
    cli::Action action = factory(app);
    commands.emplace_back(app.get_subcommands({}).at(before), std::move(action));
  };
  add(cli::add_mesh_command);
  add(cli::add_check_command);
  add(cli::add_loops_command);
  add(cli::add_sheets_command);
  add(cli::add_bench_command);
  add(cli::add_generate_command);
  add(cli::add_quality_command);
  add(cli::add_view_command);

  // A first word that names no command: CLI11 would only say "A subcommand is required".
  if (argc > 1 && argv[1][0] != '-') {
    const std::string word = argv[1];
    std::string names;
    bool known = false;
    for (const auto& [sub, action] : commands) {
      known = known || sub->check_name(word);
      names += (names.empty() ? "" : ", ") + sub->get_name();
    }
    if (!known) {
      std::cerr << "stcweave: unknown command '" << word << "'; the commands are " << names
                << " (stcweave --help lists them, stcweave COMMAND --help their options)\n";
      return cli::kUsage;
    }
  }

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? cli::kSuccess : cli::kUsage;
  }

  try {
    for (auto& [sub, action] : commands)
      if (sub->parsed()) return action();
    return cli::kUsage;
  } catch (const InvalidInput& e) {
    std::cerr << "stcweave: invalid input: " << e.what() << "\n";
    return cli::kInvalidInput;
  } catch (const IoError& e) {
    std::cerr << "stcweave: " << e.what() << "\n";
    return cli::kInvalidInput;
  } catch (const Error& e) {
    std::cerr << "stcweave: failure: " << e.what() << "\n";
    return cli::kInternal;
  } catch (const std::exception& e) {
    std::cerr << "stcweave: internal error: " << e.what()
              << " (this is a bug: please report it with the input file)\n";
    return cli::kInternal;
  }
}

}  // namespace

int main(int argc, char** argv) {
  stcweave::cli::tune_allocator();
  try {
    return run(argc, argv);
  } catch (...) {  // e.g. out of memory while setting up the command line
    std::cerr << "stcweave: internal error before any command ran\n";
    return stcweave::cli::kInternal;
  }
}
