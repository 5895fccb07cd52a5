/// `stcweave bench MANIFEST [--jobs N] [--out DIR] [--rules LIST] [--timeout S] [--memory MB]`:
/// the corpus runner. For every (input, rule set) of the manifest it runs
/// `stcweave mesh INPUT -o DIR/meshes/NAME.RULES.vtk --report DIR/reports/NAME.RULES.json -q
/// --rules RULES` in a fresh process (this very binary, /proc/self/exe) under a wall-time
/// limit (the process group is killed on timeout) and an address-space limit (RLIMIT_AS),
/// measures its wall time and peak resident memory, and writes DIR/results.{json,csv,md}.
/// Every run is a row, whatever happened to it; rows come in manifest order, then rules
/// order, whatever --jobs is. Exit code 0 whatever the rows say (2 for a bad manifest or an
/// unknown rule set, found before anything runs).

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

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
  std::string rules = "reliable";
  double timeout = 300.0;
  std::size_t memory_mb = 4096;
  bool quiet = false;
};

/// One child run to do.
struct Job {
  std::size_t entry = 0;
  std::string rules;
  fs::path mesh, report, log;
};

/// A child running.
struct Running {
  pid_t pid = -1;
  std::size_t job = 0;
  Clock::time_point start;
  bool timed_out = false;
};

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
         text.find("out of memory") != std::string::npos;
}

void write_text_atomically(const fs::path& path, const std::string& text) {
  const fs::path tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary);
    if (!out)
      throw IoError("cannot write " + path.string() + ": check the folder exists and is writable");
    out << text;
    out.flush();
    if (!out) throw IoError("writing " + path.string() + " failed (disk full?)");
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) throw IoError("cannot rename " + tmp.string() + " to " + path.string());
}

/// Starts `argv` in a new process group with stdout to /dev/null, stderr to `log` and an
/// address-space limit; returns its pid, or -1 with errno set.
pid_t spawn(const std::vector<std::string>& args, const fs::path& log, std::size_t memory_mb) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const std::string log_path = log.string();
  const pid_t pid = fork();
  if (pid != 0) {
    if (pid > 0) setpgid(pid, pid);
    return pid;
  }
  // Child: async-signal-safe calls only until exec.
  setpgid(0, 0);
  if (memory_mb > 0) {
    struct rlimit limit;
    limit.rlim_cur = limit.rlim_max = static_cast<rlim_t>(memory_mb) * 1024 * 1024;
    setrlimit(RLIMIT_AS, &limit);
  }
  const int null_fd = open("/dev/null", O_RDWR);
  const int log_fd = open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (null_fd >= 0) {
    dup2(null_fd, STDIN_FILENO);
    dup2(null_fd, STDOUT_FILENO);
  }
  if (log_fd >= 0) dup2(log_fd, STDERR_FILENO);
  execv("/proc/self/exe", argv.data());
  const char msg[] = "stcweave: cannot start /proc/self/exe\n";
  [[maybe_unused]] const ssize_t n = write(STDERR_FILENO, msg, sizeof msg - 1);
  _exit(127);
}

/// Fills the outcome of a finished child into `row`.
void finish_row(const Job& job, int status, const struct rusage& usage, bool timed_out,
                std::size_t memory_mb, double timeout, primal::BenchRow& row) {
  row.peak_memory_mb = static_cast<double>(usage.ru_maxrss) / 1024.0;  // KiB on Linux
  const std::string stderr_text = slurp(job.log);
  if (timed_out) {
    row.status = primal::RunStatus::Timeout;
    std::ostringstream s;
    s << "killed after the " << timeout << " s wall-time limit (--timeout)";
    row.reason = s.str();
  } else if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    if (mentions_out_of_memory(stderr_text)) {
      row.status = primal::RunStatus::OutOfMemory;
      row.reason = "memory limit of " + std::to_string(memory_mb) + " MB reached (--memory)";
    } else {
      row.status = primal::RunStatus::Crashed;
      row.reason = "killed by signal " + std::to_string(sig) + " (" + strsignal(sig) + ")";
    }
  } else if (WIFEXITED(status)) {
    const int code = WEXITSTATUS(status);
    if (code == kSuccess) {
      row.status = primal::RunStatus::Ok;
    } else if (mentions_out_of_memory(stderr_text)) {
      row.status = primal::RunStatus::OutOfMemory;
      row.reason = "memory limit of " + std::to_string(memory_mb) + " MB reached (--memory)";
    } else {
      row.status = code == kInvalidInput ? primal::RunStatus::Rejected : primal::RunStatus::Failed;
      row.reason = last_message(job.log);
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
  s << "[" << done << "/" << total << "] " << row.input << " " << row.rules << ": "
    << primal::to_string(row.status);
  if (row.status == primal::RunStatus::Ok) {
    if (row.hexes) s << " " << *row.hexes << " hexes";
  } else if (!row.reason.empty()) {
    s << " (" << (row.reason.size() > 100 ? row.reason.substr(0, 97) + "..." : row.reason) << ")";
  }
  char secs[32];
  std::snprintf(secs, sizeof secs, " %.2f s", row.wall_seconds);
  s << secs;
  return s.str();
}

int run_bench(const BenchArgs& a) {
  const auto t_start = Clock::now();
  const primal::Manifest manifest = primal::read_manifest(a.manifest);
  const std::vector<std::string> rules = primal::parse_rules_list(a.rules);
  for (const std::string& r : rules) (void)weave::rule_set_from_name(r);  // fail up front

  const fs::path out(a.out);
  std::error_code ec;
  for (const char* sub : {"meshes", "reports", "logs"}) {
    fs::create_directories(out / sub, ec);
    if (ec)
      throw IoError("cannot create " + (out / sub).string() + ": " + ec.message() +
                    "; choose another --out folder");
  }

  // The cheap figures, in-process: diagnosis of every input, quality of every reference.
  std::vector<primal::BenchRow> base(manifest.entries.size());
  for (std::size_t i = 0; i < manifest.entries.size(); ++i) {
    const primal::ManifestEntry& e = manifest.entries[i];
    primal::BenchRow& row = base[i];
    row.input = e.name;
    try {
      primal::apply_diagnosis(primal::diagnose(primal::read_mesh(e.input)), row);
    } catch (const std::exception&) {
      // The child run reports why the input cannot be used.
    }
    if (e.reference) {
      try {
        const primal::MeshFile ref = primal::read_mesh(*e.reference);
        if (ref.hexes.empty()) {
          row.reference_error = e.reference->string() + " has no hexahedra";
        } else {
          primal::HexMesh mesh;
          mesh.points = ref.points;
          mesh.complex.hexes = ref.hexes;
          mesh.complex.num_nodes = static_cast<std::size_t>(ref.points.rows());
          primal::apply_reference(primal::summarize_quality(mesh), row);
        }
      } catch (const std::exception& ex) {
        row.reference_error = ex.what();
      }
    }
  }

  std::vector<Job> jobs;
  for (std::size_t i = 0; i < manifest.entries.size(); ++i)
    for (const std::string& r : rules) {
      const std::string stem = manifest.entries[i].file_stem + "." + r;
      jobs.push_back({i, r, out / "meshes" / (stem + ".vtk"), out / "reports" / (stem + ".json"),
                      out / "logs" / (stem + ".stderr")});
    }

  primal::BenchResults results;
  results.manifest = a.manifest;
  results.rules = rules;
  results.jobs = a.jobs;
  results.rows.resize(jobs.size());

  std::size_t next = 0, done = 0;
  std::vector<Running> running;
  while (done < jobs.size()) {
    while (running.size() < a.jobs && next < jobs.size()) {
      const Job& job = jobs[next];
      primal::BenchRow& row = results.rows[next];
      row = base[job.entry];
      row.rules = job.rules;
      fs::remove(job.report, ec);
      fs::remove(job.mesh, ec);
      const std::vector<std::string> args = {"stcweave",
                                             "mesh",
                                             manifest.entries[job.entry].input.string(),
                                             "-o",
                                             job.mesh.string(),
                                             "--report",
                                             job.report.string(),
                                             "-q",
                                             "--rules",
                                             job.rules};
      const Clock::time_point start = Clock::now();
      const pid_t pid = spawn(args, job.log, a.memory_mb);
      if (pid < 0) {
        row.status = primal::RunStatus::Failed;
        row.reason = std::string("cannot start a process: ") + std::strerror(errno);
        ++done;
        if (!a.quiet) std::cerr << progress_line(done, jobs.size(), row) << "\n";
      } else {
        running.push_back({pid, next, start, false});
      }
      ++next;
    }
    bool reaped = false;
    for (auto it = running.begin(); it != running.end();) {
      int status = 0;
      struct rusage usage {};
      const pid_t r = wait4(it->pid, &status, WNOHANG, &usage);
      if (r == it->pid) {
        primal::BenchRow& row = results.rows[it->job];
        row.wall_seconds = std::chrono::duration<double>(Clock::now() - it->start).count();
        finish_row(jobs[it->job], status, usage, it->timed_out, a.memory_mb, a.timeout, row);
        ++done;
        if (!a.quiet) std::cerr << progress_line(done, jobs.size(), row) << "\n";
        it = running.erase(it);
        reaped = true;
        continue;
      }
      if (r < 0 && errno != EINTR) {
        primal::BenchRow& row = results.rows[it->job];
        row.status = primal::RunStatus::Failed;
        row.reason = std::string("lost the child process: ") + std::strerror(errno);
        ++done;
        it = running.erase(it);
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
    if (!reaped) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }

  results.wall_seconds = std::chrono::duration<double>(Clock::now() - t_start).count();
  primal::fit_scaling(results);
  write_text_atomically(out / "results.json", primal::to_json(results).dump(1) + "\n");
  write_text_atomically(out / "results.csv", primal::format_csv(results.rows));
  write_text_atomically(out / "results.md", primal::format_markdown(results));

  if (!a.quiet) {
    std::size_t ok = 0;
    for (const auto& r : results.rows) ok += r.status == primal::RunStatus::Ok ? 1 : 0;
    std::printf("bench: %zu runs, %zu ok, in %.1f s; results in %s/results.{md,csv,json}\n",
                results.rows.size(), ok, results.wall_seconds, out.string().c_str());
    for (const auto& [r, fit] : results.scaling)
      std::printf("scaling (%s): weave seconds ~ hexes^%.2f over %zu rows (R^2 %.3f)\n", r.c_str(),
                  fit.exponent, fit.points, fit.r_squared);
  }
  return kSuccess;
}

}  // namespace

Action add_bench_command(CLI::App& app) {
  auto args = std::make_shared<BenchArgs>();
  CLI::App* sub = app.add_subcommand(
      "bench",
      "Run the whole pipeline on every input of a manifest (one input per line, optionally "
      "followed by a reference hex mesh; # comments; paths relative to the manifest), each "
      "run in a fresh process with time and memory limits, and write DIR/results.json, "
      "results.csv and results.md: one row per (input, rule set), failures included with "
      "their reason, plus the fitted exponent of weave seconds against hexes when at least 3 "
      "runs succeed. Progress on stderr. Exit code 0 whatever the rows say.");
  sub->add_option("manifest", args->manifest, "manifest file")->required();
  sub->add_option("-j,--jobs", args->jobs, "runs at a time (rows keep manifest order)")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  sub->add_option("--out", args->out,
                  "output folder (meshes/, reports/, logs/ and results.* are written there)")
      ->capture_default_str();
  sub->add_option("--rules", args->rules,
                  "comma-separated rule sets to compare side by side (reliable, extended)")
      ->capture_default_str();
  sub->add_option("--timeout", args->timeout, "wall-time limit per run, in seconds")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  sub->add_option("--memory", args->memory_mb, "address-space limit per run, in MB (0: no limit)")
      ->capture_default_str();
  sub->add_flag("-q,--quiet", args->quiet, "no progress lines, no summary");
  return [args] { return run_bench(*args); };
}

}  // namespace stcweave::cli
