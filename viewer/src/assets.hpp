#pragma once
/// \file
/// The page's assets, embedded at build time by viewer/embed.cmake (private to the viewer).

#include <string_view>

namespace stcweave::viewer::detail {

std::string_view page_html();
std::string_view page_css();
std::string_view page_js();
/// three.js (Debian libjs-three, minified); empty when it was absent at build time.
std::string_view three_js();
/// three.js OrbitControls (examples/js); empty when three.js was absent at build time.
std::string_view orbit_controls_js();
/// True when three.js was found at build time.
bool has_three();

}  // namespace stcweave::viewer::detail
