#include "stcweave/primal/bench.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <istream>
#include <map>
#include <set>
#include <sstream>

#include "stcweave/stc/errors.hpp"

namespace stcweave::primal {
namespace {

namespace fs = std::filesystem;

std::string trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t\r\n");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t\r\n");
  return std::string(s.substr(first, last - first + 1));
}

std::vector<std::string> fields_of(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> fields;
  std::string f;
  while (in >> f) fields.push_back(f);
  return fields;
}

std::string safe_stem(std::string_view name) {
  std::string out(name);
  for (char& c : out) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '.' || c == '-' || c == '_';
    if (!ok) c = '_';
  }
  return out;
}

/// Stages in the order the pipeline runs them; `total` always last, others alphabetically
/// between.
int stage_rank(const std::string& stage) {
  static constexpr std::array<std::string_view, 11> kOrder = {
      "diagnose", "orient",  "weave", "validate", "recover",       "pillow",
      "position", "quality", "stc",   "write",    "other_interior"};
  for (std::size_t i = 0; i < kOrder.size(); ++i)
    if (stage == kOrder[i]) return static_cast<int>(i);
  return stage == "total" ? 1000 : 500;
}

bool stage_less(const std::string& a, const std::string& b) {
  const int ra = stage_rank(a), rb = stage_rank(b);
  return ra != rb ? ra < rb : a < b;
}

std::string number(double v, const char* format) {
  std::array<char, 64> buf{};
  std::snprintf(buf.data(), buf.size(), format, v);
  return buf.data();
}

template <class T>
std::string cell(const std::optional<T>& v) {
  if (!v) return {};
  if constexpr (std::is_same_v<T, bool>)
    return *v ? "true" : "false";
  else if constexpr (std::is_floating_point_v<T>)
    return number(*v, "%.6g");
  else
    return std::to_string(*v);
}

template <class T>
std::string md(const std::optional<T>& v, const char* format = "%.3f") {
  if (!v) return "–";
  if constexpr (std::is_floating_point_v<T>)
    return number(*v, format);
  else
    return std::to_string(*v);
}

std::string csv_quote(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

std::string md_escape(std::string_view s) {
  std::string out;
  for (char c : s) {
    if (c == '|')
      out += "\\|";
    else if (c == '\n' || c == '\r')
      out += ' ';
    else
      out += c;
  }
  return out;
}

/// Shortens `s` to at most `n` bytes (not in the middle of a UTF-8 sequence), with "...".
std::string shorten(const std::string& s, std::size_t n) {
  if (s.size() <= n) return s;
  std::size_t cut = n - 3;
  while (cut > 0 && (static_cast<unsigned char>(s[cut]) & 0xC0) == 0x80) --cut;
  return s.substr(0, cut) + "...";
}

std::vector<std::string> stage_columns(const std::vector<BenchRow>& rows) {
  std::set<std::string> seen;
  for (const BenchRow& r : rows)
    for (const auto& [stage, s] : r.seconds) seen.insert(stage);
  std::vector<std::string> stages(seen.begin(), seen.end());
  std::sort(stages.begin(), stages.end(), stage_less);
  return stages;
}

/// The status of a run, with its reason (shortened) when it did not end Ok.
std::string result_cell(const BenchRow& r) {
  std::string result(to_string(r.status));
  if (r.status != RunStatus::Ok && !r.reason.empty())
    result += ": " + shorten(r.reason, kMarkdownReasonLength);
  return result;
}

template <class T>
nlohmann::json or_null(const std::optional<T>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

}  // namespace

Manifest parse_manifest(std::istream& in, const fs::path& manifest_path) {
  Manifest m;
  m.path = manifest_path;
  const fs::path folder = manifest_path.parent_path();
  const std::string where = manifest_path.string();
  std::vector<std::string> written;  // input paths as written, per entry
  std::map<std::string, std::size_t> line_of;
  std::string raw;
  std::size_t line = 0;
  while (std::getline(in, raw)) {
    ++line;
    const auto hash = raw.find('#');
    const std::vector<std::string> fields =
        fields_of(hash == std::string::npos ? raw : raw.substr(0, hash));
    if (fields.empty()) continue;
    if (fields.size() > 2) {
      throw InvalidInput(where + ":" + std::to_string(line) +
                         ": expected INPUT [REFERENCE], found " + std::to_string(fields.size()) +
                         " fields; paths cannot contain spaces, and a comment starts with #");
    }
    const std::string at = where + ":" + std::to_string(line) + ": ";
    ManifestEntry e;
    e.line = line;
    std::string key;  // what identifies the input, to find duplicates
    if (fields[0].rfind(kGeneratePrefix, 0) == 0) {
      try {
        e.generated = parse_shape_spec(std::string_view(fields[0]).substr(kGeneratePrefix.size()));
      } catch (const InvalidInput& ex) {
        throw InvalidInput(at + ex.what());
      }
      key = std::string(kGeneratePrefix) + to_string(*e.generated);
    } else {
      const fs::path input = fs::path(fields[0]).lexically_normal();
      e.input = input.is_absolute() ? input : (folder / input).lexically_normal();
      key = input.generic_string();
    }
    const auto [it, fresh] = line_of.emplace(key, line);
    if (!fresh) {
      throw InvalidInput(at + "input " + fields[0] + " is already listed on line " +
                         std::to_string(it->second) +
                         "; list each input once (--rules runs it with several rule sets)");
    }
    if (fields.size() == 2) {
      const fs::path ref(fields[1]);
      if (fields[1].rfind(kGeneratePrefix, 0) == 0)
        throw InvalidInput(at + "a reference must be a hex mesh file, not " + fields[1]);
      e.reference = ref.is_absolute() ? ref : (folder / ref).lexically_normal();
    }
    written.push_back(e.generated ? std::string() : key);
    m.entries.push_back(std::move(e));
  }
  if (in.bad()) throw IoError("cannot read the manifest " + where);
  if (m.entries.empty())
    throw InvalidInput(where + ": the manifest lists no input; write one input file per line");

  // Display names: drop the leading folders every file input shares (keep at least the
  // file name); a generated input is named by its spec.
  std::vector<std::vector<std::string>> parts;
  std::optional<std::size_t> first;  // the first file input
  for (const std::string& w : written) {
    std::vector<std::string> p;
    if (!w.empty())
      for (const auto& c : fs::path(w)) p.push_back(c.string());
    if (!w.empty() && !first) first = parts.size();
    parts.push_back(std::move(p));
  }
  std::size_t common = 0;
  if (first) {
    const std::vector<std::string> front = parts[*first];
    common = front.size() - 1;
    for (const auto& p : parts) {
      if (p.empty()) continue;
      std::size_t k = 0;
      while (k < common && k + 1 < p.size() && p[k] == front[k]) ++k;
      common = k;
    }
  }
  std::set<std::string> stems;
  for (std::size_t i = 0; i < m.entries.size(); ++i) {
    ManifestEntry& e = m.entries[i];
    std::string name;
    if (e.generated) {
      name = to_string(*e.generated);
    } else {
      for (std::size_t k = common; k < parts[i].size(); ++k) {
        if (!name.empty() && name.back() != '/') name += '/';
        name += parts[i][k];
      }
    }
    e.name = name;
    e.file_stem = safe_stem(name);
    if (!stems.insert(e.file_stem).second) {
      e.file_stem += "-line" + std::to_string(e.line);
      stems.insert(e.file_stem);
    }
  }
  return m;
}

Manifest read_manifest(const fs::path& path) {
  std::ifstream in(path);
  if (!in)
    throw IoError("cannot open the manifest " + path.string() +
                  ": check the path (one input per line, # for comments)");
  return parse_manifest(in, path);
}

std::vector<std::string> parse_rules_list(std::string_view list) {
  std::vector<std::string> names;
  std::size_t start = 0;
  while (true) {
    const auto comma = list.find(',', start);
    const std::string name = trim(list.substr(
        start, comma == std::string_view::npos ? std::string_view::npos : comma - start));
    if (name.empty()) {
      throw InvalidInput("--rules '" + std::string(list) +
                         "': empty rule-set name; give names separated by commas, e.g. "
                         "reliable,extended");
    }
    if (std::find(names.begin(), names.end(), name) != names.end())
      throw InvalidInput("--rules '" + std::string(list) + "': " + name + " is given twice");
    names.push_back(name);
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return names;
}

std::string_view to_string(RunStatus status) {
  switch (status) {
    case RunStatus::Ok:
      return "ok";
    case RunStatus::Rejected:
      return "rejected";
    case RunStatus::Failed:
      return "failed";
    case RunStatus::Crashed:
      return "crashed";
    case RunStatus::Timeout:
      return "timeout";
    case RunStatus::OutOfMemory:
      return "out of memory";
  }
  return "failed";
}

std::optional<double> BenchRow::stage_seconds(std::string_view stage) const {
  for (const auto& [name, s] : seconds)
    if (name == stage) return s;
  return std::nullopt;
}

std::string tidy_reason(std::string message, const std::string& input_path,
                        const std::string& name) {
  for (const std::string_view prefix : {"invalid input: ", "failure: "}) {
    if (message.rfind(prefix, 0) == 0) {
      message.erase(0, prefix.size());
      break;
    }
  }
  // Only whole occurrences: bounded by the message's ends, spaces, quotes, brackets or
  // punctuation, so that a short path is not replaced inside a word.
  const auto is_boundary = [](char c) {
    return std::string_view(" \t'\"()[],;:").find(c) != std::string_view::npos;
  };
  if (!input_path.empty() && input_path != name) {
    std::size_t at = message.find(input_path);
    while (at != std::string::npos) {
      const std::size_t end = at + input_path.size();
      if ((at == 0 || is_boundary(message[at - 1])) &&
          (end == message.size() || is_boundary(message[end]))) {
        message.replace(at, input_path.size(), name);
        at = message.find(input_path, at + name.size());
      } else {
        at = message.find(input_path, at + 1);
      }
    }
  }
  return message;
}

void apply_report(const nlohmann::json& report, BenchRow& row) {
  if (!report.is_object()) return;
  if (report.contains("hexes") && report["hexes"].is_number_unsigned())
    row.hexes = report["hexes"].get<std::size_t>();
  if (report.contains("valid") && report["valid"].is_boolean())
    row.valid = report["valid"].get<bool>();
  if (report.contains("quality") && report["quality"].is_object()) {
    const auto& q = report["quality"];
    if (q.contains("inverted") && q["inverted"].is_number_unsigned())
      row.inverted = q["inverted"].get<std::size_t>();
    if (q.contains("min_scaled_jacobian") && q["min_scaled_jacobian"].is_number())
      row.min_scaled_jacobian = q["min_scaled_jacobian"].get<double>();
    if (q.contains("mean_scaled_jacobian") && q["mean_scaled_jacobian"].is_number())
      row.mean_scaled_jacobian = q["mean_scaled_jacobian"].get<double>();
  }
  if (report.contains("seconds") && report["seconds"].is_object()) {
    row.seconds.clear();
    for (const auto& [stage, s] : report["seconds"].items())
      if (s.is_number()) row.seconds.emplace_back(stage, s.get<double>());
    std::sort(row.seconds.begin(), row.seconds.end(),
              [](const auto& a, const auto& b) { return stage_less(a.first, b.first); });
  }
}

void apply_diagnosis(const SurfaceDiagnosis& diagnosis, BenchRow& row) {
  row.quads = diagnosis.quads;
  row.genus = diagnosis.genus;
  row.loops = diagnosis.loops;
  row.self_intersecting_loops = diagnosis.self_intersecting_loops;
}

void apply_reference(const QualitySummary& quality, BenchRow& row) {
  row.reference_hexes = quality.hexes;
  row.reference_min_scaled_jacobian = quality.min_scaled_jacobian;
  row.reference_mean_scaled_jacobian = quality.mean_scaled_jacobian;
}

nlohmann::json probe_to_json(const BenchRow& row) {
  nlohmann::json j;
  j["quads"] = or_null(row.quads);
  j["genus"] = or_null(row.genus);
  j["loops"] = or_null(row.loops);
  j["self_intersecting_loops"] = or_null(row.self_intersecting_loops);
  j["reference_hexes"] = or_null(row.reference_hexes);
  j["reference_min_scaled_jacobian"] = or_null(row.reference_min_scaled_jacobian);
  j["reference_mean_scaled_jacobian"] = or_null(row.reference_mean_scaled_jacobian);
  j["reference_error"] =
      row.reference_error.empty() ? nlohmann::json(nullptr) : nlohmann::json(row.reference_error);
  return j;
}

void apply_probe(const nlohmann::json& probe, BenchRow& row) {
  if (!probe.is_object()) return;
  const auto count = [&](const char* key, std::optional<std::size_t>& field) {
    if (probe.contains(key) && probe[key].is_number_unsigned())
      field = probe[key].get<std::size_t>();
  };
  const auto real = [&](const char* key, std::optional<double>& field) {
    if (probe.contains(key) && probe[key].is_number()) field = probe[key].get<double>();
  };
  count("quads", row.quads);
  if (probe.contains("genus") && probe["genus"].is_number_integer())
    row.genus = probe["genus"].get<int>();
  count("loops", row.loops);
  count("self_intersecting_loops", row.self_intersecting_loops);
  count("reference_hexes", row.reference_hexes);
  real("reference_min_scaled_jacobian", row.reference_min_scaled_jacobian);
  real("reference_mean_scaled_jacobian", row.reference_mean_scaled_jacobian);
  if (probe.contains("reference_error") && probe["reference_error"].is_string())
    row.reference_error = probe["reference_error"].get<std::string>();
}

PowerLawFit fit_power_law(const std::vector<double>& x, const std::vector<double>& y) {
  if (x.size() != y.size())
    throw InvalidInput("fit_power_law: " + std::to_string(x.size()) + " x values but " +
                       std::to_string(y.size()) + " y values");
  if (x.size() < 2) throw InvalidInput("fit_power_law: at least two points are needed");
  const std::size_t n = x.size();
  std::vector<double> lx(n), ly(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (!(x[i] > 0.0) || !(y[i] > 0.0) || !std::isfinite(x[i]) || !std::isfinite(y[i]))
      throw InvalidInput("fit_power_law: point " + std::to_string(i) +
                         " is not positive and finite; a log-log fit needs x > 0 and y > 0");
    lx[i] = std::log(x[i]);
    ly[i] = std::log(y[i]);
  }
  double mx = 0.0, my = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    mx += lx[i];
    my += ly[i];
  }
  mx /= static_cast<double>(n);
  my /= static_cast<double>(n);
  double sxx = 0.0, sxy = 0.0, syy = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    sxx += (lx[i] - mx) * (lx[i] - mx);
    sxy += (lx[i] - mx) * (ly[i] - my);
    syy += (ly[i] - my) * (ly[i] - my);
  }
  if (sxx <= 0.0) throw InvalidInput("fit_power_law: every x is the same; nothing to fit");
  PowerLawFit fit;
  fit.points = n;
  fit.exponent = sxy / sxx;
  fit.coefficient = std::exp(my - fit.exponent * mx);
  double residual = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double r = ly[i] - (my + fit.exponent * (lx[i] - mx));
    residual += r * r;
  }
  fit.r_squared = syy > 0.0 ? 1.0 - residual / syy : 1.0;
  return fit;
}

std::optional<PowerLawFit> fit_stage_scaling(const std::vector<BenchRow>& rows,
                                             std::string_view rules, std::string_view stage) {
  std::vector<double> x, y;
  for (const BenchRow& r : rows) {
    if (r.rules != rules || r.status != RunStatus::Ok || !r.hexes || *r.hexes < kMinScalingHexes)
      continue;
    const auto seconds = r.stage_seconds(stage);
    if (!seconds || !(*seconds > 0.0) || !std::isfinite(*seconds)) continue;
    x.push_back(static_cast<double>(*r.hexes));
    y.push_back(*seconds);
  }
  if (x.size() < kMinScalingRows) return std::nullopt;
  if (std::all_of(x.begin(), x.end(), [&](double v) { return v == x.front(); }))
    return std::nullopt;
  return fit_power_law(x, y);
}

void fit_scaling(BenchResults& results) {
  results.scaling.clear();
  for (const std::string& rules : results.rules) {
    for (const std::string_view stage : kScalingStages)
      if (const auto fit = fit_stage_scaling(results.rows, rules, stage))
        results.scaling.push_back({rules, std::string(stage), *fit});
  }
}

std::string format_csv(const std::vector<BenchRow>& rows) {
  const std::vector<std::string> stages = stage_columns(rows);
  std::ostringstream out;
  out << "input,rules,status,reason,quads,genus,loops,self_intersecting_loops,hexes,valid,"
         "inverted,min_scaled_jacobian,mean_scaled_jacobian";
  for (const std::string& s : stages) out << ",seconds_" << s;
  out << ",wall_seconds,peak_memory_mb,reference_hexes,reference_min_scaled_jacobian,"
         "reference_mean_scaled_jacobian,reference_error\n";
  for (const BenchRow& r : rows) {
    out << csv_quote(r.input) << ',' << csv_quote(r.rules) << ',' << to_string(r.status) << ','
        << csv_quote(r.reason) << ',' << cell(r.quads) << ',' << cell(r.genus) << ','
        << cell(r.loops) << ',' << cell(r.self_intersecting_loops) << ',' << cell(r.hexes) << ','
        << cell(r.valid) << ',' << cell(r.inverted) << ',' << cell(r.min_scaled_jacobian) << ','
        << cell(r.mean_scaled_jacobian);
    for (const std::string& s : stages) out << ',' << cell(r.stage_seconds(s));
    out << ',' << number(r.wall_seconds, "%.6g") << ',' << cell(r.peak_memory_mb) << ','
        << cell(r.reference_hexes) << ',' << cell(r.reference_min_scaled_jacobian) << ','
        << cell(r.reference_mean_scaled_jacobian) << ',' << csv_quote(r.reference_error) << '\n';
  }
  return out.str();
}

std::string format_markdown_table(const std::vector<BenchRow>& rows) {
  std::ostringstream out;
  out << "| input | rules | quads | genus | loops | result | hexes | inverted | min SJ | mean SJ "
         "| weave s | total s | peak MB | ref hexes | ref min SJ | ref mean SJ |\n";
  out << "|---|---|--:|--:|--:|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n";
  for (const BenchRow& r : rows) {
    out << "| " << md_escape(r.input) << " | " << md_escape(r.rules) << " | " << md(r.quads)
        << " | " << md(r.genus) << " | " << md(r.loops) << " | " << md_escape(result_cell(r))
        << " | " << md(r.hexes) << " | " << md(r.inverted) << " | " << md(r.min_scaled_jacobian)
        << " | " << md(r.mean_scaled_jacobian) << " | " << md(r.stage_seconds("weave"), "%.3g")
        << " | " << md(r.stage_seconds("total"), "%.3g") << " | " << md(r.peak_memory_mb, "%.0f")
        << " | " << md(r.reference_hexes) << " | " << md(r.reference_min_scaled_jacobian) << " | "
        << md(r.reference_mean_scaled_jacobian) << " |\n";
  }
  return out.str();
}

std::string format_markdown(const BenchResults& results) {
  std::ostringstream out;
  out << "# stcweave bench: " << md_escape(results.manifest) << "\n\n";
  out << results.rows.size() << " runs (" << results.jobs << (results.jobs == 1 ? " job" : " jobs")
      << " at a time, ";
  if (results.threads > 0)
    out << results.threads << (results.threads == 1 ? " thread" : " threads") << " each, ";
  out << number(results.wall_seconds, "%.1f") << " s wall time).\n\n";

  // Summary per rule set.
  const std::array<RunStatus, 5> failures = {RunStatus::Rejected, RunStatus::Failed,
                                             RunStatus::Crashed, RunStatus::Timeout,
                                             RunStatus::OutOfMemory};
  out << "| rules | runs | ok | valid | no inverted hex | with inverted hexes";
  for (RunStatus s : failures) out << " | " << to_string(s);
  out << " |\n|---|--:|--:|--:|--:|--:";
  for (std::size_t i = 0; i < failures.size(); ++i) out << "|--:";
  out << "|\n";
  for (const std::string& rules : results.rules) {
    std::size_t runs = 0, ok = 0, valid = 0, clean = 0, inverted = 0;
    std::map<RunStatus, std::size_t> by_status;
    for (const BenchRow& r : results.rows) {
      if (r.rules != rules) continue;
      ++runs;
      ++by_status[r.status];
      if (r.status != RunStatus::Ok) continue;
      ++ok;
      valid += r.valid.value_or(false) ? 1 : 0;
      if (r.inverted) (*r.inverted == 0 ? clean : inverted) += 1;
    }
    out << "| " << md_escape(rules) << " | " << runs << " | " << ok << " | " << valid << " | "
        << clean << " | " << inverted;
    for (RunStatus s : failures) out << " | " << by_status[s];
    out << " |\n";
  }
  out << "\n";

  if (results.rules.size() > 1) {
    out << "## Side by side\n\n| input | quads | genus | loops";
    for (const std::string& rules : results.rules) {
      const std::string r = md_escape(rules);
      out << " | " << r << " | " << r << " hexes | " << r << " inverted | " << r << " min SJ | "
          << r << " mean SJ";
    }
    out << " | ref hexes | ref min SJ | ref mean SJ |\n|---|--:|--:|--:";
    for (std::size_t i = 0; i < results.rules.size(); ++i) out << "|---|--:|--:|--:|--:";
    out << "|--:|--:|--:|\n";
    // Rows are grouped by input (manifest order), rule sets in `rules` order within a group.
    std::vector<std::string> inputs;
    for (const BenchRow& r : results.rows)
      if (std::find(inputs.begin(), inputs.end(), r.input) == inputs.end())
        inputs.push_back(r.input);
    for (const std::string& input : inputs) {
      const BenchRow* any = nullptr;
      for (const BenchRow& r : results.rows)
        if (r.input == input) any = any != nullptr ? any : &r;
      out << "| " << md_escape(input) << " | " << md(any->quads) << " | " << md(any->genus) << " | "
          << md(any->loops);
      for (const std::string& rules : results.rules) {
        const auto it = std::find_if(results.rows.begin(), results.rows.end(), [&](const auto& r) {
          return r.input == input && r.rules == rules;
        });
        if (it == results.rows.end()) {
          out << " | – | – | – | – | –";
          continue;
        }
        out << " | " << md_escape(result_cell(*it)) << " | " << md(it->hexes) << " | "
            << md(it->inverted) << " | " << md(it->min_scaled_jacobian) << " | "
            << md(it->mean_scaled_jacobian);
      }
      out << " | " << md(any->reference_hexes) << " | " << md(any->reference_min_scaled_jacobian)
          << " | " << md(any->reference_mean_scaled_jacobian) << " |\n";
    }
    out << "\n";
  }

  out << "## Every run\n\n" << format_markdown_table(results.rows) << "\n";
  out << "SJ: Verdict scaled Jacobian (inverted: SJ <= 0); seconds are the pipeline's own stage "
         "timings; peak MB is the child process's maximum resident set size; ref: the reference "
         "hex mesh given in the manifest.\n\n";

  const std::vector<std::string> stages = stage_columns(results.rows);
  if (!stages.empty()) {
    out << "## Seconds per stage\n\n| input | rules";
    for (const std::string& s : stages) out << " | " << md_escape(s);
    out << " | wall |\n|---|---";
    for (std::size_t i = 0; i <= stages.size(); ++i) out << "|--:";
    out << "|\n";
    for (const BenchRow& r : results.rows) {
      out << "| " << md_escape(r.input) << " | " << md_escape(r.rules);
      for (const std::string& s : stages) out << " | " << md(r.stage_seconds(s), "%.3g");
      out << " | " << number(r.wall_seconds, "%.3g") << " |\n";
    }
    out << "\n";
  }

  out << "## Scaling\n\n";
  out << "Least-squares fit of log(seconds) = log(c) + e log(hexes) over the successful runs of "
         "each rule set with at least "
      << kMinScalingHexes << " hexes (smaller runs time fixed costs).\n\n";
  for (const std::string& rules : results.rules) {
    for (const std::string_view stage : kScalingStages) {
      const auto it =
          std::find_if(results.scaling.begin(), results.scaling.end(),
                       [&](const auto& f) { return f.rules == rules && f.stage == stage; });
      out << "- " << md_escape(rules) << ", " << stage << " seconds: ";
      if (it == results.scaling.end()) {
        out << "no exponent (fewer than " << kMinScalingRows
            << " successful runs with distinct hex counts)\n";
      } else {
        const PowerLawFit& f = it->fit;
        out << "~ " << number(f.coefficient, "%.3g") << " x hexes^" << number(f.exponent, "%.2f")
            << " (" << f.points << " runs, R^2 = " << number(f.r_squared, "%.3f") << ")\n";
      }
    }
    std::vector<const BenchRow*> points;
    for (const BenchRow& r : results.rows)
      if (r.rules == rules && r.status == RunStatus::Ok && r.hexes && *r.hexes >= kMinScalingHexes)
        points.push_back(&r);
    if (points.size() < kMinScalingRows) continue;
    std::stable_sort(points.begin(), points.end(),
                     [](const BenchRow* a, const BenchRow* b) { return *a->hexes < *b->hexes; });
    out << "\n| " << md_escape(rules)
        << ": input | hexes | weave s | total s |\n|---|--:|--:|--:|\n";
    for (const BenchRow* r : points) {
      out << "| " << md_escape(r->input) << " | " << *r->hexes << " | "
          << md(r->stage_seconds("weave"), "%.3g") << " | " << md(r->stage_seconds("total"), "%.3g")
          << " |\n";
    }
    out << "\n";
  }
  return out.str();
}

nlohmann::json to_json(const BenchResults& results) {
  nlohmann::json j;
  j["manifest"] = results.manifest;
  j["rules"] = results.rules;
  j["jobs"] = results.jobs;
  j["threads"] = results.threads;
  j["wall_seconds"] = results.wall_seconds;
  nlohmann::json rows = nlohmann::json::array();
  for (const BenchRow& r : results.rows) {
    // The probe's figures (input and reference), then the run's; keys are sorted on output.
    nlohmann::json row = probe_to_json(r);
    row["input"] = r.input;
    row["rules"] = r.rules;
    row["status"] = std::string(to_string(r.status));
    row["reason"] = r.reason.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.reason);
    row["hexes"] = or_null(r.hexes);
    row["valid"] = or_null(r.valid);
    row["inverted"] = or_null(r.inverted);
    row["min_scaled_jacobian"] = or_null(r.min_scaled_jacobian);
    row["mean_scaled_jacobian"] = or_null(r.mean_scaled_jacobian);
    nlohmann::json seconds = nlohmann::json::object();
    for (const auto& [stage, s] : r.seconds) seconds[stage] = s;
    row["seconds"] = seconds;
    row["wall_seconds"] = r.wall_seconds;
    row["peak_memory_mb"] = or_null(r.peak_memory_mb);
    rows.push_back(std::move(row));
  }
  j["rows"] = rows;
  nlohmann::json scaling = nlohmann::json::object();
  for (const std::string& rules : results.rules)
    for (const std::string_view stage : kScalingStages)
      scaling[rules][std::string(stage)] = nullptr;
  for (const ScalingFit& s : results.scaling) {
    scaling[s.rules][s.stage] = {{"x", "hexes"},
                                 {"y", s.stage + " seconds"},
                                 {"exponent", s.fit.exponent},
                                 {"coefficient", s.fit.coefficient},
                                 {"r_squared", s.fit.r_squared},
                                 {"points", s.fit.points}};
  }
  j["scaling"] = scaling;
  return j;
}

}  // namespace stcweave::primal
