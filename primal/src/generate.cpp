#include "stcweave/primal/generate.hpp"

#include <array>

#include "stcweave/primal/diagnose.hpp"
#include "stcweave/primal/quality.hpp"
#include "stcweave/stc/errors.hpp"

namespace stcweave::primal {
namespace {

/// Per section i = 0..3 of a Fig. 5 bar: its outer and inner points in the (x, z) plane;
/// the section is swept over y in [0, width].
struct BarSections {
  std::array<std::array<double, 2>, 4> outer;
  std::array<std::array<double, 2>, 4> inner;
  double width = 1.0;
};

BarSections sections_of(BarShape shape) {
  switch (shape) {
    case BarShape::Straight:
      return {{{{0, 0}, {0, 1}, {0, 2}, {0, 3}}}, {{{1, 0}, {1, 1}, {1, 2}, {1, 3}}}, 1.0};
    case BarShape::L:
      return {{{{0, 0}, {0, 2}, {2, 2}, {3, 2}}}, {{{1, 0}, {1, 1}, {2, 1}, {3, 1}}}, 1.0};
    case BarShape::U:
      return {{{{0, 3}, {0, 0}, {3, 0}, {3, 3}}}, {{{1, 3}, {1, 1}, {2, 1}, {2, 3}}}, 1.0};
    case BarShape::Plate:
      return {{{{0, 0}, {2, 0}, {4, 0}, {6, 0}}}, {{{0, 1}, {2, 1}, {4, 1}, {6, 1}}}, 6.0};
  }
  throw InternalError("bar_hexes: unknown bar shape");
}

}  // namespace

HexMesh box_hexes(int a, int b, int c) {
  for (int n : {a, b, c}) {
    if (n < 1 || n > kMaxBoxSide) {
      throw InvalidInput("box " + std::to_string(a) + " x " + std::to_string(b) + " x " +
                         std::to_string(c) + ": every side must be between 1 and " +
                         std::to_string(kMaxBoxSide));
    }
  }
  const auto id = [&](int i, int j, int k) {
    return NodeId(static_cast<std::size_t>(i + (a + 1) * (j + (b + 1) * k)));
  };
  HexMesh mesh;
  mesh.complex.num_nodes = static_cast<std::size_t>(a + 1) * static_cast<std::size_t>(b + 1) *
                           static_cast<std::size_t>(c + 1);
  mesh.points.resize(static_cast<Eigen::Index>(mesh.complex.num_nodes), 3);
  for (int k = 0; k <= c; ++k) {
    for (int j = 0; j <= b; ++j)
      for (int i = 0; i <= a; ++i)
        mesh.points.row(static_cast<Eigen::Index>(id(i, j, k).index())) << i, j, k;
  }
  mesh.complex.hexes.reserve(static_cast<std::size_t>(a) * static_cast<std::size_t>(b) *
                             static_cast<std::size_t>(c));
  for (int k = 0; k < c; ++k) {
    for (int j = 0; j < b; ++j) {
      for (int i = 0; i < a; ++i) {
        mesh.complex.hexes.push_back({id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k),
                                      id(i, j + 1, k), id(i, j, k + 1), id(i + 1, j, k + 1),
                                      id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)});
      }
    }
  }
  return mesh;
}

SurfaceMesh box_surface(int a, int b, int c) {
  return boundary_mesh(box_hexes(a, b, c));
}

std::vector<std::string> bar_shape_names() {
  return {"straight", "l", "u", "plate"};
}

BarShape bar_shape_from_name(std::string_view name) {
  const std::vector<std::string> names = bar_shape_names();
  for (std::size_t i = 0; i < names.size(); ++i)
    if (name == names[i]) return static_cast<BarShape>(i);
  std::string list;
  for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
  throw InvalidInput("unknown bar shape '" + std::string(name) + "'; use one of: " + list);
}

HexMesh bar_hexes(BarShape shape) {
  const BarSections s = sections_of(shape);
  HexMesh mesh;
  mesh.complex.num_nodes = 16;
  mesh.points.resize(16, 3);
  for (std::size_t i = 0; i < 4; ++i) {
    const auto row = [&](std::size_t j) { return static_cast<Eigen::Index>(4 * i + j); };
    mesh.points.row(row(0)) << s.outer[i][0], 0.0, s.outer[i][1];
    mesh.points.row(row(1)) << s.inner[i][0], 0.0, s.inner[i][1];
    mesh.points.row(row(2)) << s.inner[i][0], s.width, s.inner[i][1];
    mesh.points.row(row(3)) << s.outer[i][0], s.width, s.outer[i][1];
  }
  const auto n = [](std::size_t i, std::size_t j) { return NodeId(4 * i + j); };
  for (std::size_t i = 0; i < 3; ++i) {
    stc::Hex h = {n(i, 0),     n(i, 1),     n(i, 2),     n(i, 3),
                  n(i + 1, 0), n(i + 1, 1), n(i + 1, 2), n(i + 1, 3)};
    if (hex_scaled_jacobian(mesh.points, h) < 0.0)
      h = {n(i, 0), n(i, 3), n(i, 2), n(i, 1), n(i + 1, 0), n(i + 1, 3), n(i + 1, 2), n(i + 1, 1)};
    if (!(hex_scaled_jacobian(mesh.points, h) > 0.0))
      throw InternalError("bar_hexes: hex " + std::to_string(i) + " is not convex (a bug)");
    mesh.complex.hexes.push_back(h);
  }
  return mesh;
}

SurfaceMesh bar_surface(BarShape shape) {
  return boundary_mesh(bar_hexes(shape));
}

ShapeSpec parse_shape_spec(std::string_view spec) {
  const auto bad = [&](const std::string& why) {
    return InvalidInput("shape '" + std::string(spec) + "': " + why +
                        "; write box:AxBxC (e.g. box:8x8x8) or bar:SHAPE (e.g. bar:l)");
  };
  ShapeSpec out;
  if (spec.rfind("bar:", 0) == 0) {
    out.kind = ShapeSpec::Kind::Bar;
    try {
      out.bar = bar_shape_from_name(spec.substr(4));
    } catch (const InvalidInput& e) {
      throw bad(e.what());
    }
    return out;
  }
  if (spec.rfind("box:", 0) != 0) throw bad("unknown kind of shape");
  std::array<int, 3> sides{};
  std::string_view rest = spec.substr(4);
  for (std::size_t i = 0; i < 3; ++i) {
    const std::size_t end = i < 2 ? rest.find('x') : rest.size();
    if (end == std::string_view::npos) throw bad("three sides separated by 'x' are needed");
    const std::string_view digits = rest.substr(0, end);
    if (digits.empty() || digits.size() > 4 ||
        digits.find_first_not_of("0123456789") != std::string_view::npos)
      throw bad("side '" + std::string(digits) + "' is not a whole number");
    sides[i] = std::stoi(std::string(digits));
    if (sides[i] < 1 || sides[i] > kMaxBoxSide)
      throw bad("every side must be between 1 and " + std::to_string(kMaxBoxSide));
    rest = i < 2 ? rest.substr(end + 1) : std::string_view{};
  }
  out.a = sides[0];
  out.b = sides[1];
  out.c = sides[2];
  return out;
}

std::string to_string(const ShapeSpec& spec) {
  if (spec.kind == ShapeSpec::Kind::Bar)
    return "bar:" + bar_shape_names().at(static_cast<std::size_t>(spec.bar));
  return "box:" + std::to_string(spec.a) + "x" + std::to_string(spec.b) + "x" +
         std::to_string(spec.c);
}

HexMesh shape_hexes(const ShapeSpec& spec) {
  return spec.kind == ShapeSpec::Kind::Bar ? bar_hexes(spec.bar)
                                           : box_hexes(spec.a, spec.b, spec.c);
}

SurfaceMesh boundary_mesh(const HexMesh& mesh) {
  MeshFile file;
  file.path = "generated";
  file.format = "generated";
  file.points = mesh.points;
  file.hexes = mesh.complex.hexes;
  return surface_of(file);
}

}  // namespace stcweave::primal
