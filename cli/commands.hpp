#pragma once
/// \file
/// Subcommands of the stcweave program. Each `add_*_command` registers its options on
/// `app` and returns the function to run when the subcommand is chosen; that function
/// returns the exit code and lets library exceptions escape (main maps them to codes).

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <string>

namespace stcweave::cli {

/// Exit codes, documented in README.md.
inline constexpr int kSuccess = 0;
inline constexpr int kUsage = 1;
inline constexpr int kInvalidInput = 2;
inline constexpr int kInternal = 3;
/// `mesh --fail-on-inverted`: hexes are still inverted after untangling.
inline constexpr int kInverted = 4;

using Action = std::function<int()>;

/// A real option must be a finite number: CLI11's range checks compare, and NaN passes every
/// comparison. Put before the range check: `->check(kFinite)->check(CLI::Range(a, b))`.
inline const CLI::Validator kFinite(
    [](std::string& text) -> std::string {
      // strtod, not stod: stod throws on overflow ("1e400"), which CLI11 then stores as inf.
      char* end = nullptr;
      const double v = std::strtod(text.c_str(), &end);
      if (end == text.c_str()) return {};  // not a number at all: the option's own check says so
      if (std::isfinite(v)) return {};
      return "must be a finite number, not " + text;
    },
    "FINITE");

Action add_loops_command(CLI::App& app);
Action add_sheets_command(CLI::App& app);
Action add_mesh_command(CLI::App& app);
Action add_check_command(CLI::App& app);
Action add_bench_command(CLI::App& app);
Action add_generate_command(CLI::App& app);
Action add_quality_command(CLI::App& app);
Action add_view_command(CLI::App& app);

}  // namespace stcweave::cli
