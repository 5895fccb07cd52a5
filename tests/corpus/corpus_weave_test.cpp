// Every genus-0, single-shell, loop-clean file of the shared corpus is woven into a valid
// hex complex (label `corpus`). Known counts: the Gmsh transfinite cube and L-block give
// their structured meshes (125 and 81 hexes), fichera gives 7.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "stcweave/primal/io.hpp"
#include "stcweave/primal/pipeline.hpp"
#include "support/corpus.hpp"

namespace stcweave {
namespace {

std::vector<std::string> loop_clean_files() {
  return test::expected_files([](const nlohmann::json& v) {
    return v.value("genus", nlohmann::json()) == 0 && v.value("components", 0) == 1 &&
           v.value("self_intersecting_loops", -1) == 0;
  });
}

TEST(CorpusWeave, EveryLoopCleanGenusZeroFileGivesAValidComplex) {
  const auto files = loop_clean_files();
  if (files.empty()) GTEST_SKIP() << "shared data not found at " << STCWEAVE_SHARED_DATA;
  EXPECT_GE(files.size(), 25u);
  const std::map<std::string, std::size_t> known = {{"gmsh/cube_tf_coarse.obj", 125},
                                                    {"gmsh/lblock_tf_coarse.obj", 81},
                                                    {"real/mfem/fichera.mesh", 7},
                                                    {"real/mesquite/hexes_4by2by2.vtk", 16}};
  for (const auto& name : files) {
    SCOPED_TRACE(name);
    const auto file = primal::read_mesh(test::shared_data() / name);
    primal::MeshOptions options;
    options.weave.check = file.quads.size() + file.hexes.size() < 300;
    primal::MeshResult r;
    ASSERT_NO_THROW(r = primal::mesh_file(file, options));
    EXPECT_TRUE(r.validation.valid) << r.validation.summary();
    EXPECT_GT(r.mesh.complex.hexes.size(), 0u);
    if (const auto it = known.find(name); it != known.end())
      EXPECT_EQ(r.mesh.complex.hexes.size(), it->second);
  }
}

}  // namespace
}  // namespace stcweave
