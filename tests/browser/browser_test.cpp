// The browser page in a real browser: headless Chromium (Debian's `chromium`, software WebGL
// through SwiftShader, no network) opens the page from a file. The page reports into its
// #stcweave-status element what it drew and met (see docs/viewer.md); --dump-dom gives that
// element back. Checked: the page is ready with no error, its data matches the mesh (hexes,
// sheets, chords against the `mesh` report and the STC), the replay reaches the last hex,
// "show only" shows exactly the hexes of a sheet / chord, the picture is not blank and has
// many colours. A screenshot is written too (STCWEAVE_SCREENSHOT_DIR: where to keep it; the
// README's image comes from here). Skips, saying so, when Chromium is missing.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>

#include "stcweave/stc/hex_stc.hpp"
#include "support/cli_run.hpp"

namespace stcweave {
namespace {

namespace fs = std::filesystem;

std::string chromium() {
  if (const char* env = std::getenv("STCWEAVE_CHROMIUM")) return env;
  for (const char* p : {"/usr/bin/chromium", "/usr/bin/chromium-browser"})
    if (fs::exists(p)) return p;
  return {};
}

fs::path work_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("stcweave_browser_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// Runs a shell command, returns its exit code; stdout to `out`.
int shell(const std::string& cmd) {
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string browser_flags(const fs::path& dir) {
  return " --headless --disable-gpu --use-angle=swiftshader --enable-unsafe-swiftshader"
         " --no-sandbox --no-first-run --no-default-browser-check --disable-extensions"
         " --disable-background-networking --host-resolver-rules='MAP * ~NOTFOUND'"
         " --user-data-dir='" +
         (dir / "profile").string() + "' --window-size=1200,800";
}

/// The data-* attributes of the page's status element after loading `page` with `hash`.
std::map<std::string, std::string> page_status(const fs::path& page, const std::string& hash,
                                               const fs::path& dir, std::string* log) {
  const fs::path dom = dir / "dom.html";
  const fs::path err = dir / "chromium.log";
  const std::string cmd = "timeout 180 '" + chromium() + "'" + browser_flags(dir) +
                          " --enable-logging=stderr --dump-dom 'file://" +
                          fs::absolute(page).string() + hash + "' > '" + dom.string() + "' 2> '" +
                          err.string() + "'";
  const int code = shell(cmd);
  *log = test::slurp(err);
  std::map<std::string, std::string> out;
  if (code != 0) {
    out["chromium-exit"] = std::to_string(code);
    return out;
  }
  const std::string html = test::slurp(dom);
  const std::size_t at = html.find("<div id=\"stcweave-status\"");
  if (at == std::string::npos) return out;
  const std::string tag = html.substr(at, html.find('>', at) - at);
  const std::regex attr("data-([a-z-]+)=\"([^\"]*)\"");
  for (auto it = std::sregex_iterator(tag.begin(), tag.end(), attr); it != std::sregex_iterator();
       ++it)
    out[(*it)[1]] = (*it)[2];
  return out;
}

long number(const std::map<std::string, std::string>& s, const std::string& key) {
  const auto it = s.find(key);
  return it == s.end() ? -1 : std::stol(it->second);
}

/// Checks a page of `hexes` hexes and `sheets` sheets / `chords` chords in the browser, and
/// takes a screenshot of it opened with `shot_hash` (page options, e.g. "#step=10").
void check_page(const fs::path& page, std::size_t hexes, std::size_t sheets, std::size_t chords,
                const fs::path& dir, const std::string& screenshot_name,
                const std::string& shot_hash = "") {
  std::string log;
  const auto s = page_status(page, "#test", dir, &log);
  ASSERT_FALSE(s.empty()) << "no status element in the page's DOM; chromium said:\n" << log;
  ASSERT_EQ(s.count("chromium-exit"), 0U) << "chromium failed:\n" << log;
  EXPECT_EQ(s.at("state"), "ready") << "errors: " << s.at("errors");
  EXPECT_EQ(s.at("errors"), "");
  EXPECT_EQ(log.find("Uncaught"), std::string::npos) << log;
  EXPECT_EQ(number(s, "hexes"), static_cast<long>(hexes));
  EXPECT_EQ(number(s, "sheets"), static_cast<long>(sheets));  // distinct ids in the hex data
  EXPECT_EQ(number(s, "chords"), static_cast<long>(chords));
  EXPECT_EQ(number(s, "sheets-declared"), static_cast<long>(sheets));
  EXPECT_EQ(number(s, "histogram-total"), static_cast<long>(hexes));
  EXPECT_EQ(number(s, "replay-first"), 0);
  EXPECT_EQ(number(s, "replay-one"), 1);
  EXPECT_EQ(number(s, "replay-last"), static_cast<long>(hexes));
  EXPECT_NE(s.at("replay-last-text").find("Step " + std::to_string(hexes) + " of "),
            std::string::npos)
      << s.at("replay-last-text");
  EXPECT_EQ(number(s, "sheet-shown"), number(s, "sheet-expected"));
  EXPECT_GT(number(s, "sheet-shown"), 0);
  EXPECT_EQ(number(s, "chord-shown"), number(s, "chord-expected"));
  EXPECT_GT(number(s, "chord-shown"), 0);
  EXPECT_LT(number(s, "clip-shown"), static_cast<long>(hexes));
  EXPECT_GT(number(s, "drawn-faces"), 0);
  EXPECT_GE(number(s, "picked"), 0) << "a click at the centre hit no hex";
  EXPECT_LT(number(s, "picked"), static_cast<long>(hexes));
  // Not blank: a good part of the canvas is painted, with sheets coloured apart.
  EXPECT_GT(std::stod(s.at("painted")), 0.05) << "painted fraction " << s.at("painted");
  EXPECT_GE(number(s, "colours"), static_cast<long>(std::min<std::size_t>(sheets, 8)));
  // A screenshot of the default view (the PNG's own header gives its size).
  const char* keep = std::getenv("STCWEAVE_SCREENSHOT_DIR");
  const fs::path png = (keep != nullptr ? fs::path(keep) : dir) / (screenshot_name + ".png");
  const std::string cmd = "timeout 180 '" + chromium() + "'" + browser_flags(dir) +
                          " --virtual-time-budget=5000 --screenshot='" + png.string() +
                          "' 'file://" + fs::absolute(page).string() + shot_hash +
                          "' > /dev/null 2>&1";
  ASSERT_EQ(shell(cmd), 0);
  const std::string bytes = test::slurp(png);
  ASSERT_GT(bytes.size(), 24U);
  EXPECT_EQ(bytes.substr(1, 3), "PNG");
  const auto be32 = [&](std::size_t at) {
    return (static_cast<unsigned char>(bytes[at]) << 24) |
           (static_cast<unsigned char>(bytes[at + 1]) << 16) |
           (static_cast<unsigned char>(bytes[at + 2]) << 8) |
           static_cast<unsigned char>(bytes[at + 3]);
  };
  EXPECT_EQ(be32(16), 1200U);
  EXPECT_EQ(be32(20), 800U);
  EXPECT_GT(bytes.size(), 20000U) << "a blank 1200x800 screenshot compresses to a few kB";
}

nlohmann::json report(const fs::path& path) {
  return nlohmann::json::parse(test::slurp(path));
}

TEST(Browser, MeshHtmlOfTheLBlock) {
  if (chromium().empty()) GTEST_SKIP() << "SKIPPED: no chromium (Debian package chromium)";
  const fs::path dir = work_dir("lblock");
  const auto r =
      test::run_cli(std::string("mesh ") + STCWEAVE_SOURCE_DIR + "/data/lblock.obj -o " +
                    (dir / "lblock.vtk").string() + " --html " + (dir / "lblock.html").string() +
                    " --report " + (dir / "r.json").string() + " -q");
  ASSERT_EQ(r.code, 0) << r.out;
  const nlohmann::json rep = report(dir / "r.json");
  check_page(dir / "lblock.html", rep["hexes"], rep["sheets"], rep["chords"], dir, "view-lblock");
}

TEST(Browser, ViewOfAWovenBoxAndOfAMeshWithoutCellData) {
  if (chromium().empty()) GTEST_SKIP() << "SKIPPED: no chromium (Debian package chromium)";
  const fs::path dir = work_dir("box");
  ASSERT_EQ(test::run_cli("generate box 5 6 7 -o " + (dir / "box.obj").string()).code, 0);
  auto r = test::run_cli("mesh " + (dir / "box.obj").string() + " -o " +
                         (dir / "box.vtu").string() + " --trace " + (dir / "t.jsonl").string() +
                         " --report " + (dir / "r.json").string() + " -q");
  ASSERT_EQ(r.code, 0) << r.out;
  const nlohmann::json rep = report(dir / "r.json");
  ASSERT_EQ(rep["hexes"], 210);
  r = test::run_cli("view " + (dir / "box.vtu").string() + " -o " + (dir / "view.html").string() +
                    " --trace " + (dir / "t.jsonl").string());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("weave replay"), std::string::npos) << r.out;
  check_page(dir / "view.html", rep["hexes"], rep["sheets"], rep["chords"], dir, "view-box");
  check_page(dir / "view.html", rep["hexes"], rep["sheets"], rep["chords"], dir, "view-box-replay",
             "#step=150&clip=y:0.5:flip");
  // A hex mesh with no data at all (generated): the page still works, replaying file order.
  ASSERT_EQ(test::run_cli("generate box 3 3 3 --hexes -o " + (dir / "h.vtk").string()).code, 0);
  r = test::run_cli("view " + (dir / "h.vtk").string() + " -o " + (dir / "h.html").string());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("no weave data"), std::string::npos) << r.out;
  check_page(dir / "h.html", 27, 9, 27, dir, "view-hexes");
}

}  // namespace
}  // namespace stcweave
