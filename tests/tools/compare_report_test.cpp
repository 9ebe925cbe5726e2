// What `surftrace compare` judges and shows beyond its verdict, through the programs a user
// runs: the masks from the reference's exact geometry (most hits judged at 256² on 1AON, and
// the 3×3 rule for an older reference), the difference image's colours, and the `--html` page
// opened in headless Chromium (its images and plots drawn, its table equal to the JSON report).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <tuple>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "oracles/srgb.hpp"
#include "run_tool.hpp"
#include "temp_dir.hpp"
#include "view/image_compare.hpp"
#include "view/image_io.hpp"

namespace surftrace::tools {
namespace {

namespace fs = std::filesystem;
using test::Result;
// From the repository root, where the data's relative paths point.
Result run(const std::string& args) { return test::runTool(args, SURFTRACE_SOURCE_DIR); }
std::string temp(const std::string& name) { return (::surftrace::test::testTempDir() / ("compare_report_" + name)).string(); }
bool has(const Result& r, const std::string& text) { return r.output.find(text) != std::string::npos; }

nlohmann::json readJson(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

std::size_t hitsOf(const std::string& exr) {
  const view::FrameBuffers f = view::readExr(exr);
  std::size_t hits = 0;
  for (const std::uint32_t k : f.kind) hits += k != 0;
  return hits;
}

// The Embree reference and the GL image of one view, as EXRs.
std::pair<std::string, std::string> renderBoth(const std::string& name, const std::string& args) {
  const std::string ref = temp(name + "_embree.exr"), gl = temp(name + "_gl.exr");
  const Result a = run("render " + args + " --quiet --exr " + ref);
  EXPECT_EQ(a.status, 0) << a.output;
  const Result b = run("render " + args + " --engine gl --quiet --exr " + gl);
  EXPECT_EQ(b.status, 0) << b.output;
  return {ref, gl};
}

TEST(CompareMasks, TheKindCheckCoversMostHitsOf1aonAt256) {
  // The 3×3 neighbourhood rule judged the kind on 2.1% of these hits: at 256² most 1AON
  // patches are a pixel or two across.
  for (const auto& [name, surface] : {std::pair<std::string, std::string>{"1aon_ses", ""}, {"1aon_skin", " --surface mss --shrink 0.5"}}) {
    const auto [ref, gl] = renderBoth(name, "tests/data/paper/1aon.pdb.gz --size 256x256 --view front" + surface);
    const std::string report = temp(name + ".json");
    const Result c = run("compare " + gl + " " + ref + " --report " + report);
    EXPECT_EQ(c.status, 0) << c.output;
    const nlohmann::json j = readJson(report);
    const std::size_t hits = hitsOf(ref), judged = j["patch_kind"]["samples"].get<std::size_t>();
    std::printf("%s at 256²: patch kind judged on %zu of %zu hits (%.1f%%), %.4f%% agree\n", name.c_str(), judged, hits,
                100.0 * static_cast<double>(judged) / static_cast<double>(hits), 100.0 * j["patch_kind"]["agreement"].get<double>());
    EXPECT_TRUE(j["masks"]["exact"].get<bool>()) << c.output;
    EXPECT_EQ(j["reference_hits"].get<std::size_t>(), hits);
    EXPECT_GE(judged, 8 * hits / 10) << c.output;
  }
}

TEST(CompareMasks, AReferenceWithoutSeamDistancesFallsBackToTheNeighbourhoodRule) {
  const auto [ref, gl] = renderBoth("crambin", "tests/data/structures/1crn.pdb --size 96x96 --view front");
  // The same reference as an EXR from before the seam.distance channel.
  view::ImageMetadata meta;
  view::FrameBuffers f = view::readExr(ref, &meta);
  ASSERT_EQ(f.seamDistance.size(), f.pixels()) << "render --exr records the seam distances";
  f.seamDistance.clear();
  const std::string old = temp("crambin_old.exr");
  view::writeExr(old, f, meta);
  const Result o = run("compare " + gl + " " + old + " --report " + temp("old.json"));
  EXPECT_EQ(o.status, 0) << o.output;
  EXPECT_TRUE(has(o, "3x3 neighbourhood rule")) << o.output;
  const Result n = run("compare " + gl + " " + ref + " --report " + temp("new.json"));
  EXPECT_EQ(n.status, 0) << n.output;
  EXPECT_FALSE(has(n, "3x3 neighbourhood rule")) << n.output;
  const nlohmann::json jo = readJson(temp("old.json")), jn = readJson(temp("new.json"));
  EXPECT_FALSE(jo["masks"]["exact"].get<bool>());
  EXPECT_TRUE(jn["masks"]["exact"].get<bool>());
  EXPECT_GT(jn["patch_kind"]["samples"].get<std::size_t>(), jo["patch_kind"]["samples"].get<std::size_t>());
}

// The 8-bit colour of each pixel of a PNG.
std::vector<std::tuple<int, int, int>> pngColours(const std::string& path, int& width, int& height) {
  const view::ImageChannels image = view::readImageChannels(path);
  width = image.width, height = image.height;
  std::vector<std::tuple<int, int, int>> out;
  for (std::size_t p = 0; p < image.pixels(); ++p)
    out.emplace_back(static_cast<int>(std::lround(255 * image.at(p, 0))), static_cast<int>(std::lround(255 * image.at(p, 1))),
                     static_cast<int>(std::lround(255 * image.at(p, 2))));
  return out;
}

// The PNG's code of a difference colour: sRGB-encoded, as every 8-bit image is.
std::tuple<int, int, int> byte(const float (&c)[3]) {
  return {::surftrace::test::srgbCode(c[0]), ::surftrace::test::srgbCode(c[1]), ::surftrace::test::srgbCode(c[2])};
}

TEST(CompareDiff, GlWithinTheLimitsLooksQuiet) {
  const auto [ref, gl] = renderBoth("diff", "tests/data/structures/1crn.pdb --size 128x128 --view front");
  const std::string diff = temp("diff.png");
  const Result c = run("compare " + gl + " " + ref + " --diff " + diff);
  EXPECT_EQ(c.status, 0) << c.output;
  int w = 0, h = 0;
  const auto colours = pngColours(diff, w, h);
  const view::FrameBuffers f = view::readExr(ref);
  std::size_t hits = 0, quiet = 0;
  for (std::size_t p = 0; p < f.pixels(); ++p) {
    if (f.kind[p] == 0) continue;
    ++hits;
    quiet += colours[p] == byte(view::difference_colors::kQuiet);
  }
  std::printf("%zu of %zu hit pixels quiet\n", quiet, hits);
  // GL's float depths (errors ~1e-5 Å, the limit ~2e-2 Å) leave only the band and nothing loud.
  EXPECT_GT(quiet, 9 * hits / 10);
}

TEST(CompareDiff, ColourErrorsShowWhenColourIsJudged) {
  const std::string ref = temp("colour_ref.exr");
  const Result r = run("render tests/data/structures/1crn.pdb --size 96x96 --view front --quiet --exr " + ref);
  ASSERT_EQ(r.status, 0) << r.output;
  // A renderer that gets the colour wrong in a 10×10 block at the image's centre.
  view::ImageMetadata meta;
  view::FrameBuffers f = view::readExr(ref, &meta);
  for (int y = 43; y < 53; ++y)
    for (int x = 43; x < 53; ++x) f.rgba[4 * (static_cast<std::size_t>(y) * 96 + static_cast<std::size_t>(x))] += 0.25f;
  const std::string test = temp("colour_test.exr");
  view::writeExr(test, f, meta);
  int w = 0, h = 0;
  for (const std::string preset : {"effects", "gl-vs-embree", "foreign"}) {
    const std::string diff = temp("colour_" + preset + ".png");
    const Result c = run("compare " + test + " " + ref + " --preset " + preset + " --diff " + diff);
    EXPECT_NE(c.status, 1) << c.output;
    const auto colours = pngColours(diff, w, h);
    std::size_t inside = 0, outside = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        if (colours[static_cast<std::size_t>(y * w + x)] == byte(view::difference_colors::kColor))
          ++(x >= 43 && x < 53 && y >= 43 && y < 53 ? inside : outside);
    // Colour is judged under `effects` (limit 0.02) and `gl-vs-embree` (1e-3): the block shows,
    // but for the few pixels on patch seams, where compare judges no colour (the patch colouring
    // changes there); `foreign` sets no colour limit, and shows none.
    EXPECT_EQ(outside, 0u) << preset;
    if (preset != std::string("foreign")) EXPECT_GE(inside, 85u) << c.output;
    else EXPECT_EQ(inside, 0u) << c.output;
  }
}

// ---------------------------------------------------------------------------------------
// The HTML page in headless Chromium.

// Chromium's headless flags: no sandbox (CI runs as root), no GPU, no network or updates, a
// fresh profile, one CSS pixel per image pixel.
std::string chromium(const std::string& profile) {
  return "chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run --disable-background-networking "
         "--disable-component-update --disable-sync --disable-dev-shm-usage --hide-scrollbars --force-device-scale-factor=1 "
         "--user-data-dir=" +
         profile + " --window-size=1400,1700 ";
}

struct Rect {
  int x, y, w, h;
};

// The data-rect (left, top, width, height) the page's script wrote on the element of data-panel `panel`.
bool panelRect(const std::string& dom, const std::string& panel, Rect& r) {
  const std::regex re("data-panel=\"" + panel + "\"[^>]*data-rect=\"(-?\\d+),(-?\\d+),(\\d+),(\\d+)\"");
  std::smatch m;
  if (!std::regex_search(dom, m, re)) return false;
  r = {std::stoi(m[1]), std::stoi(m[2]), std::stoi(m[3]), std::stoi(m[4])};
  return true;
}

TEST(CompareHtml, ChromiumDrawsTheImagesAndPlotsAndTheTableIsTheReports) {
  const Result which = test::runShell("command -v chromium");
  ASSERT_EQ(which.status, 0) << "chromium is not installed: bash scripts/install-deps.sh --tests installs it";
  // Two surfaces seen by one camera: probe 1.4 (the reference) and 1.6, so that every kind has
  // depth errors of both signs.
  const std::string ref = temp("html_ref.exr"), test = temp("html_test.exr"), camera = temp("html_camera.json");
  Result r = run("render tests/data/structures/1crn.pdb --size 128x128 --view front --quiet --exr " + ref +
                 " --camera-out " + camera);
  ASSERT_EQ(r.status, 0) << r.output;
  r = run("render tests/data/structures/1crn.pdb --probe 1.6 --camera " + camera + " --quiet --exr " + test);
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string html = temp("report.html"), json = temp("report.json");
  const Result c = run("compare " + test + " " + ref + " --preset none --report " + json + " --html " + html);
  ASSERT_EQ(c.status, 0) << c.output;
  const nlohmann::json report = readJson(json);
  ASSERT_GE(report["per_kind"].size(), 3u);

  const std::string profile = temp("chromium_profile"), shot = temp("report.png");
  fs::create_directories(profile);
  const Result dom = test::runShell(chromium(profile) + "--dump-dom file://" + html + " 2>/dev/null");
  ASSERT_EQ(dom.status, 0) << dom.output;
  ASSERT_NE(dom.output.find("data-ready=\"yes\""), std::string::npos) << "the page's script did not finish:\n"
                                                                      << dom.output.substr(0, 2000);
  // The per-kind table: each number the page shows is the report's (its data-value exactly,
  // its text to the 4 digits shown).
  std::size_t cells = 0;
  for (const nlohmann::json& row : report["per_kind"])
    for (const char* key : {"pixels", "samples", "median", "p1", "p99"}) {
      const std::string name = row["kind"].get<std::string>() + "." + key;
      const std::regex re("<td data-key=\"" + name + "\" data-value=\"([^\"]*)\">([^<]*)</td>");
      std::smatch m;
      ASSERT_TRUE(std::regex_search(dom.output, m, re)) << name << " is not in the page's table";
      const double want = row[key].get<double>();
      EXPECT_EQ(std::stod(m[1]), want) << name;
      EXPECT_NEAR(std::stod(m[2]), want, 5e-4 * std::abs(want)) << name << ": shown as " << m[2];
      ++cells;
    }
  EXPECT_EQ(cells, 5 * report["per_kind"].size());
  // The worst pixels' table has a row per entry of the report.
  const std::regex worstRow("<tr><td>\\d+</td><td>\\d+</td><td>(coverage|kind|depth)</td>");
  const std::size_t worstRows = static_cast<std::size_t>(
      std::distance(std::sregex_iterator(dom.output.begin(), dom.output.end(), worstRow), std::sregex_iterator()));
  EXPECT_EQ(worstRows, report["worst_pixels"].size());

  // The screenshot: each image and each plot drawn where the page says it is.
  const Result s = test::runShell(chromium(profile) + "--screenshot=" + shot + " file://" + html + " 2>/dev/null");
  ASSERT_EQ(s.status, 0) << s.output;
  int w = 0, h = 0;
  const auto pixels = pngColours(shot, w, h);
  auto coloursIn = [&](const Rect& rect, std::size_t& ink) {
    std::set<std::tuple<int, int, int>> distinct;
    ink = 0;
    for (int y = std::max(0, rect.y); y < std::min(h, rect.y + rect.h); ++y)
      for (int x = std::max(0, rect.x); x < std::min(w, rect.x + rect.w); ++x) {
        const auto& colour = pixels[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)];
        distinct.insert(colour);
        ink += colour != std::tuple<int, int, int>{250, 250, 250} && colour != std::tuple<int, int, int>{255, 255, 255};
      }
    return distinct.size();
  };
  std::vector<std::string> panels = {"test", "reference", "difference"};
  for (const nlohmann::json& row : report["per_kind"]) panels.push_back("plot " + row["kind"].get<std::string>());
  for (const std::string& panel : panels) {
    Rect rect{};
    ASSERT_TRUE(panelRect(dom.output, panel, rect)) << panel << " has no data-rect";
    ASSERT_TRUE(rect.x >= 0 && rect.y >= 0 && rect.x + rect.w <= w && rect.y + rect.h <= h)
        << panel << " lies outside the " << w << "x" << h << " screenshot";
    std::size_t ink = 0;
    const std::size_t distinct = coloursIn(rect, ink);
    std::printf("%-16s %4dx%-4d at (%d, %d): %zu colours, %zu px inked\n", panel.c_str(), rect.w, rect.h, rect.x, rect.y,
                distinct, ink);
    // Shaded renderings have hundreds of colours; the difference image a handful at least;
    // a plot its bars (and axis labels) on its light background.
    const std::size_t least = panel.rfind("plot", 0) == 0 ? 3 : panel == "difference" ? 4 : 100;
    EXPECT_GE(distinct, least) << panel;
    EXPECT_GT(ink, static_cast<std::size_t>(rect.w * rect.h) / 50) << panel;
  }
  fs::remove_all(profile);
}

}  // namespace
}  // namespace surftrace::tools
