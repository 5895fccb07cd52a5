// Compiled with Gmsh only (STCWEAVE_HAVE_GMSH, set on this file and cad.cpp by CMake).
#if STCWEAVE_HAVE_GMSH
#include "cad_split.hpp"

#include "gmsh_session.hpp"

#include <gmsh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <exception>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "stcweave/stc/errors.hpp"

namespace stcweave::primal::cad_detail {
namespace {

namespace occ = gmsh::model::occ;
using Vec = std::array<double, 3>;

const double kPi = std::acos(-1.0);

Vec sub(const Vec& a, const Vec& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
double norm(const Vec& a) {
  return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
}

Vec add(const Vec& a, const Vec& b) {
  return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
Vec scaled(const Vec& a, double s) {
  return {s * a[0], s * a[1], s * a[2]};
}
double dot(const Vec& a, const Vec& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
Vec cross(const Vec& a, const Vec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

bool near(double value, double expected, double relative) {
  return std::abs(value - expected) <= relative * std::max(std::abs(expected), 1e-300);
}

Vec centre_of(int dim, int tag) {
  Vec c{};
  occ::getCenterOfMass(dim, tag, c[0], c[1], c[2]);
  return c;
}

double mass_of(int dim, int tag) {
  double m = 0.0;
  occ::getMass(dim, tag, m);
  return m;
}

std::set<std::pair<int, int> > occ_entities() {
  gmsh::vectorpair all;
  occ::getEntities(all, -1);
  return {all.begin(), all.end()};
}

/// Removes every OpenCASCADE entity made since `before` (volumes first), synchronised.
void remove_new(const std::set<std::pair<int, int> >& before) {
  gmsh::vectorpair all;
  occ::getEntities(all, -1);
  for (int dim = 3; dim >= 0; --dim) {
    gmsh::vectorpair made;
    for (const auto& dt : all)
      if (dt.first == dim && before.count(dt) == 0) made.push_back(dt);
    if (!made.empty()) occ::remove(made, false);
  }
  occ::synchronize();
}

/// The faces of the boundary of the union of `volumes` (faces between two of them left out).
std::vector<int> union_faces(const gmsh::vectorpair& volumes) {
  gmsh::vectorpair boundary;
  gmsh::model::getBoundary(volumes, boundary, true, false, false);
  std::vector<int> faces;
  for (const auto& [d, t] : boundary) faces.push_back(std::abs(t));
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  return faces;
}

gmsh::vectorpair volumes_of(const gmsh::vectorpair& dim_tags) {
  gmsh::vectorpair out;
  for (const auto& dt : dim_tags)
    if (dt.first == 3) out.push_back(dt);
  return out;
}

}  // namespace

gmsh::vectorpair add_ogrid_section(double r,
                                   const std::function<std::array<double, 3>(double, double)>& at) {
  const double half = r / 2.5;
  const double diagonal = r / std::sqrt(2.0);
  const std::array<std::array<double, 2>, 4> directions = {
      {{1.0, -1.0}, {1.0, 1.0}, {-1.0, 1.0}, {-1.0, -1.0}}};
  const auto point = [&](double u, double v) {
    const std::array<double, 3> x = at(u, v);
    return occ::addPoint(x[0], x[1], x[2]);
  };
  const int centre = point(0, 0);
  std::array<int, 4> core{};
  std::array<int, 4> rim{};
  for (std::size_t k = 0; k < 4; ++k) {
    core[k] = point(half * directions[k][0], half * directions[k][1]);
    rim[k] = point(diagonal * directions[k][0], diagonal * directions[k][1]);
  }
  std::array<int, 4> side{};
  std::array<int, 4> cut{};
  std::array<int, 4> arc{};
  for (std::size_t k = 0; k < 4; ++k) {
    const std::size_t n = (k + 1) % 4;
    side[k] = occ::addLine(core[k], core[n]);
    cut[k] = occ::addLine(core[k], rim[k]);
    arc[k] = occ::addCircleArc(rim[k], centre, rim[n]);
  }
  gmsh::vectorpair section;
  section.emplace_back(
      2, occ::addPlaneSurface({occ::addCurveLoop({side[0], side[1], side[2], side[3]})}));
  for (std::size_t k = 0; k < 4; ++k) {
    const std::size_t n = (k + 1) % 4;
    section.emplace_back(
        2, occ::addPlaneSurface({occ::addCurveLoop({side[k], cut[n], -arc[k], -cut[k]})}));
  }
  return section;
}

gmsh::vectorpair add_torus_blocks(double major, double minor) {
  // The tube's section in the plane y = 0 around (major, 0, 0): (u, v) = (x - major, z).
  const gmsh::vectorpair section = add_ogrid_section(minor, [major](double u, double v) {
    return std::array<double, 3>{major + u, 0, v};
  });
  // Four quarter turns, each swept from the end faces of the one before (Gmsh lists each
  // swept entity's end just before its volume), so that consecutive quarters share their
  // faces; only the last quarter's end, which lies on the first section, is glued by
  // fragment, of the first and the last quarter alone (a fragment of all 20 blocks took six
  // times as long: OpenCASCADE's booleans on surfaces of revolution are slow).
  const double quarter = kPi / 2;
  gmsh::vectorpair from = section;
  std::vector<gmsh::vectorpair> quarters;
  for (int turn = 0; turn < 4; ++turn) {
    gmsh::vectorpair swept;
    occ::revolve(from, 0, 0, 0, 0, 0, 1, quarter, swept);
    gmsh::vectorpair ends;
    gmsh::vectorpair blocks;
    for (std::size_t i = 1; i < swept.size(); ++i) {
      if (swept[i].first == 3) {
        blocks.push_back(swept[i]);
        ends.push_back(swept[i - 1]);
      }
    }
    quarters.push_back(blocks);
    from = ends;
  }
  gmsh::vectorpair out;
  std::vector<gmsh::vectorpair> map;
  occ::fragment(quarters.front(), quarters.back(), out, map);
  gmsh::vectorpair all = volumes_of(out);
  for (std::size_t turn = 1; turn + 1 < quarters.size(); ++turn)
    all.insert(all.end(), quarters[turn].begin(), quarters[turn].end());
  return all;
}

namespace {
/// An O-grid cylinder of radius `r` and height `h` along z from the origin: a square core of
/// half side r / 2.5 and four ring pieces (a core side, two diagonal cuts, a quarter of the
/// circle), extruded and made conforming. Returns the blocks.
gmsh::vectorpair add_ogrid_cylinder(double r, double h) {
  const gmsh::vectorpair section = add_ogrid_section(r, [](double u, double v) {
    return std::array<double, 3>{u, v, 0};
  });
  gmsh::vectorpair extruded;
  occ::extrude(section, 0, 0, h, extruded);
  const gmsh::vectorpair blocks = volumes_of(extruded);
  gmsh::vectorpair out;
  std::vector<gmsh::vectorpair> map;
  occ::fragment({blocks.front()}, gmsh::vectorpair(blocks.begin() + 1, blocks.end()), out, map);
  return volumes_of(out);
}

/// A cubed sphere of radius `r` at the origin: a core cube of half side r / 2.5 and six
/// pieces, each the ball cut by the pyramid from the centre through one face of the cube.
/// Each piece gets its own ball, turned so that the sphere's poles and seam (OpenCASCADE
/// puts the poles on z and the seam through +x) fall outside it: otherwise the seam stays
/// in the piece's face, which then has more than four curve uses.
gmsh::vectorpair add_cubed_sphere(double r) {
  const double h = r / 2.5;
  const double big = 2.0 * r;
  const int apex = occ::addPoint(0, 0, 0);
  std::array<int, 4> base{};
  const std::array<std::array<double, 2>, 4> uv = {
      {{-1.0, -1.0}, {1.0, -1.0}, {1.0, 1.0}, {-1.0, 1.0}}};
  for (std::size_t k = 0; k < 4; ++k) base[k] = occ::addPoint(big * uv[k][0], big * uv[k][1], big);
  std::array<int, 4> rim{};
  std::array<int, 4> spoke{};
  for (std::size_t k = 0; k < 4; ++k) {
    rim[k] = occ::addLine(base[k], base[(k + 1) % 4]);
    spoke[k] = occ::addLine(apex, base[k]);
  }
  std::vector<int> faces = {
      occ::addPlaneSurface({occ::addCurveLoop({rim[0], rim[1], rim[2], rim[3]})})};
  for (std::size_t k = 0; k < 4; ++k) {
    faces.push_back(
        occ::addPlaneSurface({occ::addCurveLoop({spoke[k], rim[k], -spoke[(k + 1) % 4]})}));
  }
  const std::pair<int, int> pyramid{3, occ::addVolume({occ::addSurfaceLoop(faces)})};
  // The six directions: +z, quarter turns about x and y, the half turn about x.
  struct Turn {
    double x, y, z, angle;
  };
  const std::array<Turn, 6> turns = {{{0, 0, 1, 0.0},
                                      {1, 0, 0, kPi / 2},
                                      {1, 0, 0, -kPi / 2},
                                      {0, 1, 0, kPi / 2},
                                      {0, 1, 0, -kPi / 2},
                                      {1, 0, 0, kPi}}};
  gmsh::vectorpair pieces;
  for (const Turn& t : turns) {
    gmsh::vectorpair p;
    occ::copy({pyramid}, p);
    const int ball = occ::addSphere(0, 0, 0, r);
    // Poles on x, seam through -z: the +z piece holds neither.
    occ::rotate({{3, ball}}, 0, 0, 0, 0, 1, 0, kPi / 2);
    gmsh::vectorpair both = p;
    both.emplace_back(3, ball);
    if (t.angle != 0.0) occ::rotate(both, 0, 0, 0, t.x, t.y, t.z, t.angle);
    gmsh::vectorpair out;
    std::vector<gmsh::vectorpair> map;
    occ::intersect({{3, ball}}, p, out, map);
    const gmsh::vectorpair v = volumes_of(out);
    pieces.insert(pieces.end(), v.begin(), v.end());
  }
  occ::remove({pyramid}, true);
  const int core = occ::addBox(-h, -h, -h, 2 * h, 2 * h, 2 * h);
  gmsh::vectorpair outer;
  std::vector<gmsh::vectorpair> map;
  occ::cut(pieces, {{3, core}}, outer, map, -1, true, false);
  gmsh::vectorpair out;
  occ::fragment({{3, core}}, volumes_of(outer), out, map);
  return volumes_of(out);
}

/// Turns and moves `blocks` (built along z from the origin) so that z goes along `axis`
/// (unit) and the origin to `origin`.
void place(const gmsh::vectorpair& blocks, const Vec& axis, const Vec& origin) {
  const Vec turn = {-axis[1], axis[0], 0.0};  // z x axis
  const double s = norm(turn);
  const double angle = std::atan2(s, axis[2]);
  if (s > 1e-12) {
    occ::rotate(blocks, 0, 0, 0, turn[0], turn[1], turn[2], angle);
  } else if (axis[2] < 0) {
    occ::rotate(blocks, 0, 0, 0, 1, 0, 0, kPi);
  }
  occ::translate(blocks, origin[0], origin[1], origin[2]);
}

/// Gmsh's type names of `faces`, sorted.
std::vector<std::string> types_of(int dim, const std::vector<int>& tags) {
  std::vector<std::string> types;
  for (const int t : tags) {
    std::string type;
    gmsh::model::getType(dim, t, type);
    types.push_back(type);
  }
  std::sort(types.begin(), types.end());
  return types;
}

/// The parameters of a right circular cylinder when the solid is one: base centre, unit
/// axis, radius and height. Checked on the masses: the two discs have equal areas pi r^2,
/// the side 2 pi r h, the volume pi r^2 h (1e-6 relative).
bool is_cylinder(int volume, const std::vector<int>& faces, Vec& base, Vec& axis, double& r,
                 double& h) {
  if (faces.size() != 3) return false;
  if (types_of(2, faces) != std::vector<std::string>{"Cylinder", "Plane", "Plane"}) return false;
  std::vector<int> discs;
  int side = 0;
  for (const int f : faces) {
    std::string type;
    gmsh::model::getType(2, f, type);
    if (type == "Plane") {
      discs.push_back(f);
    } else {
      side = f;
    }
  }
  const double a0 = mass_of(2, discs[0]);
  const double a1 = mass_of(2, discs[1]);
  if (!near(a1, a0, 1e-6)) return false;
  r = std::sqrt(a0 / kPi);
  base = centre_of(2, discs[0]);
  const Vec top = centre_of(2, discs[1]);
  const Vec d = sub(top, base);
  h = norm(d);
  if (!(h > 0.0) || !(r > 0.0)) return false;
  axis = {d[0] / h, d[1] / h, d[2] / h};
  return near(mass_of(2, side), 2 * kPi * r * h, 1e-6) &&
         near(mass_of(3, volume), kPi * r * r * h, 1e-6);
}

/// Centre and radius of a sphere when the solid is one (one spherical face; area 4 pi r^2,
/// volume 4/3 pi r^3).
bool is_sphere(int volume, const std::vector<int>& faces, Vec& centre, double& r) {
  if (faces.size() != 1 || types_of(2, faces) != std::vector<std::string>{"Sphere"}) return false;
  r = std::sqrt(mass_of(2, faces[0]) / (4 * kPi));
  centre = centre_of(3, volume);
  return r > 0.0 && near(mass_of(3, volume), 4.0 / 3.0 * kPi * r * r * r, 1e-6);
}

/// A planar quadrilateral through the four corners.
std::pair<int, int> add_quad(const std::array<Vec, 4>& corners) {
  std::array<int, 4> p{};
  for (std::size_t k = 0; k < 4; ++k)
    p[k] = occ::addPoint(corners[k][0], corners[k][1], corners[k][2]);
  std::vector<int> lines;
  for (std::size_t k = 0; k < 4; ++k) lines.push_back(occ::addLine(p[k], p[(k + 1) % 4]));
  return {2, occ::addPlaneSurface({occ::addCurveLoop(lines)})};
}

/// Centre, unit axis and radii of a torus when the solid is one (one toroidal face). The
/// tube radius is 2 V / A and the centre-line radius A / (4 pi^2 r) (area A = 4 pi^2 R r,
/// volume V = 2 pi^2 R r^2); the matrix of inertia about the centre of mass (density 1) is
/// then V (R^2 / 2 + 5 r^2 / 8) across the axis plus V (R^2 / 2 + r^2 / 8) along it, which
/// gives the axis and is checked entry by entry (1e-6 of the largest moment).
bool is_torus(int volume, const std::vector<int>& faces, Vec& centre, Vec& axis, double& major,
              double& minor) {
  if (faces.size() != 1 || types_of(2, faces) != std::vector<std::string>{"Torus"}) return false;
  const double area = mass_of(2, faces[0]);
  const double v = mass_of(3, volume);
  if (!(area > 0.0) || !(v > 0.0)) return false;
  minor = 2.0 * v / area;
  major = area / (4.0 * kPi * kPi * minor);
  if (!(minor < major)) return false;
  centre = centre_of(3, volume);
  std::vector<double> m;
  occ::getMatrixOfInertia(3, volume, m);
  if (m.size() != 9) return false;
  const double across = v * (major * major / 2 + 5.0 * minor * minor / 8);
  const double along = v * (major * major / 2 + minor * minor / 8);  // the axial moment less across
  // m - across I = along a a^T: the axis is its largest column, normalised.
  std::size_t k = 0;
  for (std::size_t i = 1; i < 3; ++i)
    if (m[4 * i] > m[4 * k]) k = i;
  Vec col = {m[k], m[3 + k], m[6 + k]};
  col[k] -= across;
  const double n = norm(col);
  if (!(n > 0.0)) return false;
  axis = scaled(col, 1.0 / n);
  const double tol = 1e-6 * (across + along);
  for (std::size_t i = 0; i < 3; ++i) {
    for (std::size_t j = 0; j < 3; ++j) {
      const double expected = (i == j ? across : 0.0) + along * axis[i] * axis[j];
      if (std::abs(m[3 * i + j] - expected) > tol) return false;
    }
  }
  return true;
}

/// Fragments `copy` (a copy of `volumes`) with the surfaces `tools` and removes the tools'
/// pieces outside the solid. Returns the blocks when every face of their union has four corners;
/// otherwise removes everything made since `before` and returns none.
gmsh::vectorpair cut_into_blocks(const gmsh::vectorpair& volumes, const gmsh::vectorpair& copy,
                                 const gmsh::vectorpair& tools,
                                 const std::set<std::pair<int, int> >& before,
                                 const std::function<bool(int)>& four_cornered) {
  gmsh::vectorpair out;
  std::vector<gmsh::vectorpair> map;
  occ::fragment(copy, tools, out, map);
  occ::synchronize();
  // The pieces of the tools outside the solid bound no volume: removed.
  gmsh::vectorpair free_faces;
  for (const auto& dt : out) {
    if (dt.first != 2) continue;
    std::vector<int> up;
    std::vector<int> down;
    gmsh::model::getAdjacencies(2, dt.second, up, down);
    if (up.empty()) free_faces.push_back(dt);
  }
  if (!free_faces.empty()) occ::remove(free_faces, true);
  occ::synchronize();
  gmsh::vectorpair blocks = volumes_of(out);
  const std::vector<int> block_faces = union_faces(blocks);
  if (!std::all_of(block_faces.begin(), block_faces.end(), four_cornered)) {
    remove_new(before);
    return {};
  }
  occ::remove(volumes, true);
  occ::synchronize();
  return blocks;
}

/// The hole of a solid of planar faces and straight edges with one through-hole: one full
/// cylindrical face bounded by two circles of equal radius whose centres give the axis
/// (area 2 pi r h, 1e-6), every other curve a line, no face bounded by a circle alone (that
/// is a blind hole's bottom). `base` is the centre of the first circle.
bool is_plate_with_hole(const gmsh::vectorpair& volumes, const std::vector<int>& faces, Vec& base,
                        Vec& axis, double& r) {
  int side = 0;
  for (const int f : faces) {
    std::string type;
    gmsh::model::getType(2, f, type);
    if (type == "Cylinder") {
      if (side != 0) return false;
      side = f;
    } else if (type != "Plane") {
      return false;
    }
  }
  if (side == 0) return false;
  gmsh::vectorpair curves;
  gmsh::model::getBoundary({{2, side}}, curves, false, false, false);
  std::vector<int> circles;
  for (const auto& [d, t] : curves) {
    std::string type;
    gmsh::model::getType(1, std::abs(t), type);
    if (type == "Circle") circles.push_back(std::abs(t));
  }
  std::sort(circles.begin(), circles.end());
  circles.erase(std::unique(circles.begin(), circles.end()), circles.end());
  if (circles.size() != 2) return false;
  std::array<Vec, 2> centres{};
  std::array<double, 2> radii{};
  for (std::size_t k = 0; k < 2; ++k) {
    gmsh::vectorpair ends;
    gmsh::model::getBoundary({{1, circles[k]}}, ends, false, false, false);
    if (ends.empty()) return false;
    for (const auto& e : ends)
      if (std::abs(e.second) != std::abs(ends.front().second)) return false;  // not closed
    centres[k] = centre_of(1, circles[k]);
    radii[k] = mass_of(1, circles[k]) / (2 * kPi);
    std::vector<double> p;
    gmsh::model::getValue(0, std::abs(ends.front().second), {}, p);
    if (!near(norm(sub({p[0], p[1], p[2]}, centres[k])), radii[k], 1e-6)) return false;
  }
  r = radii[0];
  if (!(r > 0.0) || !near(radii[1], r, 1e-6)) return false;
  base = centres[0];
  const Vec d = sub(centres[1], base);
  const double h = norm(d);
  if (!(h > 0.0) || !near(mass_of(2, side), 2 * kPi * r * h, 1e-6)) return false;
  axis = scaled(d, 1.0 / h);
  gmsh::vectorpair all_curves;
  gmsh::model::getBoundary(volumes, all_curves, false, false, true);
  for (const auto& [dim, t] : all_curves) {
    if (dim != 1 || std::abs(t) == circles[0] || std::abs(t) == circles[1]) continue;
    std::string type;
    gmsh::model::getType(1, std::abs(t), type);
    if (type != "Line") return false;
  }
  for (const int f : faces) {
    gmsh::vectorpair bounds;
    gmsh::model::getBoundary({{2, f}}, bounds, true, false, false);
    if (bounds.size() == 1 &&
        (std::abs(bounds[0].second) == circles[0] || std::abs(bounds[0].second) == circles[1]))
      return false;
  }
  return true;
}

/// Cuts a solid with a through-hole (`is_plate_with_hole`) by the half-planes from the
/// hole's axis through each of its corners and through the hole's seam (the circles'
/// points: OpenCASCADE keeps them as corners of the hole's pieces), at most 16; "" and
/// `dropped` set when the blocks do not all have four-cornered faces.
std::string cut_around_hole(const gmsh::vectorpair& volumes, const Vec& base, const Vec& axis,
                            double diagonal, const std::function<bool(int)>& four_cornered,
                            std::string& dropped) {
  // A frame across the axis.
  Vec e1 = std::abs(axis[0]) < 0.9 ? Vec{1, 0, 0} : Vec{0, 1, 0};
  e1 = sub(e1, scaled(axis, dot(e1, axis)));
  e1 = scaled(e1, 1.0 / norm(e1));
  const Vec e2 = cross(axis, e1);
  gmsh::vectorpair points;
  gmsh::model::getBoundary(volumes, points, false, false, true);
  std::vector<double> angles;
  double lo = 1e300;
  double hi = -1e300;
  for (const auto& [d, t] : points) {
    if (d != 0) continue;
    std::vector<double> p;
    gmsh::model::getValue(0, std::abs(t), {}, p);
    const Vec w = sub({p[0], p[1], p[2]}, base);
    const double along = dot(w, axis);
    lo = std::min(lo, along);
    hi = std::max(hi, along);
    const Vec across = sub(w, scaled(axis, along));
    if (norm(across) > 1e-6 * diagonal)
      angles.push_back(std::atan2(dot(across, e2), dot(across, e1)));
  }
  std::sort(angles.begin(), angles.end());
  const double tol = 1e-7;
  angles.erase(
      std::unique(angles.begin(), angles.end(), [tol](double a, double b) { return b - a <= tol; }),
      angles.end());
  if (angles.size() > 1 && angles.back() - angles.front() >= 2 * kPi - tol) angles.pop_back();
  if (angles.size() < 2) return "";
  if (angles.size() > 16) {
    dropped = "a solid with a through-hole, but " + std::to_string(angles.size()) +
              " half-planes from the hole's axis through its corners (more than 16)";
    return "";
  }
  const auto before = occ_entities();
  const double margin = 0.1 * diagonal;
  const Vec bottom = add(base, scaled(axis, lo - margin));
  const Vec top = add(base, scaled(axis, hi + margin));
  gmsh::vectorpair copy;
  occ::copy(volumes, copy);
  gmsh::vectorpair tools;
  for (const double angle : angles) {
    const Vec out =
        scaled(add(scaled(e1, std::cos(angle)), scaled(e2, std::sin(angle))), 2.0 * diagonal);
    tools.push_back(add_quad({bottom, top, add(top, out), add(bottom, out)}));
  }
  const gmsh::vectorpair blocks = cut_into_blocks(volumes, copy, tools, before, four_cornered);
  if (blocks.empty()) {
    dropped = "a solid with a through-hole, cut by " + std::to_string(angles.size()) +
              " half-planes through the hole's axis, but a face of the blocks has not 4 corners";
    return "";
  }
  return "a solid with a through-hole, cut by " + std::to_string(angles.size()) +
         " half-planes through the hole's axis into " + std::to_string(blocks.size()) + " blocks";
}

/// Cuts of a solid of planes and lines by the axis planes through its corners; "" and
/// `dropped` set when it does not give blocks of four-cornered faces.
std::string cut_by_corner_planes(const gmsh::vectorpair& volumes, const std::vector<int>& faces,
                                 double diagonal, const std::function<bool(int)>& four_cornered,
                                 std::string& dropped) {
  for (const std::string& t : types_of(2, faces))
    if (t != "Plane") return "";
  {
    gmsh::vectorpair curves;
    gmsh::model::getBoundary(volumes, curves, false, false, true);
    std::vector<int> curve_tags;
    for (const auto& [d, t] : curves)
      if (d == 1) curve_tags.push_back(std::abs(t));
    for (const std::string& t : types_of(1, curve_tags))
      if (t != "Line") return "";
  }
  const double tol = 1e-6 * diagonal;
  Vec lo = {1e300, 1e300, 1e300};
  Vec hi = {-1e300, -1e300, -1e300};
  std::array<std::vector<double>, 3> at;
  gmsh::vectorpair points;
  gmsh::model::getBoundary(volumes, points, false, false, true);
  std::vector<Vec> xyz;
  for (const auto& [d, t] : points) {
    if (d != 0) continue;
    std::vector<double> p;
    gmsh::model::getValue(0, std::abs(t), {}, p);
    xyz.push_back({p[0], p[1], p[2]});
    for (std::size_t k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  }
  std::size_t planes = 0;
  for (std::size_t k = 0; k < 3; ++k) {
    for (const Vec& p : xyz)
      if (p[k] > lo[k] + tol && p[k] < hi[k] - tol) at[k].push_back(p[k]);
    std::sort(at[k].begin(), at[k].end());
    at[k].erase(
        std::unique(at[k].begin(), at[k].end(), [tol](double a, double b) { return b - a <= tol; }),
        at[k].end());
    planes += at[k].size();
  }
  if (planes == 0) return "";
  if (planes > 12) {
    dropped = std::to_string(planes) + " axis planes through its corners (more than 12)";
    return "";
  }
  const auto before = occ_entities();
  const double m = 0.1 * diagonal;
  gmsh::vectorpair copy;
  occ::copy(volumes, copy);
  gmsh::vectorpair tools;
  for (std::size_t k = 0; k < 3; ++k) {
    const std::size_t u = (k + 1) % 3;
    const std::size_t w = (k + 2) % 3;
    for (const double v : at[k]) {
      std::array<Vec, 4> c{};
      const std::array<std::array<double, 2>, 4> uw = {{{lo[u] - m, lo[w] - m},
                                                        {hi[u] + m, lo[w] - m},
                                                        {hi[u] + m, hi[w] + m},
                                                        {lo[u] - m, hi[w] + m}}};
      for (std::size_t i = 0; i < 4; ++i) {
        c[i][k] = v;
        c[i][u] = uw[i][0];
        c[i][w] = uw[i][1];
      }
      tools.push_back(add_quad(c));
    }
  }
  const gmsh::vectorpair blocks = cut_into_blocks(volumes, copy, tools, before, four_cornered);
  if (blocks.empty()) {
    dropped = "cut by " + std::to_string(planes) +
              " axis planes through its corners, but a face of the blocks still has not 4 "
              "corners";
    return "";
  }
  return "a solid of planar faces, cut by " + std::to_string(planes) +
         " axis planes through its corners into " + std::to_string(blocks.size()) + " blocks";
}

}  // namespace

SplitResult split_into_blocks(const std::vector<std::pair<int, int> >& volumes, double diagonal,
                              const std::function<bool(int)>& four_cornered) {
  SplitResult result;
  const std::vector<int> faces = union_faces(volumes);
  if (std::all_of(faces.begin(), faces.end(), four_cornered)) return result;
  const auto before = occ_entities();
  std::string what;
  try {
    Vec base{};
    Vec axis{};
    double r = 0.0;
    double h = 0.0;
    gmsh::vectorpair blocks;
    if (volumes.size() == 1 && is_cylinder(volumes[0].second, faces, base, axis, r, h)) {
      what = "a cylinder, split as an O-grid of 5 blocks";
      blocks = add_ogrid_cylinder(r, h);
      place(blocks, axis, base);
    } else if (volumes.size() == 1 && is_sphere(volumes[0].second, faces, base, r)) {
      what = "a sphere, split as a cubed sphere of 7 blocks";
      blocks = add_cubed_sphere(r);
      occ::translate(blocks, base[0], base[1], base[2]);
    } else if (volumes.size() == 1 && is_torus(volumes[0].second, faces, base, axis, r, h)) {
      what = "a torus, split as 20 blocks of a revolved O-grid";
      blocks = add_torus_blocks(r, h);  // r: centre-line radius, h: tube radius
      place(blocks, axis, base);
    } else if (volumes.size() == 1 && is_plate_with_hole(volumes, faces, base, axis, r)) {
      result.how = cut_around_hole(volumes, base, axis, diagonal, four_cornered, result.dropped);
      return result;
    } else {
      result.how = cut_by_corner_planes(volumes, faces, diagonal, four_cornered, result.dropped);
      return result;
    }
    occ::synchronize();
    const std::vector<int> block_faces = union_faces(blocks);
    if (!std::all_of(block_faces.begin(), block_faces.end(), four_cornered)) {
      result.dropped = what + ", but a face of the blocks has not 4 corners";
      remove_new(before);
      return result;
    }
    occ::remove(gmsh::vectorpair(volumes.begin(), volumes.end()), true);
    occ::synchronize();
    result.how = what;
  } catch (...) {
    result.dropped = (what.empty() ? std::string("splitting into blocks") : what) +
                     " failed in Gmsh: " + gmsh_detail::gmsh_reason();
    try {
      remove_new(before);
    } catch (...) {
      throw InternalError("the CAD model could not be restored after " + result.dropped + ": " +
                          gmsh_detail::gmsh_reason() + "; this is a bug");
    }
  }
  return result;
}

}  // namespace stcweave::primal::cad_detail

#endif
