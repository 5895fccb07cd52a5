#pragma once
/// \file
/// A minimal IGES 5.3 writer for the CAD tests: Gmsh 4.8 reads IGES but cannot write it
/// (`gmsh::write` knows no IGES format), so the tests write their IGES files themselves. A
/// box is written as six untrimmed bilinear B-spline surfaces (entity 128, degree 1 by 1,
/// 2 x 2 control points), one per face, with no solid: the usual content of an IGES file,
/// which the CAD front end sews into a solid.

#include <array>
#include <cstddef>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

namespace stcweave::test {

/// One bilinear face: its corners at parameters (0,0), (1,0), (0,1), (1,1).
using IgesFace = std::array<std::array<double, 3>, 4>;

/// The six faces of the `a` x `b` x `c` box with a corner at the origin.
inline std::vector<IgesFace> iges_box_faces(double a, double b, double c) {
  const auto p = [&](int i, int j, int k) -> std::array<double, 3> {
    return {i * a, j * b, k * c};
  };
  return {{p(0, 0, 0), p(0, 1, 0), p(1, 0, 0), p(1, 1, 0)},
          {p(0, 0, 1), p(1, 0, 1), p(0, 1, 1), p(1, 1, 1)},
          {p(0, 0, 0), p(1, 0, 0), p(0, 0, 1), p(1, 0, 1)},
          {p(0, 1, 0), p(0, 1, 1), p(1, 1, 0), p(1, 1, 1)},
          {p(0, 0, 0), p(0, 0, 1), p(0, 1, 0), p(0, 1, 1)},
          {p(1, 0, 0), p(1, 1, 0), p(1, 0, 1), p(1, 1, 1)}};
}

/// Writes `faces` to `path` as an IGES file (fixed 80-column records: start, global,
/// directory entry, parameter data and terminate sections).
inline void write_iges(const std::string& path, const std::vector<IgesFace>& faces) {
  const auto record = [](const std::string& text, char section, std::size_t n) {
    char tail[16];
    std::snprintf(tail, sizeof tail, "%c%7zu", section, n);
    std::string line = text;
    line.resize(72, ' ');
    return line + tail + "\n";
  };
  const auto field = [](const std::string& s) {
    std::string f = s;
    if (f.size() < 8) f.insert(0, 8 - f.size(), ' ');
    return f;
  };
  const auto number = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    std::string s = buf;
    if (s.find_first_of(".eE") == std::string::npos) s += ".0";
    return s;
  };
  std::string out = record("stcweave test: bilinear B-spline faces", 'S', 1);
  const std::string global =
      "1H,,1H;,4Htest,9Htest.iges,8Hstcweave,3H1.0,32,38,6,308,15,4Htest,1.0,2,2HMM,1,1.0,"
      "15H20260101.000000,1.0E-7,10.0,4Htest,4Htest,11,0;";
  std::size_t g = 0;
  for (std::size_t i = 0; i < global.size(); i += 72) out += record(global.substr(i, 72), 'G', ++g);
  std::vector<std::string> directory;
  std::vector<std::string> parameters;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    // 128: K1 K2 M1 M2, PROP1-5 (not closed, polynomial, not periodic), knots, weights,
    // control points, then the parameter range.
    std::string p = "128,1,1,1,1,0,0,1,0,0,0.0,0.0,1.0,1.0,0.0,0.0,1.0,1.0,1.0,1.0,1.0,1.0";
    for (const auto& corner : faces[f])
      for (const double v : corner) p += "," + number(v);
    p += ",0.0,1.0,0.0,1.0;";
    const std::size_t first = parameters.size() + 1;
    const std::size_t de = 2 * f + 1;
    std::size_t lines = 0;
    for (std::size_t i = 0; i < p.size(); i += 64, ++lines) {
      std::string chunk = p.substr(i, 64);
      chunk.resize(64, ' ');
      parameters.push_back(chunk + field(std::to_string(de)));
    }
    directory.push_back(field("128") + field(std::to_string(first)) + field("0") + field("0") +
                        field("0") + field("0") + field("0") + field("0") + field("00000000"));
    directory.push_back(field("128") + field("0") + field("0") + field(std::to_string(lines)) +
                        field("0") + field("") + field("") + field("") + field("0"));
  }
  for (std::size_t i = 0; i < directory.size(); ++i) out += record(directory[i], 'D', i + 1);
  for (std::size_t i = 0; i < parameters.size(); ++i) out += record(parameters[i], 'P', i + 1);
  char terminate[64];
  std::snprintf(terminate, sizeof terminate, "S%7dG%7zuD%7zuP%7zu", 1, g, directory.size(),
                parameters.size());
  out += record(terminate, 'T', 1);
  std::ofstream(path) << out;
}

}  // namespace stcweave::test
