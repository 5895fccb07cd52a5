// `stcweave mesh` on surfaces whose loops cross themselves: exit codes and the front file.
#include <gtest/gtest.h>

#include <filesystem>

#include "stcweave/primal/io.hpp"
#include "stcweave/stc/loop_moves.hpp"
#include "stcweave/stc/loops.hpp"
#include "support/cli_run.hpp"
#include "support/quadrangulations.hpp"

namespace stcweave {
namespace {

std::filesystem::path temp(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("stcweave_selfx_cli_" + name);
}

TEST(SelfCrossingCli, AnOddSurfaceIsRefusedForItsParityWithExitCode2) {
  std::optional<primal::SurfaceMesh> odd;
  for (std::uint32_t seed = 0; seed < 100 && !odd; ++seed) {
    auto m = test::random_quadrangulation(seed, 9 + 2 * static_cast<int>(seed % 5), 40);
    if (m && m->surface.quads.size() % 2 == 1) odd = std::move(m);
  }
  ASSERT_TRUE(odd.has_value());
  const auto in = temp("odd.obj");
  primal::write_surface(*odd, in);
  const test::CliRun r = test::run_cli("mesh " + in.string() + " -o " + temp("odd.vtk").string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("odd number"), std::string::npos) << r.out;
  std::filesystem::remove(in);
}

TEST(SelfCrossingCli, AGivenUpSearchExitsWith3AndLeavesTheFront) {
  // Seed 154: 8 quads, every one crossed twice by the same loop; the generated points make no
  // solid, so only the topology matters here: two moves are not enough.
  const auto mesh = test::random_quadrangulation(154, 8 + 154 % 14, 40);
  ASSERT_TRUE(mesh.has_value());
  const auto in = temp("tangled.obj");
  const auto front = temp("tangled.front.obj");
  std::filesystem::remove(front);
  primal::write_surface(*mesh, in);
  const test::CliRun r =
      test::run_cli("mesh " + in.string() + " -o " + temp("tangled.vtk").string() +
                    " --loop-moves-max 2 --front-on-failure " + front.string());
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_NE(r.out.find("self-intersecting loops"), std::string::npos) << r.out;
  EXPECT_TRUE(std::filesystem::exists(front)) << r.out;
  // The evaluation and work bounds the message tells the user to raise are options too.
  for (const std::string bound : {"--loop-moves-evaluations 1", "--loop-moves-work 1"}) {
    const test::CliRun b =
        test::run_cli("mesh " + in.string() + " -o " + temp("tangled.vtk").string() + " " + bound +
                      " --front-on-failure " + front.string());
    EXPECT_EQ(b.code, 3) << bound << ": " << b.out;
    EXPECT_NE(b.out.find("evaluation bound"), std::string::npos) << bound << ": " << b.out;
  }
  const test::CliRun off = test::run_cli("mesh " + in.string() + " -o " +
                                         temp("tangled.vtk").string() + " --no-loop-moves");
  EXPECT_EQ(off.code, 2) << off.out;
  EXPECT_NE(off.out.find("crosses itself"), std::string::npos) << off.out;
  std::filesystem::remove(in);
  std::filesystem::remove(front);
}

// With --progress the search for front moves says how far it got (every 10th attached hex):
// a generated sphere whose search attaches at least 10 hexes prints such a line, and the
// run's outcome (exit code, mesh) is the same as without --progress.
TEST(SelfCrossingCli, ProgressShowsTheFrontMoves) {
  std::optional<primal::SurfaceMesh> busy;
  for (std::uint32_t seed = 0; seed < 200 && !busy; ++seed) {
    auto m = test::random_quadrangulation(seed, 16 + static_cast<int>(seed % 10), 60);
    if (!m || m->surface.quads.size() % 2 == 1) continue;
    if (stc::untangle_loops(m->surface).hexes.hexes.size() >= 10) busy = std::move(m);
  }
  ASSERT_TRUE(busy.has_value()) << "no generated sphere needs 10 attached hexes";
  const auto in = temp("busy.obj");
  primal::write_surface(*busy, in);
  const std::string base = "mesh " + in.string() + " --no-untangle -o ";
  const test::CliRun with = test::run_cli(base + temp("busy_p.vtk").string() + " --progress");
  const test::CliRun without = test::run_cli(base + temp("busy_q.vtk").string() + " -q");
  // (A line every 10th attached hex and every `progress_every` evaluations: with the search's
  // strict contacts the first one on this sphere comes at 14 hexes.)
  EXPECT_NE(with.out.find("front moves (untangling): "), std::string::npos) << with.out;
  EXPECT_NE(with.out.find(" hexes attached, "), std::string::npos) << with.out;
  EXPECT_EQ(without.out.find("front moves"), std::string::npos) << without.out;
  EXPECT_EQ(with.code, without.code) << with.out << without.out;
  std::filesystem::remove(in);
}

// Seed 120 of the generated catalogue (16 quads): the search makes its loops simple (12
// attached hexes; the deepening of tiny fronts was needed before the search's strict contacts,
// 2026-12-07), but every weave of the front left blocks: exit 3, the message says so, and the
// front is written where asked; `--loop-moves-tiny-depth 0` is accepted and changes nothing.
TEST(SelfCrossingCli, ASphereWhoseFrontNoWeaveCompletesIsGivenUpWithItsFront) {
  const auto mesh = test::random_quadrangulation(120, 8 + 120 % 14, 40);
  ASSERT_TRUE(mesh.has_value());
  const auto in = temp("seed120.obj");
  primal::write_surface(*mesh, in);
  const std::string base = "mesh " + in.string() + " --no-untangle -q -o ";
  const auto out = temp("seed120.vtk");
  const auto front = temp("seed120.front.obj");
  const test::CliRun on =
      test::run_cli(base + out.string() + " --front-on-failure " + front.string());
  EXPECT_EQ(on.code, 3) << on.out;
  EXPECT_NE(on.out.find("every weave of the front blocked"), std::string::npos) << on.out;
  EXPECT_FALSE(std::filesystem::exists(out)) << "no mesh for a refusal";
  EXPECT_TRUE(std::filesystem::exists(front));
  const auto front_off = temp("seed120_off.front.obj");
  const test::CliRun off =
      test::run_cli(base + temp("seed120_off.vtk").string() +
                    " --loop-moves-tiny-depth 0 --front-on-failure " + front_off.string());
  EXPECT_EQ(off.code, 3) << off.out;
  EXPECT_TRUE(std::filesystem::exists(front_off));
  for (const auto& p : {in, out, front, front_off}) std::filesystem::remove(p);
}

}  // namespace
}  // namespace stcweave
