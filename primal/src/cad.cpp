#include "stcweave/primal/cad.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <string>
#include <system_error>

#include "stcweave/primal/diagnose.hpp"
#include "stcweave/stc/errors.hpp"

#if STCWEAVE_HAVE_GMSH
#include <unistd.h>

#include "cad_split.hpp"
#include "gmsh_session.hpp"

#include <gmsh.h>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <sstream>
#endif

namespace stcweave::primal {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

/// "step", "brep", "iges", or "" for another extension.
std::string cad_format_of(const std::filesystem::path& path) {
  const std::string ext = lower(path.extension().string());
  if (ext == ".step" || ext == ".stp") return "step";
  if (ext == ".brep") return "brep";
  if (ext == ".iges" || ext == ".igs") return "iges";
  return "";
}

}  // namespace

std::string_view cad_recipe_name(CadRecipe recipe) {
  switch (recipe) {
    case CadRecipe::Auto:
      return "auto";
    case CadRecipe::Transfinite:
      return "transfinite";
    case CadRecipe::TriangleSplit:
      return "triangle-split";
    case CadRecipe::Mixed:
      return "mixed";
  }
  return "auto";
}

CadRecipe cad_recipe_from_name(std::string_view name) {
  for (const CadRecipe r :
       {CadRecipe::Auto, CadRecipe::Transfinite, CadRecipe::TriangleSplit, CadRecipe::Mixed})
    if (name == cad_recipe_name(r)) return r;
  throw InvalidInput("unknown CAD surface recipe '" + std::string(name) +
                     "': use auto, transfinite, triangle-split or mixed");
}

bool is_cad_path(const std::filesystem::path& path) {
  return !cad_format_of(path).empty();
}

std::string cad_unavailable_message(const std::filesystem::path& path) {
  return path.string() +
         ": CAD input (STEP, BREP, IGES) needs Gmsh, and this stcweave was built without it "
         "(CMake option STCWEAVE_WITH_GMSH is OFF or libgmsh-dev was not found); install "
         "libgmsh-dev and reconfigure with -DSTCWEAVE_WITH_GMSH=ON, or mesh the solid's surface "
         "into quads with another tool and pass that surface (OBJ, OFF, VTK, MSH, ...)";
}

#if !STCWEAVE_HAVE_GMSH

bool has_cad_support() {
  return false;
}

CadSurface mesh_cad_surface(const std::filesystem::path& path, const CadOptions& /*options*/) {
  throw Unsupported(cad_unavailable_message(path));
}

CadSurface mesh_cad_surface(const CadPrimitive& /*primitive*/, const CadOptions& /*options*/) {
  throw Unsupported(cad_unavailable_message("<generated solid>"));
}

#else

bool has_cad_support() {
  return true;
}

namespace {

using gmsh_detail::gmsh_reason;
using gmsh_detail::GmshSession;

/// Strips terminal colour codes and surrounding blanks and stars from one line of output.
std::string clean_line(const std::string& line) {
  std::string out;
  for (std::size_t i = 0; i < line.size(); ++i) {
    if (line[i] == '\x1b') {
      while (i < line.size() && line[i] != 'm') ++i;
      continue;
    }
    out += line[i];
  }
  const auto not_blank = [](char c) { return c != ' ' && c != '*' && c != '\t' && c != '\r'; };
  const auto b = std::find_if(out.begin(), out.end(), not_blank);
  const auto e = std::find_if(out.rbegin(), out.rend(), not_blank).base();
  return b < e ? std::string(b, e) : std::string();
}

/// While alive, the process's standard output goes to a temporary file (OpenCASCADE's
/// readers print there, past Gmsh's General.Terminal); `lines()` gives back what was
/// printed. Does nothing when `active` is false.
class StdoutCapture {
 public:
  explicit StdoutCapture(bool active) {
    if (!active) return;
    file_ = std::tmpfile();
    if (file_ == nullptr) return;
    std::fflush(stdout);
    saved_ = dup(STDOUT_FILENO);
    if (saved_ < 0 || dup2(fileno(file_), STDOUT_FILENO) < 0) restore();
  }
  StdoutCapture(const StdoutCapture&) = delete;
  StdoutCapture& operator=(const StdoutCapture&) = delete;
  StdoutCapture(StdoutCapture&&) = delete;
  StdoutCapture& operator=(StdoutCapture&&) = delete;
  ~StdoutCapture() {
    restore();
    if (file_ != nullptr) std::fclose(file_);
  }

  /// Restores stdout and returns the non-empty lines printed meanwhile.
  std::vector<std::string> lines() {
    restore();
    std::vector<std::string> out;
    if (file_ == nullptr) return out;
    std::rewind(file_);
    std::string line;
    for (int c = std::fgetc(file_); c != EOF; c = std::fgetc(file_)) {
      if (c == '\n') {
        if (std::string l = clean_line(line); !l.empty()) out.push_back(l);
        line.clear();
      } else {
        line += static_cast<char>(c);
      }
    }
    if (std::string l = clean_line(line); !l.empty()) out.push_back(l);
    return out;
  }

 private:
  void restore() {
    if (saved_ < 0) return;
    std::fflush(stdout);
    dup2(saved_, STDOUT_FILENO);
    close(saved_);
    saved_ = -1;
  }
  std::FILE* file_ = nullptr;
  int saved_ = -1;
};

/// While alive, the process's standard output goes to standard error (when `active`): with
/// `CadOptions::verbose`, Gmsh's and OpenCASCADE's messages must not mix with a program's
/// own output on stdout.
class StdoutToStderr {
 public:
  explicit StdoutToStderr(bool active) {
    if (!active) return;
    std::fflush(stdout);
    saved_ = dup(STDOUT_FILENO);
    if (saved_ >= 0 && dup2(STDERR_FILENO, STDOUT_FILENO) < 0) {
      close(saved_);
      saved_ = -1;
    }
  }
  StdoutToStderr(const StdoutToStderr&) = delete;
  StdoutToStderr& operator=(const StdoutToStderr&) = delete;
  StdoutToStderr(StdoutToStderr&&) = delete;
  StdoutToStderr& operator=(StdoutToStderr&&) = delete;
  ~StdoutToStderr() {
    if (saved_ < 0) return;
    std::fflush(stdout);
    dup2(saved_, STDOUT_FILENO);
    close(saved_);
  }

 private:
  int saved_ = -1;
};

/// Gmsh's logged messages since the last call, split into errors and warnings.
struct GmshLog {
  std::vector<std::string> errors;
  std::vector<std::string> warnings;
};

GmshLog take_log() {
  std::vector<std::string> log;
  gmsh::logger::get(log);
  gmsh::logger::stop();
  gmsh::logger::start();
  GmshLog out;
  for (const std::string& l : log) {
    if (l.rfind("Error", 0) == 0) out.errors.push_back(l);
    if (l.rfind("Warning", 0) == 0) out.warnings.push_back(l);
  }
  return out;
}

std::string join(const std::vector<std::string>& v, const std::string& sep) {
  std::string out;
  for (std::size_t i = 0; i < v.size(); ++i) out += (i > 0 ? sep : "") + v[i];
  return out;
}

/// Sets every Gmsh option the front end relies on (options persist between models).
void set_common_options(const CadOptions& options) {
  gmsh::option::setNumber("General.Terminal", options.verbose ? 1 : 0);
  gmsh::option::setNumber("General.Verbosity", options.verbose ? 5 : 2);
  gmsh::option::setNumber("General.NumThreads", 1);  // determinism
  gmsh::option::setNumber("Mesh.MaxNumThreads2D", 1);
  gmsh::option::setNumber("Mesh.RandomFactor", 1e-9);     // Gmsh's default, set explicitly
  gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);  // STEP points carry their own sizes
  gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
  gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 1);
  gmsh::option::setNumber("Mesh.MeshSizeFactor", 1);
  gmsh::option::setNumber("Mesh.MeshSizeMin", 0);
  gmsh::option::setNumber("Mesh.RecombineAll", 0);
  gmsh::option::setNumber("Mesh.SubdivisionAlgorithm", 0);
  gmsh::option::setNumber("Mesh.ElementOrder", 1);
  // Gmsh 4.8's known crash: generate(2) with Mesh.Algorithm 8 (Frontal-Delaunay for quads)
  // segfaults in its cross-field closest-point search unless this is 0. We never use
  // algorithm 8, but a model or a configuration that does must not crash us.
  gmsh::option::setNumber("Mesh.CrossFieldClosestPoint", 0);
  gmsh::option::setNumber("Geometry.OCCSewFaces", 0);
  gmsh::option::setNumber("Geometry.OCCMakeSolids", 0);
}

double bbox_diagonal(const gmsh::vectorpair& volumes) {
  double lo[3] = {1e300, 1e300, 1e300};
  double hi[3] = {-1e300, -1e300, -1e300};
  for (const auto& [dim, tag] : volumes) {
    double b[6];
    gmsh::model::getBoundingBox(dim, tag, b[0], b[1], b[2], b[3], b[4], b[5]);
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], b[k]);
      hi[k] = std::max(hi[k], b[k + 3]);
    }
  }
  return std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                   (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

/// Curves of a face, in Gmsh's order, with repeats (a seam appears twice).
std::vector<int> face_curves(int face) {
  gmsh::vectorpair curves;
  gmsh::model::getBoundary({{2, face}}, curves, false, false, false);
  std::vector<int> out;
  for (const auto& [d, t] : curves) out.push_back(std::abs(t));
  return out;
}

std::vector<int> curve_points(int curve) {
  gmsh::vectorpair points;
  gmsh::model::getBoundary({{1, curve}}, points, false, false, false);
  std::vector<int> out;
  for (const auto& [d, t] : points) out.push_back(std::abs(t));
  return out;
}

int find_root(std::map<int, int>& parent, int x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

/// The four curves of `face` in cyclic order (sides 0 and 2 opposite, 1 and 3 opposite) when
/// the face has four corners: four distinct curves, each with two distinct end points,
/// forming one 4-cycle (four distinct corners, each on exactly two of the curves). Otherwise
/// false, with the reason.
bool four_sides(int face, std::array<int, 4>& sides, std::string& reason) {
  const std::vector<int> curves = face_curves(face);
  std::vector<int> distinct = curves;
  std::sort(distinct.begin(), distinct.end());
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  if (curves.size() != 4 || distinct.size() != 4) {
    reason = "CAD face " + std::to_string(face) + " is bounded by " +
             std::to_string(curves.size()) + " curve uses, not 4 curves";
    return false;
  }
  std::map<int, int> corner_uses;
  std::array<std::vector<int>, 4> ends;
  for (std::size_t i = 0; i < 4; ++i) {
    ends[i] = curve_points(curves[i]);
    if (ends[i].size() != 2 || ends[i][0] == ends[i][1]) {
      reason = "CAD face " + std::to_string(face) + " has a closed curve (curve " +
               std::to_string(curves[i]) + ")";
      return false;
    }
    for (const int p : ends[i]) ++corner_uses[p];
  }
  if (corner_uses.size() != 4 || std::any_of(corner_uses.begin(), corner_uses.end(),
                                             [](const auto& kv) { return kv.second != 2; })) {
    reason = "CAD face " + std::to_string(face) + " has " + std::to_string(corner_uses.size()) +
             " corners, not 4";
    return false;
  }
  // Side 2 is the one sharing no corner with side 0.
  sides = {curves[0], 0, 0, 0};
  std::vector<int> rest;
  for (std::size_t i = 1; i < 4; ++i) {
    const bool shares = std::find(ends[0].begin(), ends[0].end(), ends[i][0]) != ends[0].end() ||
                        std::find(ends[0].begin(), ends[0].end(), ends[i][1]) != ends[0].end();
    if (shares) {
      rest.push_back(curves[i]);
    } else {
      sides[2] = curves[i];
    }
  }
  if (rest.size() != 2 || sides[2] == 0) {
    reason = "CAD face " + std::to_string(face) + ": its four curves do not form a cycle";
    return false;
  }
  sides[1] = rest[0];
  sides[3] = rest[1];
  return true;
}

/// Puts transfinite constraints (and recombination) on the faces of `structured`, whose
/// sides are given. Opposite curves of a face must get the same number of segments: the
/// curves are grouped in chains of opposite curves (union-find), and every curve of a chain
/// gets round(longest / size) segments, at least 1.
void set_transfinite(const std::map<int, std::array<int, 4> >& structured, double size) {
  std::map<int, int> parent;
  for (const auto& [f, s] : structured)
    for (const int c : s) parent.emplace(c, c);
  for (const auto& [f, s] : structured) {
    for (int k = 0; k < 2; ++k) {
      const int a = find_root(parent, s[k]);
      const int b = find_root(parent, s[k + 2]);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  }
  std::map<int, double> longest;
  for (const auto& [c, p] : parent) {
    double length = 0.0;
    gmsh::model::occ::getMass(1, c, length);
    double& l = longest[find_root(parent, c)];
    l = std::max(l, length);
  }
  for (const auto& [c, p] : parent) {
    const double l = longest[find_root(parent, c)];
    const int segments = std::max(1, static_cast<int>(std::lround(l / size)));
    gmsh::model::mesh::setTransfiniteCurve(c, segments + 1);
  }
  for (const auto& [f, s] : structured) {
    gmsh::model::mesh::setTransfiniteSurface(f);
    gmsh::model::mesh::setRecombine(2, f);
  }
}

/// Meshes the boundary of the current model's volumes with the recipe of `options`.
/// `record` has path and format set; the model holds `volumes` (synchronised).
CadSurface mesh_current_model(const CadOptions& options, CadRecord record) {
  const auto t0 = std::chrono::steady_clock::now();
  if (options.triangle_algorithm != 1 && options.triangle_algorithm != 5 &&
      options.triangle_algorithm != 6) {
    throw InvalidInput("Gmsh triangle algorithm " + std::to_string(options.triangle_algorithm) +
                       " is not one the CAD front end uses: give 1 (MeshAdapt), 5 (Delaunay) or "
                       "6 (Frontal-Delaunay)");
  }
  gmsh::vectorpair volumes;
  gmsh::model::getEntities(volumes, 3);
  gmsh::vectorpair all_faces;
  gmsh::model::getEntities(all_faces, 2);
  if (volumes.empty()) {
    if (all_faces.empty()) {
      throw InvalidInput(record.path +
                         ": holds no shape at all (no solid, no face); check the "
                         "file is a CAD export of a solid");
    }
    throw InvalidInput(record.path + ": not a closed solid: it holds " +
                       std::to_string(all_faces.size()) +
                       " faces and no volume, and sewing them makes no closed shell (an open "
                       "shell or loose faces); export the part as a solid");
  }
  if (volumes.size() > 1) {
    // Solids of an assembly touch without sharing their faces (a STEP file keeps each
    // solid's own copy): make the model conforming, so that the boundary of the union below
    // leaves the faces between two solids out instead of meshing both copies.
    try {
      gmsh::model::occ::removeAllDuplicates();
      gmsh::model::occ::synchronize();
    } catch (...) {
      throw InvalidInput(record.path + ": Gmsh could not merge its " +
                         std::to_string(volumes.size()) + " solids into one: " + gmsh_reason() +
                         "; export the part as one solid");
    }
    gmsh::model::getEntities(volumes, 3);
  }
  record.volumes = volumes.size();
  if (options.split && options.recipe != CadRecipe::TriangleSplit) {
    const cad_detail::SplitResult split =
        cad_detail::split_into_blocks(volumes, bbox_diagonal(volumes), [](int face) {
          std::array<int, 4> sides{};
          std::string why;
          return four_sides(face, sides, why);
        });
    record.split = split.how;
    if (!split.dropped.empty())
      record.warnings.push_back("not split into blocks: " + split.dropped);
    if (!split.how.empty()) gmsh::model::getEntities(volumes, 3);
  }
  // The boundary of the union of the volumes (faces between two volumes are left out).
  gmsh::vectorpair boundary;
  gmsh::model::getBoundary(volumes, boundary, true, false, false);
  std::vector<int> faces;
  for (const auto& [d, t] : boundary) faces.push_back(std::abs(t));
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  record.faces = faces.size();
  {
    std::vector<int> curves;
    for (const int f : faces)
      for (const int c : face_curves(f)) curves.push_back(c);
    std::sort(curves.begin(), curves.end());
    record.curves = static_cast<std::size_t>(
        std::distance(curves.begin(), std::unique(curves.begin(), curves.end())));
  }
  const double diagonal = bbox_diagonal(volumes);
  record.size = options.size > 0.0 ? options.size : diagonal / 10.0;
  if (!std::isfinite(record.size) || record.size <= 0.0) {
    throw InvalidInput(record.path + ": cannot choose a mesh size (bounding box diagonal " +
                       std::to_string(diagonal) + "); give --size");
  }
  if (diagonal / record.size > 2000.0) {
    throw InvalidInput(record.path + ": --size " + std::to_string(record.size) +
                       " is too small for a solid of diagonal " + std::to_string(diagonal) +
                       " (more than 2000 edges across); give a larger size");
  }

  set_common_options(options);
  // Which faces have four corners, and the first that has not (the reason for the record).
  std::map<int, std::array<int, 4> > four_cornered;
  std::string not_four;
  for (const int f : faces) {
    std::array<int, 4> sides{};
    std::string why;
    if (four_sides(f, sides, why)) {
      four_cornered.emplace(f, sides);
    } else if (not_four.empty()) {
      not_four = why;
    }
  }
  const bool all_four = four_cornered.size() == faces.size();
  if (options.recipe == CadRecipe::Transfinite && !all_four) {
    throw Unsupported(record.path +
                      ": the transfinite recipe needs every CAD face to have 4 "
                      "corners, but " +
                      not_four + "; use --cad-recipe triangle-split, mixed or auto");
  }

  CadSurface out;
  std::vector<std::array<std::size_t, 4> > quads;
  std::set<int> structured;  // faces meshed structured in the current attempt
  // Generates the surface mesh with the options set; returns why it failed ("" when every
  // element of the boundary faces is a quad), with the quads in `quads`.
  const auto generate = [&]() -> std::string {
    quads.clear();
    record.triangles = 0;
    take_log();
    // Gmsh meshes the faces inside an OpenMP region, where an error it throws (its default,
    // General.AbortOnError 2) cannot be caught and ends the process ("Impossible to mesh
    // periodic surface" on a hollow torus): while it meshes, it only logs errors, and the log
    // is read below. Its own setting comes back after.
    double abort_on_error = 2;
    gmsh::option::getNumber("General.AbortOnError", abort_on_error);
    gmsh::option::setNumber("General.AbortOnError", 0);
    try {
      gmsh::model::mesh::generate(2);
    } catch (...) {
      gmsh::option::setNumber("General.AbortOnError", abort_on_error);
      const std::string reason = gmsh_reason();
      const GmshLog log = take_log();
      return reason + (log.errors.empty() ? "" : " [" + join(log.errors, "; ") + "]");
    }
    gmsh::option::setNumber("General.AbortOnError", abort_on_error);
    const GmshLog log = take_log();
    record.warnings.insert(record.warnings.end(), log.warnings.begin(), log.warnings.end());
    if (!log.errors.empty()) return join(log.errors, "; ");
    std::size_t non_quads = 0;
    for (const int f : faces) {
      std::vector<int> types;
      std::vector<std::vector<std::size_t> > element_tags;
      std::vector<std::vector<std::size_t> > node_tags;
      gmsh::model::mesh::getElements(types, element_tags, node_tags, 2, f);
      for (std::size_t k = 0; k < types.size(); ++k) {
        if (types[k] != 3) {  // 3: 4-node quadrangle
          non_quads += element_tags[k].size();
          continue;
        }
        if (structured.count(f) == 0) record.triangles += element_tags[k].size() / 3;
        // Sort by element tag so the order does not depend on Gmsh's internal storage.
        std::vector<std::size_t> order(element_tags[k].size());
        std::iota(order.begin(), order.end(), std::size_t{0});
        std::sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) {
          return element_tags[k][x] < element_tags[k][y];
        });
        for (const std::size_t e : order)
          quads.push_back({node_tags[k][4 * e], node_tags[k][4 * e + 1], node_tags[k][4 * e + 2],
                           node_tags[k][4 * e + 3]});
      }
    }
    if (non_quads > 0 || quads.empty()) {
      return std::to_string(non_quads) + " elements that are not quads were left on the " +
             "solid's boundary (" + std::to_string(quads.size()) + " quads)";
    }
    return "";
  };
  const auto fail = [&](const std::string& why) {
    return InvalidInput(record.path + ": Gmsh could not mesh the surface of the solid (" +
                        std::string(cad_recipe_name(record.recipe)) + " recipe, size " +
                        std::to_string(record.size) + "): " + why +
                        "; check the CAD model, or try another --size or --cad-recipe");
  };
  // Drops the mesh and every constraint, for the next attempt.
  const auto reset = [&] {
    gmsh::model::mesh::clear();
    gmsh::model::mesh::removeConstraints();
    structured.clear();
  };
  // Triangles at twice the size, every element then split (a triangle into three quads, a
  // quad of a structured face into four), so that the quads' edges are about the size.
  const auto split_options = [&] {
    gmsh::option::setNumber("Mesh.Algorithm", options.triangle_algorithm);
    gmsh::option::setNumber("Mesh.MeshSizeMax", 2.0 * record.size);
    gmsh::option::setNumber("Mesh.SubdivisionAlgorithm", 1);
  };

  CadRecipe recipe = options.recipe;
  if (recipe == CadRecipe::Auto) {
    recipe = all_four                ? CadRecipe::Transfinite
             : four_cornered.empty() ? CadRecipe::TriangleSplit
                                     : CadRecipe::Mixed;
  }
  if (recipe == CadRecipe::Mixed && four_cornered.empty()) recipe = CadRecipe::TriangleSplit;
  std::string split_reason =
      options.recipe == CadRecipe::TriangleSplit
          ? "asked for"
          : "not transfinite: " + not_four + ", and no CAD face has 4 corners";

  if (recipe == CadRecipe::Transfinite) {
    record.recipe = CadRecipe::Transfinite;
    record.reason = "every one of the " + std::to_string(faces.size()) + " CAD faces has 4 corners";
    if (!record.split.empty()) record.reason += " (" + record.split + ")";
    set_transfinite(four_cornered, record.size);
    for (const auto& [f, s] : four_cornered) structured.insert(f);
    gmsh::option::setNumber("Mesh.MeshSizeMax", record.size);
    if (const std::string why = generate(); !why.empty()) {
      if (options.recipe == CadRecipe::Transfinite) throw fail(why);
      // Auto: Gmsh could not make the faces transfinite after all; split triangles instead.
      record.warnings.push_back("transfinite meshing failed (" + why +
                                "): the surface was made with triangle-split instead");
      split_reason = "transfinite meshing failed: " + why;
      reset();
      recipe = CadRecipe::TriangleSplit;
    }
  }
  if (recipe == CadRecipe::Mixed) {
    record.recipe = CadRecipe::Mixed;
    set_transfinite(four_cornered, 2.0 * record.size);
    for (const auto& [f, s] : four_cornered) structured.insert(f);
    split_options();
    std::string why = generate();
    std::size_t crossing = 0;
    if (why.empty()) {
      // A loop leaving a structured face into a split one may come back across itself:
      // check, and split every face instead when one does.
      std::vector<std::size_t> used;
      for (const auto& q : quads) used.insert(used.end(), q.begin(), q.end());
      std::sort(used.begin(), used.end());
      used.erase(std::unique(used.begin(), used.end()), used.end());
      std::map<std::size_t, std::size_t> row;
      for (std::size_t i = 0; i < used.size(); ++i) row.emplace(used[i], i);
      MeshFile probe;
      probe.points.resize(static_cast<Eigen::Index>(used.size()), 3);
      for (std::size_t i = 0; i < used.size(); ++i) {
        std::vector<double> xyz;
        std::vector<double> uvw;
        gmsh::model::mesh::getNode(used[i], xyz, uvw);
        for (int k = 0; k < 3; ++k) probe.points(static_cast<Eigen::Index>(i), k) = xyz[k];
      }
      for (const auto& q : quads) {
        probe.quads.push_back({NodeId(row.at(q[0])), NodeId(row.at(q[1])), NodeId(row.at(q[2])),
                               NodeId(row.at(q[3]))});
      }
      const SurfaceDiagnosis d = diagnose(probe);
      crossing = d.self_intersecting_loops.value_or(0);
      if (crossing > 0) {
        why = std::to_string(crossing) + " self-intersecting loop(s)";
      } else if (options.recipe == CadRecipe::Auto && d.genus.value_or(0) > 0) {
        // A handle: no mixed surface tried has had a disc cut that weaves, while the
        // triangle-split one gets the tet interior, which needs no cut (docs/cad.md).
        why = "genus " + std::to_string(*d.genus) +
              ": a handle, which the tet interior of a triangle-split surface meshes without "
              "a cut";
      } else if (options.recipe == CadRecipe::Auto && d.components > record.volumes) {
        // A cavity: the same, for the annulus cut of a cavity (docs/topology.md).
        why = std::to_string(d.components) + " shells for " + std::to_string(record.volumes) +
              " solid(s): a cavity, which the tet interior of a triangle-split surface meshes "
              "without a cut";
      }
    }
    if (why.empty()) {
      record.reason = std::to_string(four_cornered.size()) + " of the " +
                      std::to_string(faces.size()) +
                      " CAD faces have 4 corners and are structured, the others split from "
                      "triangles (" +
                      not_four + "); checked loop-clean";
    } else {
      record.warnings.push_back("the mixed surface was dropped (" + why +
                                "): the surface was made with triangle-split instead");
      split_reason = "mixed surface dropped: " + why;
      reset();
      recipe = CadRecipe::TriangleSplit;
    }
  }
  if (recipe == CadRecipe::TriangleSplit) {
    record.recipe = CadRecipe::TriangleSplit;
    record.reason = split_reason;
    split_options();
    if (const std::string why = generate(); !why.empty()) throw fail(why);
  }
  record.structured_faces = structured.size();
  record.quads = quads.size();

  // Nodes used by the quads, numbered by increasing Gmsh tag; coordinates and the CAD
  // entity each is classified on (for the distance check).
  std::vector<std::size_t> used;
  for (const auto& q : quads) used.insert(used.end(), q.begin(), q.end());
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  std::map<std::size_t, std::size_t> row_of;
  for (std::size_t i = 0; i < used.size(); ++i) row_of.emplace(used[i], i);
  out.file.points.resize(static_cast<Eigen::Index>(used.size()), 3);
  std::vector<bool> seen(used.size(), false);
  double max_distance = 0.0;
  for (int dim = 0; dim <= 2; ++dim) {
    gmsh::vectorpair entities;
    gmsh::model::getEntities(entities, dim);
    for (const auto& [d, tag] : entities) {
      std::vector<std::size_t> tags;
      std::vector<double> coords;
      std::vector<double> params;
      gmsh::model::mesh::getNodes(tags, coords, params, d, tag, false, false);
      std::vector<double> mine;
      for (std::size_t i = 0; i < tags.size(); ++i) {
        const auto it = row_of.find(tags[i]);
        if (it == row_of.end()) continue;
        const auto r = static_cast<Eigen::Index>(it->second);
        for (int k = 0; k < 3; ++k) out.file.points(r, k) = coords[3 * i + k];
        seen[it->second] = true;
        mine.insert(mine.end(), coords.begin() + static_cast<std::ptrdiff_t>(3 * i),
                    coords.begin() + static_cast<std::ptrdiff_t>(3 * i + 3));
      }
      if (mine.empty()) continue;
      std::vector<double> closest;
      if (d == 0) {
        gmsh::model::getValue(0, tag, {}, closest);
        std::vector<double> repeated;
        for (std::size_t i = 0; i < mine.size() / 3; ++i)
          repeated.insert(repeated.end(), closest.begin(), closest.end());
        closest = repeated;
      } else {
        std::vector<double> closest_params;
        gmsh::model::getClosestPoint(d, tag, mine, closest, closest_params);
      }
      if (closest.size() != mine.size()) continue;
      for (std::size_t i = 0; i < mine.size(); i += 3) {
        const double dx = mine[i] - closest[i];
        const double dy = mine[i + 1] - closest[i + 1];
        const double dz = mine[i + 2] - closest[i + 2];
        max_distance = std::max(max_distance, std::sqrt(dx * dx + dy * dy + dz * dz));
      }
    }
  }
  const auto missing = std::find(seen.begin(), seen.end(), false);
  if (missing != seen.end()) {
    throw InternalError(record.path + ": Gmsh node " +
                        std::to_string(used[static_cast<std::size_t>(missing - seen.begin())]) +
                        " of the surface is on no CAD point, curve or face; this is a bug");
  }
  record.max_cad_distance = max_distance;
  record.nodes = used.size();

  out.file.path = record.path;
  out.file.format = record.format;
  out.file.quads.reserve(quads.size());
  for (const auto& q : quads) {
    out.file.quads.push_back({NodeId(row_of.at(q[0])), NodeId(row_of.at(q[1])),
                              NodeId(row_of.at(q[2])), NodeId(row_of.at(q[3]))});
  }
  out.file.quad_lines.assign(quads.size(), 0);
  out.file.notes.push_back("quad surface made by Gmsh " + record.gmsh_version + " (" +
                           std::string(cad_recipe_name(record.recipe)) + ", size " +
                           std::to_string(record.size) + ")");
  record.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  out.record = std::move(record);
  return out;
}

std::string gmsh_version() {
  std::string v;
  gmsh::option::getString("General.Version", v);
  return v;
}

/// An `a` x `b` x `c` plate with a hole of radius min(a, b) / 4 at its centre, as four blocks
/// cut along its diagonals (each block: a plate edge, two diagonal cuts, an arc of the hole),
/// made conforming by OpenCASCADE's fragment.
void add_plate_with_hole_blocks(double a, double b, double c) {
  namespace occ = gmsh::model::occ;
  const double cx = a / 2;
  const double cy = b / 2;
  const double radius = std::min(a, b) / 4;
  const std::array<std::array<double, 2>, 4> corners = {{{0.0, 0.0}, {a, 0.0}, {a, b}, {0.0, b}}};
  const int centre = occ::addPoint(cx, cy, 0);
  std::array<int, 4> corner{};
  std::array<int, 4> on_hole{};
  for (std::size_t k = 0; k < 4; ++k) {
    const double dx = corners[k][0] - cx;
    const double dy = corners[k][1] - cy;
    const double len = std::hypot(dx, dy);
    corner[k] = occ::addPoint(corners[k][0], corners[k][1], 0);
    on_hole[k] = occ::addPoint(cx + radius * dx / len, cy + radius * dy / len, 0);
  }
  std::array<int, 4> edge{};
  std::array<int, 4> cut{};
  std::array<int, 4> arc{};
  for (std::size_t k = 0; k < 4; ++k) {
    const std::size_t n = (k + 1) % 4;
    edge[k] = occ::addLine(corner[k], corner[n]);
    cut[k] = occ::addLine(on_hole[k], corner[k]);
    arc[k] = occ::addCircleArc(on_hole[k], centre, on_hole[n]);
  }
  gmsh::vectorpair pieces;
  for (std::size_t k = 0; k < 4; ++k) {
    const std::size_t n = (k + 1) % 4;
    const int loop = occ::addCurveLoop({edge[k], -cut[n], -arc[k], cut[k]});
    const int face = occ::addPlaneSurface({loop});
    gmsh::vectorpair extruded;
    occ::extrude({{2, face}}, 0, 0, c, extruded);
    for (const auto& dt : extruded)
      if (dt.first == 3) pieces.push_back(dt);
  }
  gmsh::vectorpair out;
  std::vector<gmsh::vectorpair> map;
  occ::fragment({pieces.front()}, gmsh::vectorpair(pieces.begin() + 1, pieces.end()), out, map);
}

/// Runs `body` with the Gmsh session locked, a fresh model and the logger on; always
/// clears the model afterwards.
template <typename Body>
CadSurface with_gmsh(const CadOptions& options, Body body) {
  GmshSession& session = GmshSession::instance();
  const std::lock_guard<std::mutex> lock(session.mutex);
  const StdoutToStderr redirect(options.verbose);
  gmsh::clear();
  set_common_options(options);
  gmsh::logger::start();
  struct Cleanup {
    Cleanup() = default;
    Cleanup(const Cleanup&) = delete;
    Cleanup& operator=(const Cleanup&) = delete;
    Cleanup(Cleanup&&) = delete;
    Cleanup& operator=(Cleanup&&) = delete;
    ~Cleanup() {
      try {
        gmsh::logger::stop();
        gmsh::clear();
      } catch (...) {  // NOLINT(bugprone-empty-catch): already failing or done
      }
    }
  } cleanup;
  return body();
}

}  // namespace

CadSurface mesh_cad_surface(const std::filesystem::path& path, const CadOptions& options) {
  const std::string format = cad_format_of(path);
  if (format.empty()) {
    throw InvalidInput(path.string() +
                       ": not a CAD file by its extension; CAD inputs are .step, .stp, .brep, "
                       ".iges, .igs");
  }
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw IoError("cannot open " + path.string() + ": no such file");
  }
  if (std::ifstream probe(path); !probe) {
    throw IoError("cannot open " + path.string() + ": check it is readable");
  }
  const auto t0 = std::chrono::steady_clock::now();
  return with_gmsh(options, [&] {
    CadRecord record;
    record.path = path.string();
    record.format = format;
    record.gmsh_version = gmsh_version();
    gmsh::vectorpair imported;
    {
      StdoutCapture capture(!options.verbose);
      try {
        gmsh::model::occ::importShapes(path.string(), imported, true, format);
        gmsh::model::occ::synchronize();
      } catch (...) {
        const std::string reason = gmsh_reason();
        const std::vector<std::string> printed = capture.lines();
        std::vector<std::string> occ;
        for (const std::string& l : printed)
          if (l.find("ERR") != std::string::npos || l.find("rror") != std::string::npos)
            occ.push_back(l);
        throw InvalidInput(path.string() + ": Gmsh cannot read it as " + format + ": " + reason +
                           (occ.empty() ? "" : " (OpenCASCADE: " + join(occ, "; ") + ")") +
                           "; check it is a valid " + format + " file of a solid");
      }
    }
    take_log();
    // Files that hold faces but no solid (IGES files usually do, some STEP exporters too):
    // read again, sewing the faces and making solids of the closed shells. An open shell
    // stays without a volume and is refused below.
    gmsh::vectorpair volumes;
    gmsh::vectorpair faces;
    gmsh::model::getEntities(volumes, 3);
    gmsh::model::getEntities(faces, 2);
    if (volumes.empty() && !faces.empty()) {
      gmsh::clear();
      gmsh::option::setNumber("Geometry.OCCSewFaces", 1);
      gmsh::option::setNumber("Geometry.OCCMakeSolids", 1);
      try {
        const StdoutCapture quiet(!options.verbose);
        gmsh::model::occ::importShapes(path.string(), imported, true, format);
        gmsh::model::occ::synchronize();
      } catch (...) {
        throw InvalidInput(path.string() + ": Gmsh could not sew its " +
                           std::to_string(faces.size()) + " faces into a solid: " + gmsh_reason() +
                           "; export the part as a solid");
      }
      gmsh::option::setNumber("Geometry.OCCSewFaces", 0);
      gmsh::option::setNumber("Geometry.OCCMakeSolids", 0);
      take_log();
      gmsh::model::getEntities(volumes, 3);
      if (!volumes.empty()) {
        record.warnings.push_back("the file holds " + std::to_string(faces.size()) +
                                  " faces and no solid: they were sewn into " +
                                  std::to_string(volumes.size()) + " solid(s)");
      }
    }
    record.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return mesh_current_model(options, std::move(record));
  });
}

CadSurface mesh_cad_surface(const CadPrimitive& primitive, const CadOptions& options) {
  if (!(primitive.a > 0.0) || !(primitive.b > 0.0) || !(primitive.c > 0.0) ||
      !std::isfinite(primitive.a) || !std::isfinite(primitive.b) || !std::isfinite(primitive.c)) {
    throw InvalidInput("a CAD primitive needs positive, finite dimensions");
  }
  if ((primitive.kind == CadPrimitive::Kind::Torus ||
       primitive.kind == CadPrimitive::Kind::TorusBlocks) &&
      !(primitive.b < primitive.a)) {
    throw InvalidInput("a CAD torus needs its tube radius b below its radius a");
  }
  const auto t0 = std::chrono::steady_clock::now();
  return with_gmsh(options, [&] {
    CadRecord record;
    record.format = "occ";
    record.gmsh_version = gmsh_version();
    const double a = primitive.a;
    const double b = primitive.b;
    const double c = primitive.c;
    try {
      switch (primitive.kind) {
        case CadPrimitive::Kind::Box:
          record.path = "generated box";
          gmsh::model::occ::addBox(0, 0, 0, a, b, c);
          break;
        case CadPrimitive::Kind::Cylinder:
          record.path = "generated cylinder";
          gmsh::model::occ::addCylinder(0, 0, 0, 0, 0, b, a);
          break;
        case CadPrimitive::Kind::Sphere:
          record.path = "generated sphere";
          gmsh::model::occ::addSphere(0, 0, 0, a);
          break;
        case CadPrimitive::Kind::LBlock: {
          record.path = "generated L-block";
          const int whole = gmsh::model::occ::addBox(0, 0, 0, a, b, c);
          const int corner = gmsh::model::occ::addBox(a / 2, b / 2, 0, a / 2, b / 2, c);
          gmsh::vectorpair out;
          std::vector<gmsh::vectorpair> map;
          gmsh::model::occ::cut({{3, whole}}, {{3, corner}}, out, map);
          break;
        }
        case CadPrimitive::Kind::LBlockBlocks: {
          record.path = "generated L-block of three blocks";
          const int first = gmsh::model::occ::addBox(0, 0, 0, a / 2, b / 2, c);
          const int second = gmsh::model::occ::addBox(a / 2, 0, 0, a / 2, b / 2, c);
          const int third = gmsh::model::occ::addBox(0, b / 2, 0, a / 2, b / 2, c);
          gmsh::vectorpair out;
          std::vector<gmsh::vectorpair> map;
          gmsh::model::occ::fragment({{3, first}}, {{3, second}, {3, third}}, out, map);
          break;
        }
        case CadPrimitive::Kind::PlateWithHole: {
          record.path = "generated plate with a hole";
          const int plate = gmsh::model::occ::addBox(0, 0, 0, a, b, c);
          const int hole =
              gmsh::model::occ::addCylinder(a / 2, b / 2, -c, 0, 0, 3 * c, std::min(a, b) / 4);
          gmsh::vectorpair out;
          std::vector<gmsh::vectorpair> map;
          gmsh::model::occ::cut({{3, plate}}, {{3, hole}}, out, map);
          break;
        }
        case CadPrimitive::Kind::PlateWithHoleBlocks:
          record.path = "generated plate with a hole of four blocks";
          add_plate_with_hole_blocks(a, b, c);
          break;
        case CadPrimitive::Kind::Torus:
          record.path = "generated torus";
          gmsh::model::occ::addTorus(0, 0, 0, a, b);
          break;
        case CadPrimitive::Kind::TorusBlocks:
          record.path = "generated torus of 20 blocks";
          (void)cad_detail::add_torus_blocks(a, b);
          break;
      }
      gmsh::model::occ::synchronize();
    } catch (...) {
      throw InvalidInput("Gmsh could not build the " + record.path + ": " + gmsh_reason());
    }
    take_log();
    record.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return mesh_current_model(options, std::move(record));
  });
}

#endif

}  // namespace stcweave::primal
