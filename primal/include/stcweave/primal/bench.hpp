#pragma once
/// \file
/// The pure half of the corpus runner (`stcweave bench`): benchmark manifests, result rows,
/// their CSV / Markdown / JSON forms and the fitted scaling exponent. Running the pipeline
/// in child processes (time and memory limits) is the CLI's business; everything here is
/// deterministic and testable without a process.
///
/// A manifest is a text file, one input per line, optionally followed by whitespace and a
/// reference hex mesh:
///
///     # comment (a `#` starts a comment anywhere on a line)
///     ../../shared/data/real/mfem/fichera.mesh   ../../shared/data/real/mfem/fichera.mesh
///     ../../shared/data/gmsh/torus_tf_coarse.obj
///
/// Blank lines are ignored; relative paths are relative to the manifest's folder; paths
/// cannot contain whitespace or `#`.

#include <cstddef>
#include <filesystem>
#include <iosfwd>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "stcweave/primal/diagnose.hpp"
#include "stcweave/primal/quality.hpp"

namespace stcweave::primal {

/// One input of a manifest.
struct ManifestEntry {
  std::filesystem::path input;                     ///< manifest folder / path as written
  std::optional<std::filesystem::path> reference;  ///< same, for the reference hex mesh
  /// Display name: the input path as written, without the leading folders shared by every
  /// input of the manifest (`real/mfem/fichera.mesh`). Unique within the manifest.
  std::string name;
  /// `name` with every character other than letters, digits, `.`, `-` and `_` replaced by
  /// `_`: the stem of the files the runner writes for this input. Unique within the
  /// manifest.
  std::string file_stem;
  std::size_t line = 0;  ///< 1-based line in the manifest
};

struct Manifest {
  std::filesystem::path path;
  std::vector<ManifestEntry> entries;  ///< in manifest order
};

/// Parses a manifest; `manifest_path` names it in messages and its folder anchors relative
/// paths. Does not check that the files exist (a missing file is a failed row, not a bad
/// manifest).
/// \throw InvalidInput naming `manifest:line` for a line with more than two fields or an
///        input listed twice, and when the manifest lists no input.
[[nodiscard]] Manifest parse_manifest(std::istream& in,
                                      const std::filesystem::path& manifest_path);

/// Reads and parses the manifest file `path`.
/// \throw IoError when it cannot be read; InvalidInput as `parse_manifest`.
[[nodiscard]] Manifest read_manifest(const std::filesystem::path& path);

/// Splits a comma-separated list of rule-set names (`"reliable,extended"`), spaces
/// trimmed, order kept. Does not check the names (see `weave::rule_set_from_name`).
/// \throw InvalidInput for an empty list, an empty name or a name given twice.
[[nodiscard]] std::vector<std::string> parse_rules_list(std::string_view list);

/// How a run ended.
enum class RunStatus {
  Ok,           ///< exit 0: a valid hex mesh was written
  Rejected,     ///< exit 2: the input was refused (unreadable, defect, unsupported)
  Failed,       ///< another exit code (weave blocked, invalid complex, internal error)
  Crashed,      ///< killed by a signal
  Timeout,      ///< killed after the wall-time limit
  OutOfMemory,  ///< hit the memory limit
};

/// `"ok"`, `"rejected"`, `"failed"`, `"crashed"`, `"timeout"`, `"out of memory"`.
[[nodiscard]] std::string_view to_string(RunStatus status);

/// One (input, rule set) run. Optional figures are null when the run or the diagnosis did
/// not produce them.
struct BenchRow {
  std::string input;  ///< `ManifestEntry::name`
  std::string rules;
  RunStatus status = RunStatus::Failed;
  std::string reason;  ///< empty for Ok; the error message, signal, limit otherwise

  // From the in-process diagnosis of the input (`stcweave loops`).
  std::optional<std::size_t> quads;
  std::optional<int> genus;
  std::optional<std::size_t> loops;
  std::optional<std::size_t> self_intersecting_loops;

  // From the child's report (`stcweave mesh --report`).
  std::optional<std::size_t> hexes;
  std::optional<bool> valid;
  std::optional<std::size_t> inverted;
  std::optional<double> min_scaled_jacobian;
  std::optional<double> mean_scaled_jacobian;
  /// Seconds per stage as the report gives them ("weave", "total", ...), report order.
  std::vector<std::pair<std::string, double>> seconds;

  // Measured by the runner.
  double wall_seconds = 0.0;
  std::optional<double> peak_memory_mb;  ///< the child's maximum resident set size

  // From the reference hex mesh, when the manifest gives one.
  std::optional<std::size_t> reference_hexes;
  std::optional<double> reference_min_scaled_jacobian;
  std::optional<double> reference_mean_scaled_jacobian;
  std::string reference_error;  ///< why the reference could not be used (empty if it could)

  /// The seconds of `stage`, or null when the report did not give them.
  [[nodiscard]] std::optional<double> stage_seconds(std::string_view stage) const;
};

/// Copies into `row` the figures of a `stcweave mesh --report` JSON object: hexes, valid,
/// quality (inverted, min / mean scaled Jacobian), seconds per stage (canonical stage
/// order, `total` last). Missing keys leave the fields untouched.
void apply_report(const nlohmann::json& report, BenchRow& row);

/// Copies into `row` the quads, genus, loops and self-intersecting loops of a diagnosis.
void apply_diagnosis(const SurfaceDiagnosis& diagnosis, BenchRow& row);

/// Copies into `row` the hexes and min / mean scaled Jacobian of a reference's quality.
void apply_reference(const QualitySummary& quality, BenchRow& row);

/// The least-squares fit of log y = log c + e log x.
struct PowerLawFit {
  double exponent = 0.0;     ///< e
  double coefficient = 0.0;  ///< c
  double r_squared = 0.0;    ///< of the log-log fit (1 when every point is on the line)
  std::size_t points = 0;
};

/// Fits y = c x^e by least squares on (log x, log y).
/// \throw InvalidInput when the sizes differ, fewer than two points are given, a value is
///        not positive and finite, or every x is the same.
[[nodiscard]] PowerLawFit fit_power_law(const std::vector<double>& x, const std::vector<double>& y);

/// The scaling of weave seconds against hexes over the rows of rule set `rules` that ended
/// Ok with hexes > 0 and weave seconds > 0; null when there are fewer than
/// `kMinScalingRows` such rows or they all have the same number of hexes.
[[nodiscard]] std::optional<PowerLawFit> fit_weave_scaling(const std::vector<BenchRow>& rows,
                                                           std::string_view rules);

/// Successful rows needed before `fit_weave_scaling` reports an exponent.
inline constexpr std::size_t kMinScalingRows = 3;

/// Everything a benchmark run reports.
struct BenchResults {
  std::string manifest;  ///< the manifest as named on the command line
  std::vector<std::string> rules;
  std::vector<BenchRow> rows;  ///< manifest order, then rules order
  /// Per rule set (in `rules` order), the fitted scaling when there is one.
  std::vector<std::pair<std::string, PowerLawFit>> scaling;
  double wall_seconds = 0.0;  ///< of the whole run
  std::size_t jobs = 1;
};

/// Fills `results.scaling` from its rows (one fit per rule set that has one).
void fit_scaling(BenchResults& results);

/// One CSV line per row after a header line (RFC 4180 quoting, `\n` line ends). Columns:
/// input, rules, status, reason, quads, genus, loops, self_intersecting_loops, hexes, valid,
/// inverted, min/mean scaled Jacobian, `seconds_<stage>` for every stage any row has
/// (canonical order), wall_seconds, peak_memory_mb, reference hexes and min / mean scaled
/// Jacobian, reference_error. Null figures are empty cells.
[[nodiscard]] std::string format_csv(const std::vector<BenchRow>& rows);

/// A Markdown page: a title, a count of rows per status, one table (input, rules, quads,
/// genus, loops, result, hexes, inverted, min / mean SJ, weave and total seconds, peak MB,
/// reference hexes and min / mean SJ; reasons shortened to `kMarkdownReasonLength`
/// characters, `|` escaped) and the scaling exponent per rule set.
[[nodiscard]] std::string format_markdown(const BenchResults& results);

/// The longest reason shown in a Markdown cell (the CSV and JSON have it whole).
inline constexpr std::size_t kMarkdownReasonLength = 90;

/// Just the Markdown table of `format_markdown` (header, separator, one line per row).
[[nodiscard]] std::string format_markdown_table(const std::vector<BenchRow>& rows);

/// The results as JSON: manifest, rules, jobs, wall_seconds, rows (every field of
/// `BenchRow`, nulls where absent, `seconds` as an object) and scaling (per rule set:
/// exponent, coefficient, r_squared, points; null when there is no fit).
[[nodiscard]] nlohmann::json to_json(const BenchResults& results);

}  // namespace stcweave::primal
