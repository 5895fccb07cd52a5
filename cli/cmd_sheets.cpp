// PLACEHOLDER: being written (must be replaced before commit)
#include "commands.hpp"
namespace stcweave::cli {
Action add_sheets_command(CLI::App& app) {
  app.add_subcommand("sheets", "not yet");
  return [] { return 3; };
}
}  // namespace stcweave::cli
