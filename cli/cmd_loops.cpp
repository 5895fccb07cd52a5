// PLACEHOLDER: being written (must be replaced before commit)
#include "commands.hpp"
namespace stcweave::cli {
Action add_loops_command(CLI::App& app) {
  app.add_subcommand("loops", "not yet");
  return [] { return 3; };
}
}  // namespace stcweave::cli
