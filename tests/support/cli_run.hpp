#pragma once
/// \file
/// Running the stcweave program from a test: its exit code and its output. Needs the
/// STCWEAVE_CLI definition (the program's path) of the test executable.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>

namespace stcweave::test {

struct CliRun {
  int code = -1;
  std::string out;  // stdout and stderr together
};

/// Runs `stcweave ARGS` through the shell.
inline CliRun run_cli(const std::string& args) {
  const std::string cmd = std::string(STCWEAVE_CLI) + " " + args + " 2>&1";
  CliRun r;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (pipe == nullptr) return r;
  std::array<char, 4096> buf{};
  while (fgets(buf.data(), static_cast<int>(buf.size()), pipe) != nullptr) r.out += buf.data();
  const int status = pclose(pipe);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

/// The whole content of a file ("" when it cannot be read).
inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// A fixture giving each test case a fresh, empty folder `dir_` (the system's temporary
/// folder / PREFIX followed by the test's name), removed after the test.
class CliTest : public ::testing::Test {
 protected:
  explicit CliTest(std::string prefix) : prefix_(std::move(prefix)) {}
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           (prefix_ + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  /// A file of the repository's data/ folder.
  static std::string data(const std::string& name) {
    return std::string(STCWEAVE_SOURCE_DIR) + "/data/" + name;
  }
  std::filesystem::path dir_;

 private:
  std::string prefix_;
};

}  // namespace stcweave::test
