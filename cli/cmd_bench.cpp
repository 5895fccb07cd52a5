/// `stcweave bench MANIFEST [--jobs N] [--out DIR] [--rules LIST] [--timeout S] [--memory MB]`:
/// the corpus runner. A thin process manager over `primal/bench.hpp`.
///
/// For every input of the manifest it first runs a probe (a forked copy of this process, not
/// exec'd) that diagnoses the input and summarises the quality of its reference, then, for
/// every rule set, `stcweave mesh INPUT -o DIR/meshes/NAME.RULES.vtk --report
/// DIR/reports/NAME.RULES.json -q --rules RULES` in a fresh process (this very binary, via
/// /proc/self/exe). Every child runs in its own process group under a wall-time limit (the
/// group is killed on timeout) and an address-space limit (RLIMIT_AS); the runner measures
/// its wall time and, through wait4, its peak resident memory. Doing the diagnosis and the
/// reference in probes keeps the runner itself small, so its resident size (which Linux
/// counts towards a forked child's peak) stays a few MB, and isolates it from any input.
///
/// Every run is a row, whatever happened to it; rows come in manifest order, then rules
/// order, whatever --jobs is. Exit code 0 whatever the rows say (2 for a bad manifest or an
/// unknown rule set, found before anything runs; 130 when interrupted, after writing the
/// results with the runs not done marked as such).

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "commands.hpp"
#include "stcweave/primal/bench.hpp"
#include "stcweave/primal/diagnose.hpp"
#include "stcweave/primal/generate.hpp"
#include "stcweave/primal/io.hpp"
#include "stcweave/primal/quality.hpp"
#include "stcweave/stc/errors.hpp"
#include "stcweave/weave/weave.hpp"

namespace stcweave::cli {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct BenchArgs {
  std::string manifest;
  std::size_t jobs = 1;
  std::string out = "bench-results";
  std::string rules = "extended";
  double timeout = 180.0;
  int threads = 0;
  std::size_t memory_mb = 4096;
  bool quiet = false;
};

/// One child process to run: the probe of an input, or one (input, rule set) mesh run.
struct Job {
  enum class Kind { Probe, Mesh };
  Kind kind = Kind::Mesh;
  std::size_t entry = 0;
  std::size_t row = 0;  ///< index in the results (Mesh only)
  std::string rules;
  fs::path mesh, report, log;  ///< report: the probe's JSON for a probe
};

/// A child running.
struct Running {
  pid_t pid = -1;
  std::size_t job = 0;
  Clock::time_point start;
  bool timed_out = false;
};

/// Set by SIGINT / SIGTERM: stop starting runs, kill the running ones, write what we have.
volatile std::sig_atomic_t g_interrupted = 0;

extern "C" void on_interrupt(int /*signal*/) {
  g_interrupted = 1;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// The last non-empty line of a child's stderr, without the program's "stcweave: " prefix.
std::string last_message(const fs::path& log) {
  std::istringstream in(slurp(log));
  std::string line, last;
  while (std::getline(in, line))
    if (line.find_first_not_of(" \t\r") != std::string::npos) last = line;
  const std::string prefix = "stcweave: ";
  if (last.rfind(prefix, 0) == 0) last.erase(0, prefix.size());
  while (!last.empty() && (last.back() == '\r' || last.back() == ' ')) last.pop_back();
  return last;
}

bool mentions_out_of_memory(const std::string& text) {
  return text.find("bad_alloc") != std::string::npos ||
         text.find("Cannot allocate memory") != std::string::npos ||
         text.find("out of memory") != std::string::npos ||
         // the dynamic loader could not map a shared library within the address-space limit
         text.find("failed to map segment") != std::string::npos;
}

/// In a freshly forked child: own process group, address-space limit, stdin and stdout to
/// /dev/null, stderr to `log`. Only async-signal-safe calls.
void enter_child(const char* log, std::size_t memory_mb) {
  setpgid(0, 0);
  if (memory_mb > 0) {
    struct rlimit limit;
    limit.rlim_cur = limit.rlim_max = static_cast<rlim_t>(memory_mb) * 1024 * 1024;
    setrlimit(RLIMIT_AS, &limit);
  }
  struct sigaction dfl {};
  dfl.sa_handler = SIG_DFL;
  sigaction(SIGINT, &dfl, nullptr);
  sigaction(SIGTERM, &dfl, nullptr);
  const int null_fd = open("/dev/null", O_RDWR);
  const int log_fd = open(log, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (null_fd >= 0) {
    dup2(null_fd, STDIN_FILENO);
    dup2(null_fd, STDOUT_FILENO);
  }
  if (log_fd >= 0) dup2(log_fd, STDERR_FILENO);
}

/// Forks a child in its own process group, set up by `enter_child` (stderr to `log`, the
/// memory limit), that runs `child`, which must not return. Returns the child's pid, or -1
/// with errno set.
template <typename Child>
pid_t spawn(const fs::path& log, std::size_t memory_mb, const Child& child) {
  const std::string log_path = log.string();
  std::fflush(nullptr);
  const pid_t pid = fork();
  if (pid != 0) {
    if (pid > 0) setpgid(pid, pid);
    return pid;
  }
  enter_child(log_path.c_str(), memory_mb);
  child();
  _exit(127);
}

/// Starts `args` (this program's argv) in a child; returns its pid, or -1 with errno set.
pid_t spawn_exec(const std::vector<std::string>& args, const fs::path& log, std::size_t memory_mb) {
  std::vector<char*> argv;
  argv.reserve(args.size() + 1);
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  return spawn(log, memory_mb, [&argv] {
    execv("/proc/self/exe", argv.data());
    const char msg[] = "stcweave: cannot start /proc/self/exe\n";
    [[maybe_unused]] const ssize_t n = write(STDERR_FILENO, msg, sizeof msg - 1);
  });
}

/// The probe, run in a forked child: the diagnosis of `entry`'s input and the quality of its
/// reference, written to `out` as `primal::probe_to_json`. Never returns.
[[noreturn]] void run_probe(const primal::ManifestEntry& entry, const fs::path& out) {
  int code = 0;
  try {
    primal::BenchRow row;
    try {
      primal::apply_diagnosis(primal::diagnose(primal::read_mesh(entry.input)), row);
    } catch (const std::exception& e) {
      // The mesh run reports why the input cannot be used; this only goes to the log.
      std::cerr << "stcweave: probe: " << e.what() << "\n";
    }
    if (entry.reference) {
      try {
        const primal::MeshFile ref = primal::read_mesh(*entry.reference);
        if (ref.hexes.empty()) {
          row.reference_error = entry.reference->string() + " has no hexahedra";
        } else {
          primal::HexMesh mesh;
          mesh.points = ref.points;
          mesh.complex.hexes = ref.hexes;
          mesh.complex.num_nodes = static_cast<std::size_t>(ref.points.rows());
          primal::apply_reference(primal::summarize_quality(mesh, 0), row);
        }
      } catch (const std::exception& e) {
        row.reference_error = e.what();
      }
    }
    primal::write_text_file(out, primal::probe_to_json(row).dump(1) + "\n");
  } catch (const std::exception& e) {
    std::cerr << "stcweave: probe failed: " << e.what() << "\n";
    code = mentions_out_of_memory(e.what()) ? kInternal : kInvalidInput;
  }
  std::cerr.flush();
  _exit(code);
}

pid_t spawn_probe(const primal::ManifestEntry& entry, const Job& job, std::size_t memory_mb) {
  return spawn(job.log, memory_mb, [&entry, &job] { run_probe(entry, job.report); });
}

/// Fills the outcome of a finished mesh run into `row`.
void finish_mesh_row(const Job& job, const std::string& input_path, int status,
                     const struct rusage& usage, bool timed_out, const BenchArgs& a,
                     primal::BenchRow& row) {
  row.peak_memory_mb = static_cast<double>(usage.ru_maxrss) / 1024.0;  // KiB on Linux
  const std::string stderr_text = slurp(job.log);
  const std::string memory_reason =
      "memory limit of " + std::to_string(a.memory_mb) + " MB reached (--memory)";
  if (timed_out) {
    row.status = primal::RunStatus::Timeout;
    std::ostringstream s;
    s << "killed after the " << a.timeout << " s wall-time limit (--timeout)";
    row.reason = s.str();
  } else if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    const std::string signal_text =
        "killed by signal " + std::to_string(sig) + " (" + strsignal(sig) + ")";
    // A crash with the resident size already at half the address-space limit is most
    // likely an allocation that failed where no exception could be thrown.
    const bool near_limit =
        a.memory_mb > 0 && *row.peak_memory_mb >= 0.5 * static_cast<double>(a.memory_mb);
    if (mentions_out_of_memory(stderr_text)) {
      row.status = primal::RunStatus::OutOfMemory;
      row.reason = memory_reason;
    } else if (near_limit) {
      row.status = primal::RunStatus::OutOfMemory;
      row.reason = signal_text + " with its resident size near the memory limit of " +
                   std::to_string(a.memory_mb) + " MB (--memory)";
    } else {
      row.status = primal::RunStatus::Crashed;
      row.reason = signal_text;
    }
  } else if (WIFEXITED(status)) {
    const int code = WEXITSTATUS(status);
    if (code == kSuccess) {
      row.status = primal::RunStatus::Ok;
    } else if (mentions_out_of_memory(stderr_text)) {
      row.status = primal::RunStatus::OutOfMemory;
      row.reason = memory_reason;
    } else {
      row.status = code == kInvalidInput ? primal::RunStatus::Rejected : primal::RunStatus::Failed;
      row.reason = primal::tidy_reason(last_message(job.log), input_path, row.input);
      if (row.reason.empty()) row.reason = "exit code " + std::to_string(code) + ", no message";
    }
  }
  if (fs::exists(job.report)) {
    try {
      primal::apply_report(nlohmann::json::parse(slurp(job.report)), row);
    } catch (const nlohmann::json::exception& e) {
      if (row.status == primal::RunStatus::Ok) {
        row.status = primal::RunStatus::Failed;
        row.reason = "unreadable report " + job.report.string() + ": " + e.what();
      }
    }
  } else if (row.status == primal::RunStatus::Ok) {
    row.status = primal::RunStatus::Failed;
    row.reason = "exit code 0 but no report written to " + job.report.string();
  }
}

std::string progress_line(std::size_t done, std::size_t total, const primal::BenchRow& row) {
  std::ostringstream s;
  s << "bench [" << done << "/" << total << "] " << row.input << " " << row.rules << ": "
    << primal::to_string(row.status);
  if (row.status == primal::RunStatus::Ok) {
    if (row.hexes) s << ", " << *row.hexes << " hexes";
  } else if (!row.reason.empty()) {
    s << " (" << (row.reason.size() > 100 ? row.reason.substr(0, 97) + "..." : row.reason) << ")";
  }
  char secs[32];
  std::snprintf(secs, sizeof secs, ", %.2f s", row.wall_seconds);
  s << secs;
  return s.str();
}

/// Writes the surface and the hex mesh of every generated input into `folder` and points
/// the entry at them (the hex mesh becomes the reference unless the manifest gave one).
void write_generated_inputs(primal::Manifest& manifest, const fs::path& folder) {
  for (primal::ManifestEntry& e : manifest.entries) {
    if (!e.generated) continue;
    const primal::HexMesh hexes = primal::shape_hexes(*e.generated);
    e.input = folder / (e.file_stem + ".obj");
    primal::write_surface(primal::boundary_mesh(hexes), e.input);
    if (!e.reference) {
      e.reference = folder / (e.file_stem + ".hexes.vtk");
      primal::write_hex_mesh(hexes, *e.reference);
    }
  }
}

int run_bench(const BenchArgs& a) {
  const auto t_start = Clock::now();
  primal::Manifest manifest = primal::read_manifest(a.manifest);
  const std::vector<std::string> rules = primal::parse_rules_list(a.rules);
  for (const std::string& r : rules) (void)weave::rule_set_from_name(r);  // fail up front

  const fs::path out(a.out);
  std::error_code ec;
  for (const char* sub : {"meshes", "reports", "logs", "probes", "inputs"}) {
    fs::create_directories(out / sub, ec);
    if (ec)
      throw IoError("cannot create " + (out / sub).string() + ": " + ec.message() +
                    "; choose another --out folder");
  }
  write_generated_inputs(manifest, out / "inputs");

  // Probes first (one per input), then the mesh runs in manifest order, then rules order.
  std::vector<Job> jobs;
  for (std::size_t i = 0; i < manifest.entries.size(); ++i) {
    const std::string& stem = manifest.entries[i].file_stem;
    Job probe;
    probe.kind = Job::Kind::Probe;
    probe.entry = i;
    probe.report = out / "probes" / (stem + ".json");
    probe.log = out / "logs" / (stem + ".probe.stderr");
    jobs.push_back(probe);
  }
  primal::BenchResults results;
  results.manifest = a.manifest;
  results.rules = rules;
  results.jobs = a.jobs;
  // Each run's threads (`mesh --threads`): by default the hardware threads shared out over
  // the runs at a time, so that concurrent runs do not compete for cores (the mesh does not
  // depend on it; the timings do).
  const std::size_t hardware = std::max(1U, std::thread::hardware_concurrency());
  results.threads = a.threads > 0 ? static_cast<std::size_t>(a.threads)
                                  : std::max<std::size_t>(1, hardware / a.jobs);
  for (std::size_t i = 0; i < manifest.entries.size(); ++i) {
    for (const std::string& r : rules) {
      const std::string stem = manifest.entries[i].file_stem + "." + r;
      Job job;
      job.entry = i;
      job.row = results.rows.size();
      job.rules = r;
      job.mesh = out / "meshes" / (stem + ".vtk");
      job.report = out / "reports" / (stem + ".json");
      job.log = out / "logs" / (stem + ".stderr");
      jobs.push_back(job);
      primal::BenchRow row;
      row.input = manifest.entries[i].name;
      row.rules = r;
      row.status = primal::RunStatus::Failed;
      row.reason = "not run: the bench was interrupted";
      results.rows.push_back(std::move(row));
    }
  }
  const std::size_t mesh_runs = results.rows.size();

  struct sigaction handler {
  }, old_int{}, old_term{};
  handler.sa_handler = on_interrupt;
  sigemptyset(&handler.sa_mask);
  g_interrupted = 0;
  sigaction(SIGINT, &handler, &old_int);
  sigaction(SIGTERM, &handler, &old_term);

  std::vector<bool> probed(manifest.entries.size(), false);
  std::size_t next = 0, done = 0;
  std::vector<Running> running;
  while (next < jobs.size() || !running.empty()) {
    if (g_interrupted != 0) {
      for (const Running& r : running) {
        kill(-r.pid, SIGKILL);
        kill(r.pid, SIGKILL);
      }
      for (const Running& r : running) {
        int status = 0;
        while (waitpid(r.pid, &status, 0) < 0 && errno == EINTR) {
        }
        if (jobs[r.job].kind == Job::Kind::Mesh)
          results.rows[jobs[r.job].row].reason =
              "not finished: killed when the bench was interrupted";
      }
      running.clear();
      break;
    }
    while (running.size() < a.jobs && next < jobs.size()) {
      Job& job = jobs[next];
      fs::remove(job.report, ec);
      pid_t pid = -1;
      if (job.kind == Job::Kind::Probe) {
        pid = spawn_probe(manifest.entries[job.entry], job, a.memory_mb);
      } else {
        fs::remove(job.mesh, ec);
        pid = spawn_exec({"stcweave", "mesh", manifest.entries[job.entry].input.string(), "-o",
                          job.mesh.string(), "--report", job.report.string(), "-q", "--rules",
                          job.rules, "--threads", std::to_string(results.threads)},
                         job.log, a.memory_mb);
      }
      if (pid < 0) {
        const std::string why = std::string("cannot start a process: ") + std::strerror(errno);
        if (job.kind == Job::Kind::Mesh) {
          primal::BenchRow& row = results.rows[job.row];
          row.status = primal::RunStatus::Failed;
          row.reason = why;
          ++done;
          if (!a.quiet) std::cerr << progress_line(done, mesh_runs, row) << "\n";
        }
      } else {
        running.push_back({pid, next, Clock::now(), false});
      }
      ++next;
    }
    bool reaped = false;
    for (auto it = running.begin(); it != running.end();) {
      int status = 0;
      struct rusage usage {};
      const pid_t r = wait4(it->pid, &status, WNOHANG, &usage);
      const Job& job = jobs[it->job];
      if (r == it->pid || (r < 0 && errno != EINTR)) {
        const double seconds = std::chrono::duration<double>(Clock::now() - it->start).count();
        if (job.kind == Job::Kind::Probe) {
          probed[job.entry] =
              r == it->pid && !it->timed_out && WIFEXITED(status) && WEXITSTATUS(status) == 0;
        } else {
          primal::BenchRow& row = results.rows[job.row];
          row.wall_seconds = seconds;
          if (r == it->pid) {
            row.reason.clear();
            finish_mesh_row(job, manifest.entries[job.entry].input.string(), status, usage,
                            it->timed_out, a, row);
          } else {
            row.status = primal::RunStatus::Failed;
            row.reason = std::string("lost the child process: ") + std::strerror(errno);
          }
          ++done;
          if (!a.quiet) std::cerr << progress_line(done, mesh_runs, row) << "\n";
        }
        it = running.erase(it);
        reaped = true;
        continue;
      }
      if (!it->timed_out &&
          std::chrono::duration<double>(Clock::now() - it->start).count() > a.timeout) {
        kill(-it->pid, SIGKILL);
        kill(it->pid, SIGKILL);
        it->timed_out = true;
      }
      ++it;
    }
    if (!reaped) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  sigaction(SIGINT, &old_int, nullptr);
  sigaction(SIGTERM, &old_term, nullptr);

  // The probes' figures go into every row of their input.
  for (const Job& job : jobs) {
    if (job.kind != Job::Kind::Mesh) continue;
    primal::BenchRow& row = results.rows[job.row];
    const fs::path probe = out / "probes" / (manifest.entries[job.entry].file_stem + ".json");
    if (probed[job.entry]) {
      try {
        primal::apply_probe(nlohmann::json::parse(slurp(probe)), row);
      } catch (const nlohmann::json::exception&) {
        probed[job.entry] = false;
      }
    }
    if (!probed[job.entry] && manifest.entries[job.entry].reference && row.reference_error.empty())
      row.reference_error = "the probe of this input failed (see logs/" +
                            manifest.entries[job.entry].file_stem + ".probe.stderr)";
  }

  results.wall_seconds = std::chrono::duration<double>(Clock::now() - t_start).count();
  primal::fit_scaling(results);
  primal::write_text_file(out / "results.json", primal::to_json(results).dump(1) + "\n");
  primal::write_text_file(out / "results.csv", primal::format_csv(results.rows));
  primal::write_text_file(out / "results.md", primal::format_markdown(results));

  if (!a.quiet) {
    std::size_t ok = 0;
    for (const auto& r : results.rows) ok += r.status == primal::RunStatus::Ok ? 1 : 0;
    std::printf("bench: %zu runs, %zu ok, in %.1f s; results in %s/results.{md,csv,json}\n",
                results.rows.size(), ok, results.wall_seconds, out.string().c_str());
    for (const primal::ScalingFit& s : results.scaling)
      std::printf("scaling (%s): %s seconds ~ hexes^%.2f over %zu runs (R^2 %.3f)\n",
                  s.rules.c_str(), s.stage.c_str(), s.fit.exponent, s.fit.points, s.fit.r_squared);
  }
  if (g_interrupted != 0) {
    std::cerr << "stcweave: bench interrupted; the runs not done are rows marked 'not run'\n";
    return 130;
  }
  return kSuccess;
}

}  // namespace

Action add_bench_command(CLI::App& app) {
  auto args = std::make_shared<BenchArgs>();
  CLI::App* sub = app.add_subcommand(
      "bench",
      "Run the whole pipeline on every input of a manifest (one input per line, optionally "
      "followed by a reference hex mesh; # comments; paths relative to the manifest; "
      "generate:box:AxBxC or generate:bar:SHAPE for a generated shape), each run in a fresh "
      "process with time and memory limits, and write DIR/results.json, results.csv and "
      "results.md: one row per (input, rule set), failures included with their reason, plus "
      "the fitted exponent of seconds against hexes. Progress on stderr. Exit code 0 whatever "
      "the rows say.");
  sub->add_option("manifest", args->manifest, "manifest file")->required();
  sub->add_option("-j,--jobs", args->jobs, "runs at a time (rows keep manifest order)")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  sub->add_option("--out", args->out,
                  "output folder (results.*, and meshes/, reports/, logs/, probes/, inputs/)")
      ->capture_default_str();
  sub->add_option("--rules", args->rules,
                  "comma-separated rule sets to compare side by side (reliable, extended)")
      ->capture_default_str();
  sub->add_option("--timeout", args->timeout, "wall-time limit per run, in seconds")
      ->check(kFinite)
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  sub->add_option("--memory", args->memory_mb, "address-space limit per run, in MB (0: no limit)")
      ->capture_default_str();
  sub->add_option("--threads", args->threads,
                  "threads per run (passed to mesh --threads; 0: the hardware threads divided "
                  "by --jobs, at least 1)")
      ->check(CLI::Range(0, 256))
      ->capture_default_str();
  sub->add_flag("-q,--quiet", args->quiet, "no progress lines, no summary");
  return [args] { return run_bench(*args); };
}

}  // namespace stcweave::cli
