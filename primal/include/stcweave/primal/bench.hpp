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
///     generate:box:8x8x8
///
/// Blank lines are ignored; relative paths are relative to the manifest's folder; paths
/// cannot contain whitespace or `#`. An input written `generate:SPEC` (SPEC as
/// `parse_shape_spec` reads it: `box:AxBxC`, `bar:SHAPE`) is a generated shape: the runner
/// writes its surface and its natural hex mesh into its output folder, and that hex mesh is
/// the reference unless the line names another.

#include <array>
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
#include "stcweave/primal/generate.hpp"
#include "stcweave/primal/quality.hpp"

namespace stcweave::primal {

/// The prefix of a generated input in a manifest (`generate:box:8x8x8`).
inline constexpr std::string_view kGeneratePrefix = "generate:";

/// One input of a manifest.
struct ManifestEntry {
  /// Manifest folder / path as written; empty for a generated input.
  std::filesystem::path input;
  /// The shape of a `generate:` input (then `input` is empty until the runner writes it).
  std::optional<ShapeSpec> generated;
  std::optional<std::filesystem::path> reference;  ///< same, for the reference hex mesh
  /// Display name: the input path as written, without the leading folders shared by every
  /// file input of the manifest (`real/mfem/fichera.mesh`); for a generated input its spec
  /// (`box:8x8x8`). Unique within the manifest.
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
/// \throw InvalidInput naming `manifest:line` for a line with more than two fields, a bad
///        `generate:` spec or an input listed twice, and when the manifest lists no input.
[[nodiscard]] Manifest parse_manifest(std::istream& in, const std::filesystem::path& manifest_path);

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

/// A child's one-line error message made into a row's reason: the category prefix the
/// program adds ("invalid input: ", "failure: ") dropped, since the row's status says it,
/// and every occurrence of `input_path` replaced by `name` (the row's input).
[[nodiscard]] std::string tidy_reason(std::string message, const std::string& input_path,
                                      const std::string& name);

/// Copies into `row` the figures of a `stcweave mesh --report` JSON object: hexes, valid,
/// quality (inverted, min / mean scaled Jacobian), seconds per stage (canonical stage
/// order, `total` last). Missing keys leave the fields untouched.
void apply_report(const nlohmann::json& report, BenchRow& row);

/// Copies into `row` the quads, genus, loops and self-intersecting loops of a diagnosis.
void apply_diagnosis(const SurfaceDiagnosis& diagnosis, BenchRow& row);

/// Copies into `row` the hexes and min / mean scaled Jacobian of a reference's quality.
void apply_reference(const QualitySummary& quality, BenchRow& row);

/// The figures the runner measures before meshing (the diagnosis of the input and the
/// quality of the reference) as a JSON object: quads, genus, loops,
/// self_intersecting_loops, reference_hexes, reference_min_scaled_jacobian,
/// reference_mean_scaled_jacobian, reference_error (nulls where absent). The runner's
/// probe process writes it; `apply_probe` reads it back.
[[nodiscard]] nlohmann::json probe_to_json(const BenchRow& row);

/// Copies into `row` the figures of a `probe_to_json` object. Missing or mistyped keys
/// leave the fields untouched.
void apply_probe(const nlohmann::json& probe, BenchRow& row);

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

/// The scaling of the seconds of `stage` ("weave", "total", ...) against hexes over the rows
/// of rule set `rules` that ended Ok with at least `kMinScalingHexes` hexes and seconds > 0;
/// null when there are fewer than `kMinScalingRows` such rows or they all have the same
/// number of hexes.
[[nodiscard]] std::optional<PowerLawFit> fit_stage_scaling(const std::vector<BenchRow>& rows,
                                                           std::string_view rules,
                                                           std::string_view stage);

/// Successful rows needed before `fit_stage_scaling` reports an exponent.
inline constexpr std::size_t kMinScalingRows = 3;

/// Smaller runs are left out of the fit: their stage times (well under a millisecond) are
/// fixed costs and timer noise, not the asymptotic behaviour the exponent is about.
inline constexpr std::size_t kMinScalingHexes = 1000;

/// The stages whose seconds `fit_scaling` fits against hexes.
inline constexpr std::array<std::string_view, 2> kScalingStages = {"weave", "total"};

/// One fitted exponent: seconds of `stage` ~ coefficient x hexes^exponent for `rules`.
struct ScalingFit {
  std::string rules;
  std::string stage;
  PowerLawFit fit;
};

/// Everything a benchmark run reports.
struct BenchResults {
  std::string manifest;  ///< the manifest as named on the command line
  std::vector<std::string> rules;
  std::vector<BenchRow> rows;  ///< manifest order, then rules order
  /// Per rule set (in `rules` order) and stage (`kScalingStages` order), the fitted scaling
  /// when there is one.
  std::vector<ScalingFit> scaling;
  double wall_seconds = 0.0;  ///< of the whole run
  std::size_t jobs = 1;
  /// Threads each run was given (`mesh --threads`; 0: not said).
  std::size_t threads = 0;
};

/// Fills `results.scaling` from its rows (one fit per rule set and stage that has one).
void fit_scaling(BenchResults& results);

/// One CSV line per row after a header line (RFC 4180 quoting, `\n` line ends). Columns:
/// input, rules, status, reason, quads, genus, loops, self_intersecting_loops, hexes, valid,
/// inverted, min/mean scaled Jacobian, `seconds_<stage>` for every stage any row has
/// (canonical order), wall_seconds, peak_memory_mb, reference hexes and min / mean scaled
/// Jacobian, reference_error. Null figures are empty cells.
[[nodiscard]] std::string format_csv(const std::vector<BenchRow>& rows);

/// A Markdown page: a title; a summary per rule set (runs, ok, valid, runs with inverted
/// hexes, failures by kind); with several rule sets, a side-by-side table (one line per
/// input; result, hexes, inverted and min / mean SJ per rule set; the reference's figures);
/// the table of every run (`format_markdown_table`); the seconds of every stage per run;
/// and the scaling section (per rule set and stage, the fitted exponent, and the points).
/// Reasons are shortened to `kMarkdownReasonLength` characters and `|` is escaped.
[[nodiscard]] std::string format_markdown(const BenchResults& results);

/// The longest reason shown in a Markdown cell (the CSV and JSON have it whole).
inline constexpr std::size_t kMarkdownReasonLength = 90;

/// The table of every run (input, rules, quads, genus, loops, result, hexes, inverted,
/// min / mean SJ, weave and total seconds, peak MB, reference hexes and min / mean SJ):
/// header, separator, one line per row.
[[nodiscard]] std::string format_markdown_table(const std::vector<BenchRow>& rows);

/// The results as JSON: manifest, rules, jobs, wall_seconds, rows (every field of
/// `BenchRow`, nulls where absent, `seconds` as an object) and scaling (per rule set, per
/// stage of `kScalingStages`: exponent, coefficient, r_squared, points, or null when there
/// is no fit).
[[nodiscard]] nlohmann::json to_json(const BenchResults& results);

}  // namespace stcweave::primal
