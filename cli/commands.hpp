#pragma once
/// \file
/// Subcommands of the stcweave program. Each `add_*_command` registers its options on
/// `app` and returns the function to run when the subcommand is chosen; that function
/// returns the exit code and lets library exceptions escape (main maps them to codes).

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <string>

#include "stcweave/primal/io.hpp"

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
      // CLI11 reads an empty value as 0 without an error.
      if (text.empty()) return "must be a number, not an empty value";
      char* end = nullptr;
      const double v = std::strtod(text.c_str(), &end);
      if (end == text.c_str()) return {};  // not a number at all: the option's own check says so
      if (std::isfinite(v)) return {};
      return "must be a finite number, not " + text;
    },
    "FINITE");

/// A count (an unsigned option): digits only, at most 18 of them (below 10^18). CLI11 reads
/// "-1" into an unsigned as its wrap-around and an empty or overflowing value without an
/// error, so such options check the text first: `->check(kCount)`.
inline const CLI::Validator kCount(
    [](std::string& text) -> std::string {
      const bool digits = !text.empty() && text.size() <= 18 &&
                          std::all_of(text.begin(), text.end(),
                                      [](unsigned char c) { return c >= '0' && c <= '9'; });
      if (digits) return {};
      return "must be a whole number from 0 to 999999999999999999, not '" + text + "'";
    },
    "COUNT");

/// The input format an option names: "auto" (every command's default) guesses from the
/// file's extension; any other name goes to `primal::format_from_name`, which refuses an
/// unknown or empty one.
inline primal::Format input_format(const std::string& name) {
  return name == "auto" ? primal::Format::Auto : primal::format_from_name(name);
}

Action add_loops_command(CLI::App& app);
Action add_sheets_command(CLI::App& app);
Action add_mesh_command(CLI::App& app);
Action add_check_command(CLI::App& app);
Action add_bench_command(CLI::App& app);
Action add_generate_command(CLI::App& app);
Action add_quality_command(CLI::App& app);
Action add_view_command(CLI::App& app);

}  // namespace stcweave::cli
