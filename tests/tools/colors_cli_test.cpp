// `render --color residue|hydrophobicity|rainbow|bfactor|value`, --values, --color-map,
// --color-range, --color-select, --legend and --background r,g,b,a through the program: each
// covered pixel's colour, undone from the headlight's shading, is matplotlib's colour (the
// oracle, tests/oracles/mpl_colormap.py) of its atom's number, read here from the PDB's own
// columns, decoded from sRGB to the linear colour that is shaded; the legend's swatches are
// matplotlib's sRGB bytes in the PNG; selections paint exactly their atoms' pixels; GL agrees with Embree (compare); the
// alpha channel of the PNG and the EXR; and the errors for data a file does not have.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "oracles/mpl_colormap.hpp"
#include "oracles/python_oracle.hpp"
#include "oracles/srgb.hpp"
#include "run_tool.hpp"
#include "temp_dir.hpp"
#include "view/camera.hpp"
#include "view/color_legend.hpp"
#include "view/image_io.hpp"
#include "view/shading.hpp"

namespace surftrace::tools::test {
namespace {

namespace fs = std::filesystem;
using ::surftrace::test::matplotlibColors;

const std::string kData = SURFTRACE_TEST_DATA;
const std::string kCrambin = kData + "/structures/1crn.pdb";

// The atoms of a PDB file as its fixed columns give them (ATOM and HETATM records, in order).
struct PdbAtom {
  std::string name;
  int resid = 0;
  double bFactor = 0.0;
};
std::vector<PdbAtom> pdbAtoms(const std::string& path) {
  std::vector<PdbAtom> atoms;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("ATOM", 0) == 0 || line.rfind("HETATM", 0) == 0)
      atoms.push_back({line.substr(12, 4), std::stoi(line.substr(22, 4)), std::stod(line.substr(60, 6))});
  return atoms;
}

Result render(const std::string& args) { return runTool("render " + kCrambin + " --quiet " + args); }

struct Image {
  view::FrameBuffers f;
  view::ImageMetadata meta;
  view::Camera camera;
};
Image readImage(const fs::path& exr) {
  Image i;
  i.f = view::readExr(exr.string(), &i.meta);
  i.camera = view::cameraFromJson(i.meta.at("surftrace:camera"));
  return i;
}

// The colour a covered pixel's atom gave it, undone from the Blinn–Phong headlight of an
// orthographic camera (README: c = base·(ambient + diffuse·n·l) + specular·(n·l)^shininess);
// nothing where the light is too grazing or a channel saturated to tell.
std::optional<glm::dvec3> baseColor(const Image& im, std::size_t p) {
  const view::Lighting light;
  const glm::dvec3 n(im.f.normal[3 * p], im.f.normal[3 * p + 1], im.f.normal[3 * p + 2]);
  const double nl = glm::dot(n, -im.camera.forward());
  if (nl < 0.3) return std::nullopt;
  glm::dvec3 base;
  for (int c = 0; c < 3; ++c) {
    const double v = im.f.rgba[4 * p + static_cast<std::size_t>(c)];
    if (v > 0.999) return std::nullopt;
    base[c] = (v - light.specular * std::pow(nl, light.shininess)) / (light.ambient + light.diffuse * nl);
  }
  return base;
}

// The linear colour the renderer shades for a colour given or tabled in sRGB.
glm::dvec3 linearOf(const glm::dvec3& srgb) {
  using ::surftrace::test::linearFromSrgb;
  return {linearFromSrgb(srgb.r), linearFromSrgb(srgb.g), linearFromSrgb(srgb.b)};
}

// Every covered pixel whose atom has a wanted colour (sRGB, as matplotlib's and any given)
// shows its linear value; returns how many were compared.
std::size_t expectPixelsShow(const Image& im, const std::vector<glm::dvec3>& want, const std::string& what) {
  std::size_t compared = 0, bad = 0;
  for (std::size_t p = 0; p < im.f.pixels(); ++p) {
    if (im.f.kind[p] == 0 || im.f.atomId[p] >= want.size()) continue;
    const auto base = baseColor(im, p);
    if (!base) continue;
    ++compared;
    const glm::dvec3 w = linearOf(want[im.f.atomId[p]]);
    if (glm::length(*base - w) > 2e-4 && bad++ < 5)
      ADD_FAILURE() << what << ": pixel " << p << " of atom " << im.f.atomId[p] << " shows " << base->r << ","
                    << base->g << "," << base->b << ", want " << w.r << "," << w.g << "," << w.b;
  }
  EXPECT_EQ(bad, 0u) << what;
  EXPECT_GT(compared, 1000u) << what;
  return compared;
}

TEST(ColorsCli, BfactorPixelsAreTheMapAtTheirAtomsBfactor) {
  const fs::path dir = ::surftrace::test::testTempDir();
  const std::vector<PdbAtom> atoms = pdbAtoms(kCrambin);
  double lo = 1e300, hi = -1e300;
  for (const auto& a : atoms) lo = std::min(lo, a.bFactor), hi = std::max(hi, a.bFactor);
  const fs::path exr = dir / "b.exr";
  const Result r = render("--size 128x128 --ortho --color bfactor --color-map magma --exr " + exr.string());
  ASSERT_EQ(r.status, 0) << r.output;
  char line[128];
  std::snprintf(line, sizeof line, "colour map magma: B-factor from %.6g to %.6g (the data's min..max", lo, hi);
  EXPECT_NE(r.output.find(line), std::string::npos) << r.output;
  const Image im = readImage(exr);
  const nlohmann::json map = nlohmann::json::parse(im.meta.at("surftrace:color_map"));
  EXPECT_EQ(map["map"], "magma");
  EXPECT_EQ(map["range"][0].get<double>(), lo);
  EXPECT_EQ(map["range"][1].get<double>(), hi);
  EXPECT_EQ(map["range_from"], "data");
  std::vector<double> t;
  for (const auto& a : atoms) t.push_back((a.bFactor - lo) / (hi - lo));
  expectPixelsShow(im, matplotlibColors("magma", t, dir), "bfactor");
  // The oracle can fail: the same pixels against another map.
  const std::vector<glm::dvec3> viridis = matplotlibColors("viridis", t, dir);
  std::size_t differ = 0;
  for (std::size_t p = 0; p < im.f.pixels(); ++p)
    if (im.f.kind[p] != 0 && im.f.atomId[p] < atoms.size())
      if (const auto base = baseColor(im, p)) differ += glm::length(*base - linearOf(viridis[im.f.atomId[p]])) > 2e-4;
  EXPECT_GT(differ, 1000u);
}

TEST(ColorsCli, ValuesColourTheirAtomsOrResiduesAndTheRestIsGrey) {
  const fs::path dir = ::surftrace::test::testTempDir();
  const std::vector<PdbAtom> atoms = pdbAtoms(kCrambin);
  // By atom index: every third atom has no value; a range of one's own that clips some.
  {
    std::ofstream out(dir / "atoms.csv");
    out << "atom,rmsf\n";
    for (std::size_t i = 0; i < atoms.size(); ++i)
      if (i % 3 != 0) out << i << "," << 10.0 + 5.0 * std::sin(static_cast<double>(i)) << "\n";
  }
  const fs::path exr = dir / "v.exr";
  Result r = render("--size 128x128 --ortho --color value --values " + (dir / "atoms.csv").string() +
                    " --color-map cividis --color-range 6:14 --exr " + exr.string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("colour map cividis: rmsf from 6 to 14 (--color-range); 109 atoms without a value are grey"),
            std::string::npos)
      << r.output;
  std::vector<double> t;
  for (std::size_t i = 0; i < atoms.size(); ++i) t.push_back((10.0 + 5.0 * std::sin(static_cast<double>(i)) - 6.0) / 8.0);
  std::vector<glm::dvec3> want = matplotlibColors("cividis", t, dir);
  for (std::size_t i = 0; i < atoms.size(); i += 3) want[i] = glm::dvec3(0.5);
  expectPixelsShow(readImage(exr), want, "values by atom");
  // By residue: the residue number as the value, the data's range.
  {
    std::ofstream out(dir / "residues.csv");
    out << "chain,resid,number\n";
    for (int k = 1; k <= 46; ++k) out << "A," << k << "," << k << "\n";
  }
  r = render("--size 128x128 --ortho --color value --values " + (dir / "residues.csv").string() + " --exr " + exr.string());
  ASSERT_EQ(r.status, 0) << r.output;
  t.clear();
  for (const auto& a : atoms) t.push_back((a.resid - 1.0) / 45.0);
  expectPixelsShow(readImage(exr), matplotlibColors("viridis", t, dir), "values by residue");
}

TEST(ColorsCli, ColorSelectPaintsExactlyTheSelectedAtomsPixels) {
  const fs::path dir = ::surftrace::test::testTempDir();
  const std::vector<PdbAtom> atoms = pdbAtoms(kCrambin);
  const fs::path plain = dir / "plain.exr", painted = dir / "painted.exr";
  ASSERT_EQ(render("--size 128x128 --ortho --color element --exr " + plain.string()).status, 0);
  const Result r = render("--size 128x128 --ortho --color element --color-select 'resid 10-20=#ff8000' "
                          "--color-select 'name CA=#00ff00' --exr " + painted.string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("--color-select name CA=#00ff00: 46 atoms"), std::string::npos) << r.output;
  const Image a = readImage(plain), b = readImage(painted);
  ASSERT_EQ(a.f.atomId, b.f.atomId);
  std::size_t selected = 0;
  for (std::size_t p = 0; p < a.f.pixels(); ++p) {
    const std::uint32_t atom = a.f.atomId[p];
    const bool ca = atom < atoms.size() && atoms[atom].name == " CA ";
    const bool range = atom < atoms.size() && atoms[atom].resid >= 10 && atoms[atom].resid <= 20;
    if (!ca && !range) {
      for (int c = 0; c < 4; ++c) ASSERT_EQ(a.f.rgba[4 * p + c], b.f.rgba[4 * p + c]) << "pixel " << p << " of atom " << atom;
      continue;
    }
    const glm::dvec3 want = linearOf(ca ? glm::dvec3(0, 1, 0) : glm::dvec3(1.0, 128.0 / 255.0, 0.0));
    if (const auto base = baseColor(b, p)) {
      ++selected;
      EXPECT_LT(glm::length(*base - want), 2e-4) << "pixel " << p << " of atom " << atom;
    }
  }
  EXPECT_GT(selected, 200u);
  EXPECT_EQ(nlohmann::json::parse(b.meta.at("surftrace:color_select")),
            nlohmann::json({"resid 10-20=#ff8000", "name CA=#00ff00"}));
}

// Every map's legend file (--legend-file, the bar alone) shows matplotlib's sRGB colours as its
// bytes: column i of the bar is the map at (i + 0.5)/width, rounded to 8 bits, on every row.
TEST(ColorsCli, LegendSwatchesAreTheMapsSrgbBytes) {
  const fs::path dir = ::surftrace::test::testTempDir();
  for (const std::string map : {"viridis", "magma", "coolwarm", "rainbow"}) {
    const fs::path file = dir / (map + "_legend.png");
    const Result r = render("--size 200x160 --color bfactor --color-map " + map + " --legend-file " + file.string() +
                            " -o " + (dir / "image.png").string());
    ASSERT_EQ(r.status, 0) << r.output;
    const view::ImageChannels f = view::readImageChannels(file.string());
    view::ColorLegend legend;
    legend.label = "B-factor";
    legend.loText = "x", legend.hiText = "x";
    const view::LegendLayout l = view::legendLayout(legend, 1);
    std::vector<double> t;
    for (int i = 0; i < l.barWidth; ++i) t.push_back((i + 0.5) / l.barWidth);
    const std::vector<glm::dvec3> want = matplotlibColors(map, t, dir);
    ASSERT_EQ(want.size(), t.size());
    std::size_t wrong = 0, compared = 0;
    for (int y = l.barY; y < l.barY + l.barHeight; ++y)
      for (int i = 0; i < l.barWidth; ++i) {
        const std::size_t at = static_cast<std::size_t>(y) * static_cast<std::size_t>(f.width) + static_cast<std::size_t>(l.barX + i);
        for (int c = 0; c < 3; ++c, ++compared)
          if (std::abs(f.at(at, c) * 255.0 - 255.0 * want[static_cast<std::size_t>(i)][c]) > 0.5 + 1e-3 && wrong++ < 3)
            ADD_FAILURE() << map << " column " << i << " channel " << c << ": byte " << f.at(at, c) * 255.0
                          << ", matplotlib's " << 255.0 * want[static_cast<std::size_t>(i)][c];
      }
    EXPECT_EQ(wrong, 0u) << map;
    EXPECT_EQ(compared, 3u * static_cast<std::size_t>(l.barWidth * l.barHeight)) << map;
  }
}

TEST(ColorsCli, ASchemeWithoutDataAndBadOptionsAreErrors) {
  const fs::path dir = ::surftrace::test::testTempDir();
  const std::string xyzr = (dir / "four.xyzr").string();
  std::ofstream(xyzr) << "0 0 0 1.7\n3 0 0 1.7\n0 3 0 1.5\n0 0 3 1.6\n";
  // 1CRN with every B-factor set to zero.
  const std::string zero = (dir / "zero.pdb").string();
  {
    std::ifstream in(kCrambin);
    std::ofstream out(zero);
    std::string line;
    while (std::getline(in, line)) {
      if ((line.rfind("ATOM", 0) == 0 || line.rfind("HETATM", 0) == 0) && line.size() >= 66) line.replace(60, 6, "  0.00");
      out << line << "\n";
    }
  }
  const std::string csv = (dir / "bad.csv").string();
  std::ofstream(csv) << "atom,rmsf\n0,1.0\n1,fast\n";
  const std::string out = " --size 32x32 -o " + (dir / "x.png").string();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {xyzr + " --color bfactor", "four.xyzr has no B-factors"},
      {zero + " --color bfactor", "zero.pdb has no B-factors"},
      {xyzr + " --color residue", "four.xyzr has no residue names"},
      {xyzr + " --color hydrophobicity", "four.xyzr has no amino-acid residues"},
      {xyzr + " --color rainbow", "four.xyzr has no residues"},
      {kCrambin + " --color value", "--color value needs --values FILE"},
      {kCrambin + " --color element --values " + csv, "is read by --color value only"},
      {kCrambin + " --color value --values " + csv, "bad.csv:3: value 'fast' is not a finite number"},
      {kCrambin + " --color element --color-map viridis", "--color-map applies to --color bfactor"},
      {kCrambin + " --color element --legend", "--legend shows a colour map"},
      {kCrambin + " --color bfactor --color-range 5:1", "--color-range '5:1': LO must be below HI"},
      {kCrambin + " --color bfactor --color-range 5", "--color-range '5': expected LO:HI"},
      {kCrambin + " --color element --color-select 'resid 1-5=red'", "expected SELECTION=#rrggbb"},
      {kCrambin + " --color element --color-select 'resname TRP=#ff0000'", "--color-select:"},
      {kCrambin + " --color patch --color-select 'resid 1=#ff0000'", "--color patch colours by patch kind"},
      {kCrambin + " --background 1,1,1,2", "--background '1,1,1,2': expected r,g,b or r,g,b,a, each in [0, 1]"},
      {kCrambin + " --color bfactor --legend --size 100x100", "does not fit a 100x100 image"}};
  for (const auto& [args, message] : cases) {
    const Result r = runTool("render " + args + (args.find("--size") == std::string::npos ? out : " -o " + (dir / "y.png").string()));
    EXPECT_NE(r.status, 0) << args;
    EXPECT_NE(r.output.find(message), std::string::npos) << args << ":\n" << r.output;
    EXPECT_EQ(r.output.find("terminate"), std::string::npos) << r.output;
  }
}

// GL against Embree with each scheme, a legend, selections and a transparent background, to the
// gl-vs-embree preset of `compare` (colour p99 < 1e-3 among its limits).
TEST(ColorsCli, GlAgreesWithEmbreeForEverySchemeLegendAndAlphaBackground) {
  const fs::path dir = ::surftrace::test::testTempDir();
  const std::string csv = (dir / "v.csv").string();
  {
    std::ofstream out(csv);
    out << "chain,resid,score\n";
    for (int k = 1; k <= 46; k += 2) out << "A," << k << "," << (k * 7) % 11 << "\n";
  }
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"residue", "--color residue"},
      {"hydrophobicity", "--color hydrophobicity --legend"},
      {"rainbow", "--color rainbow --color-select 'resid 1-5=#ff00ff'"},
      {"bfactor", "--color bfactor --legend --background 0.2,0.3,0.4,0"},
      {"value", "--color value --values " + csv + " --color-map coolwarm --legend --background 1,1,1,0.5"}};
  for (const auto& [name, args] : cases) {
    const fs::path embree = dir / (name + "_embree.exr"), gl = dir / (name + "_gl.exr");
    Result r = render("--size 200x200 " + args + " --exr " + embree.string());
    ASSERT_EQ(r.status, 0) << r.output;
    r = render("--size 200x200 " + args + " --engine gl --exr " + gl.string());
    ASSERT_EQ(r.status, 0) << r.output;
    const Result c = runTool("compare " + gl.string() + " " + embree.string() + " --preset gl-vs-embree");
    EXPECT_EQ(c.status, 0) << name << ":\n" << c.output;
    std::printf("%s, GL vs Embree:\n%s", name.c_str(), c.output.c_str());
  }
  // The check can fail: a GL image without the legend against Embree's with it differs in its settings.
  const fs::path bare = dir / "bare_gl.exr";
  ASSERT_EQ(render("--size 200x200 --color bfactor --background 0.2,0.3,0.4,0 --engine gl --exr " + bare.string()).status, 0);
  const Result c = runTool("compare " + bare.string() + " " + (dir / "bfactor_embree.exr").string());
  EXPECT_EQ(c.status, 1) << c.output;
  EXPECT_NE(c.output.find("legend: test none, reference image"), std::string::npos) << c.output;
}

TEST(ColorsCli, TransparentBackgroundIsTheAlphaOfThePngAndTheExr) {
  const fs::path dir = ::surftrace::test::testTempDir();
  const fs::path png = dir / "a.png", exr = dir / "a.exr", opaque = dir / "o.png";
  ASSERT_EQ(render("--size 96x96 --background 0.2,0.4,0.6,0.25 -o " + png.string() + " --exr " + exr.string()).status, 0);
  ASSERT_EQ(render("--size 96x96 -o " + opaque.string()).status, 0);
  const Image im = readImage(exr);
  EXPECT_EQ(im.meta.at("surftrace:background"), "0.2,0.4,0.6,0.25");
  const view::ImageChannels p = view::readImageChannels(png.string());
  ASSERT_EQ(p.names, (std::vector<std::string>{"R", "G", "B", "A"}));
  EXPECT_EQ(view::readImageChannels(opaque.string()).names.size(), 3u) << "an opaque background keeps an RGB PNG";
  std::size_t background = 0, covered = 0;
  for (std::size_t i = 0; i < im.f.pixels(); ++i) {
    if (im.f.kind[i] == 0) {
      ++background;
      EXPECT_EQ(im.f.rgba[4 * i + 3], 0.25f) << i;
      EXPECT_NEAR(im.f.rgba[4 * i], 0.25 * ::surftrace::test::linearFromSrgb(0.2), 1e-7)
          << "the EXR's colour is linear and premultiplied";
      EXPECT_NEAR(p.at(i, 3), 0.25, 0.5 / 255) << i;
    } else {
      ++covered;
      EXPECT_EQ(im.f.rgba[4 * i + 3], 1.0f) << i;
      EXPECT_EQ(p.at(i, 3), 1.0f) << i;
    }
  }
  EXPECT_GT(background, 1000u);
  EXPECT_GT(covered, 1000u);
}

TEST(ColorsCli, LegendIsTheMapsBarWithItsRangeInTheCornerOrItsOwnFile) {
  const fs::path dir = ::surftrace::test::testTempDir();
  const fs::path plain = dir / "plain.exr", drawn = dir / "drawn.exr", file = dir / "legend.png";
  ASSERT_EQ(render("--size 200x160 --color bfactor --color-map viridis --exr " + plain.string()).status, 0);
  const Result r = render("--size 200x160 --color bfactor --color-map viridis --legend --legend-file " + file.string() +
                          " --exr " + drawn.string());
  ASSERT_EQ(r.status, 0) << r.output;
  const Image a = readImage(plain), b = readImage(drawn);
  EXPECT_EQ(b.meta.at("surftrace:color_legend"), "image");
  EXPECT_EQ(a.f.depth, b.f.depth) << "the legend changes colour only";
  view::ColorLegend legend;
  const nlohmann::json map = nlohmann::json::parse(b.meta.at("surftrace:color_map"));
  legend.map = "viridis";
  legend.label = map["label"];
  char lo[32], hi[32];
  std::snprintf(lo, sizeof lo, "%.4g", map["range"][0].get<double>());
  std::snprintf(hi, sizeof hi, "%.4g", map["range"][1].get<double>());
  legend.loText = lo, legend.hiText = hi;
  const view::LegendLayout l = view::legendLayout(legend, 1);
  // Only the corner's pixels changed.
  int minX = 1 << 30, minY = 1 << 30, maxX = -1, maxY = -1;
  for (int y = 0; y < 160; ++y)
    for (int x = 0; x < 200; ++x) {
      const std::size_t p = static_cast<std::size_t>(y) * 200 + static_cast<std::size_t>(x);
      bool same = true;
      for (int c = 0; c < 4; ++c) same = same && a.f.rgba[4 * p + c] == b.f.rgba[4 * p + c];
      if (!same) minX = std::min(minX, x), minY = std::min(minY, y), maxX = std::max(maxX, x), maxY = std::max(maxY, y);
    }
  EXPECT_GE(minX, 200 - l.width - 4);
  EXPECT_GE(minY, 160 - l.height - 4);
  EXPECT_LE(maxX, 200 - 4 - 1);
  EXPECT_LE(maxY, 160 - 4 - 1);
  // The bar's middle row in the file and in the image: matplotlib's viridis from left to right.
  const view::ImageChannels f = view::readImageChannels(file.string());
  ASSERT_EQ(f.width, l.width);
  ASSERT_EQ(f.height, l.height);
  std::vector<double> t;
  for (int i = 0; i < l.barWidth; ++i) t.push_back((i + 0.5) / l.barWidth);
  const std::vector<glm::dvec3> want = matplotlibColors("viridis", t, dir);
  const int row = l.barY + l.barHeight / 2;
  const int x0 = 200 - 4 - l.width, y0 = 160 - 4 - l.height;
  for (int i = 0; i < l.barWidth; ++i) {
    const std::size_t inFile = static_cast<std::size_t>(row) * static_cast<std::size_t>(f.width) + static_cast<std::size_t>(l.barX + i);
    const std::size_t inImage = static_cast<std::size_t>(y0 + row) * 200 + static_cast<std::size_t>(x0 + l.barX + i);
    for (int c = 0; c < 3; ++c) {
      const double srgb = want[static_cast<std::size_t>(i)][c];
      EXPECT_NEAR(f.at(inFile, c) * 255.0, 255.0 * srgb, 0.5 + 1e-3)
          << "column " << i << ": the file's 8-bit code is matplotlib's sRGB colour, rounded";
      EXPECT_NEAR(b.f.rgba[4 * inImage + static_cast<std::size_t>(c)], ::surftrace::test::linearFromSrgb(srgb), 1e-6)
          << "column " << i << ": the EXR holds the map's colour decoded to linear";
    }
  }
}

}  // namespace
}  // namespace surftrace::tools::test
