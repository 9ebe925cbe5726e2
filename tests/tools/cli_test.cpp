// The `surftrace` program end to end: what a user types and what they get back.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <sys/wait.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "build/io/molecule.hpp"
#include "build/patch_list.hpp"
#include "build/io/stp_file.hpp"
#include "frame_buffers_equal.hpp"
#include "run_tool.hpp"
#include "temp_dir.hpp"
#include "view/camera.hpp"
#include "view/image_io.hpp"

namespace {

using surftrace::test::testTempDir;
using surftrace::tools::test::Result;
Result run(const std::string& args) { return surftrace::tools::test::runTool(args); }

std::string data(const std::string& file) { return std::string(SURFTRACE_TEST_DATA) + "/" + file; }

TEST(Cli, HelpTeachesTheCommands) {
  const Result r = run("--help");
  EXPECT_EQ(r.status, 0);
  for (const char* word : {"info", "area", "build", "PDB", "mmCIF"}) EXPECT_NE(r.output.find(word), std::string::npos) << word;
  // The first paragraph names what the program does: both surfaces, trajectories, compare.
  const std::string intro = r.output.substr(0, r.output.find("\n\n"));
  for (const char* word : {"solvent excluded surface", "molecular skin surface", "trajectories", "compares"})
    EXPECT_NE(intro.find(word), std::string::npos) << word << "\n" << intro;
}

// An option that takes one of a few names shows the names, not CLI11's map of them.
TEST(Cli, NamedOptionsShowTheirNames) {
  const Result help = run("info --help");
  EXPECT_NE(help.output.find("auto|pdb|mmcif|cif|pqr|xyzr|xyz|gro|psf"), std::string::npos) << help.output;
  EXPECT_EQ(help.output.find("->"), std::string::npos) << help.output;
  const Result wrong = run("info --input-format pdbx " + data("structures/1crn.pdb"));
  EXPECT_NE(wrong.status, 0);
  EXPECT_NE(wrong.output.find("expected one of auto, pdb, mmcif, cif, pqr, xyzr, xyz, gro, psf; got 'pdbx'"),
            std::string::npos)
      << wrong.output;
  EXPECT_EQ(wrong.output.find("->"), std::string::npos) << wrong.output;
  const Result upper = run("info --input-format PDB " + data("structures/1crn.pdb"));
  EXPECT_EQ(upper.status, 0) << upper.output;
}

TEST(Cli, InfoCountsTheDemoMolecule) {
  // 1VIS: 2531 atoms, of which 43 water (tests/data/MANIFEST.md).
  const Result r = run("info --json " + data("paper/1vis.pdb.gz"));
  ASSERT_EQ(r.status, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  EXPECT_EQ(j["atoms"], 2488);
  EXPECT_EQ(j["skipped"]["water"], 43);
  const Result keep = run("info --json --keep-water " + data("paper/1vis.pdb.gz"));
  EXPECT_EQ(nlohmann::json::parse(keep.output)["atoms"], 2531);
}

// A heme protein reads, builds and renders with no options: its Fe takes Alvarez's radius,
// and `info` says so.
TEST(Cli, HemeProteinWorksOutOfTheBox) {
  const Result info = run("info --json " + data("structures/1mbn.pdb.gz"));
  ASSERT_EQ(info.status, 0) << info.output;
  const auto j = nlohmann::json::parse(info.output);
  EXPECT_EQ(j["radii"]["sources"]["Alvarez 2013"], 1);  // the heme iron
  EXPECT_EQ(j["radii"]["sources"]["Bondi 1964"], 1259);
  const Result text = run("info " + data("structures/1mbn.pdb.gz"));
  EXPECT_NE(text.output.find("Alvarez 2013 1 atom"), std::string::npos) << text.output;
  const std::string png = (testTempDir() / "1mbn.png").string();
  const Result render = run("render " + data("structures/1mbn.pdb.gz") + " --size 32x32 --quiet -o " + png);
  EXPECT_EQ(render.status, 0) << render.output;
}

TEST(Cli, BadInputIsAClearErrorNotACrash) {
  const std::string path = (testTempDir() / "nan.xyzr").string();
  std::ofstream(path) << "0 0 0 1.5\n1 nan 0 1.5\n";
  const Result r = run("info " + path);
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find(path + ":2"), std::string::npos) << r.output;
  const Result missing = run("info /no/such/file.pdb");
  EXPECT_NE(missing.status, 0);
  EXPECT_NE(missing.output.find("/no/such/file.pdb"), std::string::npos) << missing.output;
  const Result probe = run("area --probe -1 " + data("paper/1grm.pdb.gz"));
  EXPECT_NE(probe.status, 0);
  EXPECT_NE(probe.output.find("--probe"), std::string::npos) << probe.output;
}

// The skin from the command line: areas by kind that add up, the per-atom shares that add up
// to the same total, a patch list that reads back valid, and a clear word on a bad s.
TEST(Cli, SkinAreaBuildAndShrinkErrors) {
  const Result r = run("area --surface mss --shrink 0.3 --format json " + data("paper/1grm.pdb.gz"));
  ASSERT_EQ(r.status, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output)["mss"];
  const double kinds = double(j["convex"]) + double(j["edge"]) + double(j["face"]) + double(j["concave"]);
  EXPECT_NEAR(double(j["total"]), kinds, 1e-9 * kinds);
  double perAtom = 0.0;
  for (double a : j["per_atom"]) perAtom += a;
  EXPECT_NEAR(perAtom, kinds, 1e-9 * kinds);
  EXPECT_GT(double(j["volume"]), 0.0);
  for (const char* kind : {"convex", "edge", "face", "concave"}) EXPECT_GT(double(j[kind]), 0.0) << kind;

  const std::string stp = (testTempDir() / "1grm_mss.stp").string();
  const Result b = run("build --surface mss --shrink 0.5 " + data("paper/1grm.pdb.gz") + " -o " + stp);
  ASSERT_EQ(b.status, 0) << b.output;
  EXPECT_NE(b.output.find("edge hyperboloids"), std::string::npos) << b.output;
  const surftrace::build::PatchList p = surftrace::build::readPatchList(stp);
  EXPECT_EQ(p.params.surface, surftrace::build::SurfaceKind::Mss);
  EXPECT_EQ(p.params.shrinkFactor, 0.5);
  EXPECT_GT(p.mss.size(), p.params.atomCount);
  // `info` on the skin's list names the skin's kinds with their counts (it printed 0 convex,
  // 0 toroidal, 0 concave).
  const auto kindCount = [&](surftrace::build::MssKind kind) {
    const auto [first, last] = surftrace::build::mssKindRange(p.mss, kind);
    return std::to_string(last - first);
  };
  const Result info = run("info " + stp);
  ASSERT_EQ(info.status, 0) << info.output;
  EXPECT_NE(info.output.find("shrink factor 0.500"), std::string::npos) << info.output;
  EXPECT_NE(info.output.find(kindCount(surftrace::build::MssKind::Convex) + " skin convex, " +
                             kindCount(surftrace::build::MssKind::Edge) + " skin edge, " +
                             kindCount(surftrace::build::MssKind::Face) + " skin face, " +
                             kindCount(surftrace::build::MssKind::Concave) + " skin concave"),
            std::string::npos)
      << info.output;

  for (const char* bad : {"0", "1.5", "-0.2", "nan", "half", "1e-4", "1e-12", "1e-200", "1e-400"}) {
    const Result e = run(std::string("area --surface mss --shrink ") + bad + " " + data("paper/1grm.pdb.gz"));
    EXPECT_EQ(e.status, 1) << bad << "\n" << e.output;
    EXPECT_NE(e.output.find("[0.001, 1]"), std::string::npos) << e.output;
    EXPECT_EQ(e.output.find("000000"), std::string::npos) << "no raw numeric limits: " << e.output;
  }
  // A factor below the limit says why it is refused (issue 18: 1e-12 gave negative volumes,
  // 1e-200 an assertion).
  for (const char* tiny : {"1e-4", "1e-12", "1e-200"}) {
    const Result e = run(std::string("render --surface mss --shrink ") + tiny + " -o x.png " + data("structures/1crn.pdb"));
    EXPECT_EQ(e.status, 1) << tiny << "\n" << e.output;
    EXPECT_NE(e.output.find("double precision no longer carries"), std::string::npos) << e.output;
  }
  // The limit itself is served.
  const Result least = run("area --surface mss --shrink 0.001 " + data("structures/1crn.pdb"));
  EXPECT_EQ(least.status, 0) << least.output;
}

// Every numeric option says what it expects and what it got, in a line a person reads:
// no 300-digit limits of double from the option library.
TEST(Cli, OptionErrorsAreReadable) {
  const std::string mol = data("structures/1crn.pdb");
  const std::string png = (testTempDir() / "o.png").string();
  struct Case {
    std::string args, mustSay;
  };
  const Case cases[] = {
      {"area --probe -1 " + mol, "--probe: expected a number > 0, got '-1'"},
      {"area --probe inf " + mol, "--probe: expected a number > 0, got 'inf' (not finite)"},
      {"area --probe nan " + mol, "got 'nan'"},
      {"area --probe 0 " + mol, "got '0'"},
      {"area --probe 1e-320 " + mol, "got '1e-320' (below 2.2e-308, the smallest normal double)"},
      {"area --probe 1e400 " + mol, "got '1e400' (beyond double's range)"},
      {"build --threads -1 -o x.stp " + mol, "--threads: expected a whole number in [0, 4096], got '-1'"},
      {"info --model 0 " + mol, "--model: expected a whole number >= 1, got '0'"},
      {"info --default-radius -2 " + mol, "--default-radius: expected a number > 0, got '-2'"},
      {"render --spp 0 -o " + png + " " + mol, "--spp: expected a whole number in [1, 1024], got '0'"},
      {"render --ao -1 -o " + png + " " + mol, "--ao: expected a whole number in [0, 4096]"},
      {"render --ao-distance 0 -o " + png + " " + mol, "--ao-distance: expected a number > 0"},
      {"render --gl-steps 0 -o " + png + " " + mol, "--gl-steps: expected a whole number in [1, 10000]"},
      {"render --up 0,0,0 -o " + png + " " + mol, "--up '0,0,0': the up vector must not be zero"},
      {"render --size 32768x32768 -o " + png + " " + mol, "GiB for its buffers, more than this machine's"},
      {"render --size -4x4 -o " + png + " " + mol, "--size '-4x4': expected WIDTHxHEIGHT"},
      {"compare --min-kind 2 " + mol + " " + mol, "--min-kind: expected a number in [0, 1], got '2'"},
      {"compare --max-depth-p99 -1 " + mol + " " + mol, "--max-depth-p99: expected a number >= 0"},
  };
  for (const auto& c : cases) {
    const Result r = run(c.args);
    EXPECT_NE(r.status, 0) << c.args;
    EXPECT_NE(r.output.find(c.mustSay), std::string::npos) << c.args << "\n" << r.output;
    EXPECT_EQ(r.output.find("not in range"), std::string::npos) << c.args << "\n" << r.output;
    EXPECT_LT(r.output.size(), 300u) << c.args << "\n" << r.output;
  }
}

// A probe past what double precision serves is refused with the limit and the reason; below
// it the SES of 1UBQ is its convex hull's area (3451 Å², as the issue measured at 1e5 Å).
TEST(Cli, HugeProbeIsAnErrorNamingTheLimit) {
  const Result r = run("area --probe 1e9 " + data("structures/1ubq.pdb.gz"));
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("probe radius 1e+09 Å is above the limit of 796918 Å (2^19 times the smallest atom "
                          "radius, 1.52 Å)"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("double-precision rounding"), std::string::npos) << r.output;
}

TEST(Cli, AreaJsonHasTheDocumentedShape) {
  const Result r = run("area --format json " + data("paper/1grm.pdb.gz"));
  ASSERT_EQ(r.status, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  const double convex = j["ses"]["convex"], toroidal = j["ses"]["toroidal"], concave = j["ses"]["concave"];
  EXPECT_NEAR(j["ses"]["total"].get<double>(), convex + toroidal + concave, 1e-9);
  EXPECT_GT(j["ses"]["volume"].get<double>(), 0.0);
  EXPECT_GT(j["sas"]["total"].get<double>(), j["ses"]["total"].get<double>());
  double perAtom = 0;
  for (double v : j["sas"]["per_atom"]) perAtom += v;
  EXPECT_NEAR(perAtom, j["sas"]["total"].get<double>(), 1e-6);
  EXPECT_EQ(j["sas"]["per_atom"].size(), j["atoms"].get<std::size_t>());
}

TEST(Cli, BuildWritesAReadablePatchList) {
  const std::string out = (testTempDir() / "1grm.stp").string();
  const Result r = run("build " + data("paper/1grm.pdb.gz") + " --probe 1.4 -o " + out);
  ASSERT_EQ(r.status, 0) << r.output;
  const auto p = surftrace::build::readPatchList(out);
  EXPECT_EQ(p.params.atomCount, 272u);
  EXPECT_DOUBLE_EQ(p.params.probeRadius, 1.4);
  EXPECT_GT(p.tori.size(), 0u);
  EXPECT_GT(p.concave.size(), 0u);
  EXPECT_NE(p.params.inputCrc32, 0u);
}

// Near-coincident atoms (issue 18): copies within 1e-5 Å merge with a note naming them and
// their per-atom areas are 0; a cluster that does not merge is refused in a line that says
// where and which --merge-within resolves it, and that distance does.
TEST(Cli, NearCoincidentAtomsMergeWithANoteOrAreRefused) {
  const std::string dir = testTempDir().string();
  const std::string copies = (std::filesystem::path(dir) / "copies.xyzr").string();
  const std::string crowd = (std::filesystem::path(dir) / "crowd.xyzr").string();
  {
    std::ofstream a(copies), b(crowd);
    a << "0 0 0 1.7\n3 0 0 1.7\n3.000000001 0 0 1.7\n0 0 1e-9 1.7\n";
    for (int k = 0; k < 40; ++k)
      b << 1e-4 * std::cos(k) << " " << 1e-4 * std::sin(k) << " " << 1e-6 * k << " 1.7\n";
  }
  const Result merged = run("area --format csv " + copies);
  ASSERT_EQ(merged.status, 0) << merged.output;
  EXPECT_NE(merged.output.find("surftrace: note: " + copies + ": 2 atoms lie within 1e-05 Å of a kept atom's ball"),
            std::string::npos)
      << merged.output;
  EXPECT_NE(merged.output.find("\n2,3,,,0,,,,,1.7000,0.000000,0.000000\n"), std::string::npos) << merged.output;
  EXPECT_NE(merged.output.find("\n3,4,,,0,,,,,1.7000,0.000000,0.000000\n"), std::string::npos) << merged.output;

  const Result refused = run("area " + crowd);
  EXPECT_EQ(refused.status, 1) << refused.output;
  EXPECT_NE(refused.output.find("surftrace: error: " + crowd + ": 40 atoms lie within 0.5 Å of line 1"),
            std::string::npos)
      << refused.output;
  const std::size_t at = refused.output.find("--merge-within ");
  ASSERT_NE(at, std::string::npos) << refused.output;
  const std::string distance = refused.output.substr(at + 15, refused.output.find(' ', at + 15) - at - 15);
  const Result resolved = run("area --merge-within " + distance + " " + crowd);
  ASSERT_EQ(resolved.status, 0) << resolved.output;
  EXPECT_NE(resolved.output.find("39 atoms lie within " + distance + " Å"), std::string::npos) << resolved.output;
  const Result tooSmall = run("area --merge-within 1e-6 " + crowd);
  EXPECT_EQ(tooSmall.status, 1);
  EXPECT_NE(tooSmall.output.find("--merge-within: expected a number >= 1e-05, got '1e-6'"), std::string::npos)
      << tooSmall.output;
}

}  // namespace

// `render` writes a PNG and an EXR of the requested size whose metadata holds the camera,
// and a patch list built earlier renders the same image as building it on the fly.
TEST(Cli, RenderWritesImagesWithTheirCamera) {
  const auto dir = testTempDir();
  const std::string png = (dir / "r.png").string(), exr = (dir / "r.exr").string(), exr2 = (dir / "r2.exr").string(),
                    stp = (dir / "r.stp").string();
  const Result r = run("render " + data("structures/1crn.pdb") + " --size 64x48 --quiet -o " + png + " --exr " + exr);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_TRUE(std::filesystem::file_size(png) > 100);
  const auto frame = surftrace::view::readExr(exr);
  EXPECT_EQ(frame.width, 64);
  EXPECT_EQ(frame.height, 48);
  std::size_t covered = 0;
  for (auto k : frame.kind) covered += k != 0;
  EXPECT_GT(covered, frame.pixels() / 4) << "the framed molecule should fill much of the image";
  surftrace::view::ImageMetadata meta;
  surftrace::view::readExr(exr, &meta);
  const auto camera = surftrace::view::cameraFromJson(meta.at("surftrace:camera"));
  EXPECT_EQ(camera.width, 64);

  ASSERT_EQ(run("build " + data("structures/1crn.pdb") + " -o " + stp).status, 0);
  const Result again = run("render " + data("structures/1crn.pdb") + " --patches " + stp + " --size 64x48 --quiet --exr " + exr2);
  ASSERT_EQ(again.status, 0) << again.output;
  const auto frame2 = surftrace::view::readExr(exr2);
  EXPECT_EQ(frame2.depth, frame.depth);
  EXPECT_EQ(frame2.patchId, frame.patchId);
}

// --opacity: recorded in the metadata with --max-layers, the buffers stay the nearest
// crossing's (those of the opaque image), the colour differs; the GL engine peels it (still
// refusing what it cannot draw with it, e.g. --shadows) and a value outside (0, 1] is refused.
TEST(Cli, OpacityIsRecordedAndGlPeelsIt) {
  const auto dir = testTempDir();
  const std::string opaque = (dir / "o.exr").string(), clear = (dir / "t.exr").string();
  ASSERT_EQ(run("render " + data("structures/1crn.pdb") + " --size 48x48 --quiet --exr " + opaque).status, 0);
  const Result r = run("render " + data("structures/1crn.pdb") + " --size 48x48 --opacity 0.5 --max-layers 6 --exr " + clear);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("layers per covered pixel"), std::string::npos) << r.output;
  surftrace::view::ImageMetadata meta;
  const auto t = surftrace::view::readExr(clear, &meta);
  const auto o = surftrace::view::readExr(opaque);
  EXPECT_EQ(meta.at("surftrace:opacity"), "0.500000");
  EXPECT_EQ(meta.at("surftrace:max_layers"), "6");
  EXPECT_EQ(t.kind, o.kind);
  EXPECT_NE(t.rgba, o.rgba);
  const std::string peeled = (dir / "g.exr").string();
  const Result gl = run("render " + data("structures/1crn.pdb") + " --size 48x48 --engine gl --opacity 0.5 --max-layers 6 --exr " + peeled);
  ASSERT_EQ(gl.status, 0) << gl.output;
  EXPECT_NE(gl.output.find("layers per covered pixel"), std::string::npos) << gl.output;
  const auto g = surftrace::view::readExr(peeled);
  EXPECT_EQ(g.kind, o.kind);
  EXPECT_NE(g.rgba, o.rgba);
  const Result shadows = run("render " + data("structures/1crn.pdb") + " --size 16x16 --engine gl --opacity 0.5 --shadows --exr " + clear);
  EXPECT_NE(shadows.status, 0);
  EXPECT_NE(shadows.output.find("--engine gl draws one sample per pixel without shadows"), std::string::npos) << shadows.output;
  EXPECT_NE(run("render " + data("structures/1crn.pdb") + " --opacity 0 --exr " + clear).status, 0);
  EXPECT_NE(run("render " + data("structures/1crn.pdb") + " --opacity 1.5 --exr " + clear).status, 0);
}

// --lighting: recorded in the metadata (model, rays, filter passes); the GL engine draws `simple`
// and `soft` (its shadows and occlusion from light maps: tests/gl/gl_lighting_test.cpp); an
// unknown preset is refused with the list.
TEST(Cli, LightingPresetsAreRecordedAndGlDrawsSoft) {
  const auto dir = testTempDir();
  const std::string soft = (dir / "s.exr").string(), simple = (dir / "g.exr").string();
  const Result r = run("render " + data("structures/1crn.pdb") + " --size 24x24 --quiet --lighting soft --exr " + soft);
  ASSERT_EQ(r.status, 0) << r.output;
  surftrace::view::ImageMetadata meta;
  surftrace::view::readExr(soft, &meta);
  EXPECT_NE(meta.at("surftrace:lighting").find("\"model\":\"key-fill soft\""), std::string::npos) << meta.at("surftrace:lighting");
  EXPECT_NE(meta.at("surftrace:lighting").find("\"shadow_rays\":4"), std::string::npos) << meta.at("surftrace:lighting");
  EXPECT_NE(meta.at("surftrace:lighting").find("\"filter_passes\":4"), std::string::npos) << meta.at("surftrace:lighting");
  const Result gl = run("render " + data("structures/1crn.pdb") + " --size 24x24 --quiet --engine gl --lighting simple --exr " + simple);
  ASSERT_EQ(gl.status, 0) << gl.output;
  const Result glSoft = run("render " + data("structures/1crn.pdb") + " --size 24x24 --quiet --engine gl --lighting soft --exr " + simple);
  ASSERT_EQ(glSoft.status, 0) << glSoft.output;
  // Its record names the light maps GL drew, not rays it did not trace.
  surftrace::view::ImageMetadata glMeta;
  surftrace::view::readExr(simple, &glMeta);
  const auto glLighting = nlohmann::json::parse(glMeta.at("surftrace:lighting"));
  EXPECT_EQ(glLighting.at("model"), "key-fill soft") << glLighting;
  EXPECT_EQ(glLighting.at("light_maps").at("key"), 16) << glLighting;
  EXPECT_EQ(glLighting.at("light_maps").at("ambient"), 128) << glLighting;
  EXPECT_EQ(glLighting.at("light_maps").at("key_texel_angstrom"), 0.16) << glLighting;
  EXPECT_FALSE(glLighting.contains("shadow_rays") || glLighting.contains("occlusion_rays") ||
               glLighting.contains("filter_passes") || glLighting.contains("ao_distance"))
      << glLighting;
  // GL's soft frame is as bright as Embree's over the pixels both cover, to 5 %.
  const auto softFrame = surftrace::view::readExr(simple), softEmbree = surftrace::view::readExr(soft);
  double glSum = 0.0, embreeSum = 0.0;
  for (std::size_t p = 0; p < softFrame.pixels(); ++p)
    if (softFrame.kind[p] != 0 && softEmbree.kind[p] != 0) {
      glSum += softFrame.rgba[4 * p + 1];
      embreeSum += softEmbree.rgba[4 * p + 1];
    }
  EXPECT_NEAR(glSum, embreeSum, 0.05 * embreeSum);
  const Result unknown = run("render " + data("structures/1crn.pdb") + " --lighting studio --exr " + simple);
  EXPECT_NE(unknown.status, 0);
  EXPECT_NE(unknown.output.find("headlight"), std::string::npos) << unknown.output;
}

// The skin at any shrink factor fills the picture as s = 0.5 does, and no frame clips it:
// framing takes the tighter of the patches' balls (loose as r/√s for small s) and the hull
// of the atoms grown by the largest radius (issue 23: 0.2 % of the pixels at s = 0.01 before).
TEST(Cli, WideSkinFillsThePicture) {
  const auto dir = testTempDir();
  struct Fill {
    double fraction;
    bool touchesBorder;
  };
  auto render = [&](const std::string& shrink) {
    const std::string exr = (dir / ("skin" + shrink + ".exr")).string();
    const Result r = run("render " + data("structures/1crn.pdb") + " --surface mss --shrink " + shrink +
                         " --size 64x64 --quiet --exr " + exr);
    EXPECT_EQ(r.status, 0) << r.output;
    const auto frame = surftrace::view::readExr(exr);
    std::size_t covered = 0;
    bool border = false;
    for (int y = 0; y < frame.height; ++y)
      for (int x = 0; x < frame.width; ++x)
        if (frame.kind[static_cast<std::size_t>(y) * frame.width + x] != 0) {
          ++covered;
          border = border || x == 0 || y == 0 || x == frame.width - 1 || y == frame.height - 1;
        }
    return Fill{static_cast<double>(covered) / static_cast<double>(frame.pixels()), border};
  };
  const Fill half = render("0.5");
  EXPECT_GT(half.fraction, 0.25);
  EXPECT_FALSE(half.touchesBorder);
  for (const char* s : {"0.01", "0.05", "0.1", "0.3"}) {
    const Fill f = render(s);
    EXPECT_GT(f.fraction, 0.7 * half.fraction) << "s = " << s << " fills " << f.fraction << " of the image, s = 0.5 "
                                               << half.fraction;
    EXPECT_FALSE(f.touchesBorder) << "s = " << s;
  }
}

// Issue 18: eight atoms on a 3 Å cube moved by ~1e-11 Å leave a sliver tetrahedron on a face
// whose concave sphere, about an orthocentre 3 Å off, holds no skin. Its ball moved the view of
// the skin rendered from its patch list alone (which frames on the patches' balls): the look-at
// point by 3.1 Å and the eye 12 Å further. The jittered cube is framed as the exact one.
TEST(Cli, SliverPatchesDoNotMoveTheSkinsFraming) {
  const auto dir = testTempDir();
  const char* exact[] = {"0 0 0", "3 0 0", "0 3 0", "3 3 0", "0 0 3", "3 0 3", "0 3 3", "3 3 3"};
  const char* jittered[] = {"-5.4658828123790234e-12 9.2459007166876556e-12 -7.4733820269828078e-12",
                            "3.0000000000040963 -8.2962946389849461e-12 -5.0511803014182982e-12",
                            "9.9825707832515798e-12 2.9999999999941878 2.8373687014421398e-12",
                            "2.9999999999991829 2.9999999999990625 -1.0034612221644589e-13",
                            "-6.1553831551463561e-12 6.610425472659433e-12 2.9999999999917915",
                            "2.9999999999946838 -9.6001738755163842e-12 2.9999999999953353",
                            "-1.8467227407808572e-12 3.0000000000080411 2.9999999999975815",
                            "2.9999999999922746 2.999999999995167 3.0000000000098321"};
  auto camera = [&](const std::string& name, const char* const* atoms, const std::string& view) {
    const std::string xyz = (dir / (name + ".xyz")).string(), stp = (dir / (name + ".stp")).string(),
                      exr = (dir / (name + ".exr")).string();
    {
      std::ofstream f(xyz);
      f << "8\ncube\n";
      for (int k = 0; k < 8; ++k) f << "C " << atoms[k] << "\n";
    }
    const Result b = run("build " + xyz + " --surface mss --shrink 0.3 -o " + stp);
    EXPECT_EQ(b.status, 0) << b.output;
    const Result r = run("render " + stp + " --view=" + view + " --size 16x16 --quiet --exr " + exr);
    EXPECT_EQ(r.status, 0) << r.output;
    surftrace::view::ImageMetadata meta;
    surftrace::view::readExr(exr, &meta);
    return surftrace::view::cameraFromJson(meta.at("surftrace:camera"));
  };
  for (const std::string view : {"front", "left", "1,-1,0.5"}) {
    const auto a = camera("exact", exact, view), b = camera("jittered", jittered, view);
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(a.eye[k], b.eye[k], 1e-6) << view;
      EXPECT_NEAR(a.lookAt[k], b.lookAt[k], 1e-6) << view;
    }
  }
}

// `info --xyzr` writes the atoms as the commands use them (issue 20): read back, they are the
// same doubles as the structure gives with the same choices (water dropped, chains chosen).
TEST(Cli, InfoWritesTheAtomsAsXyzrExactly) {
  const auto dir = testTempDir();
  const std::string xyzr = (dir / "1vis_chainA.xyzr").string();
  const Result r = run("info " + data("paper/1vis.pdb.gz") + " --chains A --xyzr " + xyzr);
  ASSERT_EQ(r.status, 0) << r.output;
  surftrace::build::ReadOptions chosen;
  chosen.chains = {"A"};
  const auto original = surftrace::build::readMolecule(data("paper/1vis.pdb.gz"), chosen);
  const auto written = surftrace::build::readMolecule(xyzr);
  ASSERT_EQ(written.size(), original.size());
  EXPECT_EQ(written.centers, original.centers);
  EXPECT_EQ(written.radii, original.radii);
  const Result stp = run("info " + xyzr + ".stp --xyzr " + xyzr);
  EXPECT_NE(stp.status, 0);
}

using ::surftrace::test::sameBytes;  // frame_buffers_equal.hpp

// Two EXRs of one view: the same camera, a tenth of the image covered, and every buffer
// equal bit for bit.
void expectSameImage(const std::string& a, const std::string& b, const std::string& engine) {
  surftrace::view::ImageMetadata ma, mb;
  const auto fa = surftrace::view::readExr(a, &ma), fb = surftrace::view::readExr(b, &mb);
  EXPECT_EQ(ma.at("surftrace:camera"), mb.at("surftrace:camera")) << engine;
  std::size_t covered = 0;
  for (auto k : fa.kind) covered += k != 0;
  EXPECT_GT(covered, fa.pixels() / 10) << engine;
  EXPECT_TRUE(sameBytes(fa.rgba, fb.rgba)) << engine;
  EXPECT_TRUE(sameBytes(fa.depth, fb.depth)) << engine;
  EXPECT_TRUE(sameBytes(fa.viewZ, fb.viewZ)) << engine;
  EXPECT_TRUE(sameBytes(fa.normal, fb.normal)) << engine;
  EXPECT_TRUE(sameBytes(fa.kind, fb.kind)) << engine;
  EXPECT_TRUE(sameBytes(fa.patchId, fb.patchId)) << engine;
  EXPECT_TRUE(sameBytes(fa.atomId, fb.atomId)) << engine;
  EXPECT_TRUE(sameBytes(fa.flags, fb.flags)) << engine;
}

// `build`'s patch list rendered as FILE (named without .stp: it is told by its magic) gives
// the image the structure gives, buffer for buffer and bit for bit, on both engines, with
// the same camera; `area` of it gives the structure's areas.
TEST(Cli, PatchListRendersAsTheStructureDoes) {
  const auto dir = testTempDir();
  const std::string mol = data("structures/1crn.pdb"), stp = (dir / "crn.patches").string();
  ASSERT_EQ(run("build " + mol + " -o " + stp + ".stp").status, 0);  // `build` names it .stp
  std::filesystem::rename(stp + ".stp", stp);
  for (const std::string engine : {"embree", "gl"}) {
    const std::string a = (dir / ("from_structure_" + engine + ".exr")).string();
    const std::string b = (dir / ("from_patches_" + engine + ".exr")).string();
    const std::string common = " --size 64x48 --quiet --view 1,-0.5,0.3 --engine " + engine + " --exr ";
    const Result r1 = run("render " + mol + common + a);
    ASSERT_EQ(r1.status, 0) << r1.output;
    const Result r2 = run("render " + stp + common + b);
    ASSERT_EQ(r2.status, 0) << r2.output;
    expectSameImage(a, b, engine);
  }
  const Result areaMol = run("area --format json " + mol), areaStp = run("area --format json " + stp);
  ASSERT_EQ(areaStp.status, 0) << areaStp.output;
  const auto jm = nlohmann::json::parse(areaMol.output), js = nlohmann::json::parse(areaStp.output);
  EXPECT_EQ(jm["ses"]["total"], js["ses"]["total"]);
  EXPECT_EQ(jm["sas"]["total"], js["sas"]["total"]);
  EXPECT_EQ(jm["ses"]["volume"], js["ses"]["volume"]);
  const Result info = run("info " + stp);
  EXPECT_NE(info.output.find("SurfTrace patch list"), std::string::npos) << info.output;
  // What a patch list cannot do is said, not guessed.
  EXPECT_NE(run("render " + stp + " --quiet --color element -o x.png").output.find("needs the atoms' records"),
            std::string::npos);
  EXPECT_NE(run("area --probe 3 " + stp).output.find("cannot change it"), std::string::npos);
  EXPECT_NE(run("build " + stp + " -o y.stp").output.find("is a patch list already"), std::string::npos);
}

TEST(Cli, RenderRejectsImpossibleOptionsClearly) {
  const std::string out = (testTempDir() / "x.png").string();
  const std::string mol = data("structures/1crn.pdb");
  struct Case {
    std::string args, mustSay;
  };
  const Case cases[] = {
      {"--size 0x10", "--size '0x10'"},
      {"--size 10", "--size '10'"},
      {"--view sideways", "unknown view 'sideways'"},
      {"--view 0,0,0", "unknown view '0,0,0'"},
      {"--eye 1,2", "--eye '1,2'"},
      {"--fov 180", "field of view"},
      {"--background 2,0,0", "--background"},
      {"--color jet", "jet"},
      {"--patches " + data("structures/1crn.pdb"), "not a SurfTrace patch list"},
  };
  for (const auto& c : cases) {
    const Result r = run("render " + mol + " --quiet -o " + out + " " + c.args);
    EXPECT_NE(r.status, 0) << c.args;
    EXPECT_NE(r.output.find(c.mustSay), std::string::npos) << c.args << "\n" << r.output;
  }
  const Result none = run("render " + mol + " --quiet");
  EXPECT_NE(none.status, 0);
  EXPECT_NE(none.output.find("nothing to write"), std::string::npos) << none.output;
  // A patch list of another molecule is refused, not rendered as a wrong picture.
  const std::string stp = (testTempDir() / "other.stp").string();
  ASSERT_EQ(run("build " + data("small/1grm_single.pdb") + " -o " + stp).status, 0);
  const Result other = run("render " + mol + " --quiet -o " + out + " --patches " + stp);
  EXPECT_NE(other.status, 0);
  EXPECT_NE(other.output.find("different input"), std::string::npos) << other.output;
}

// Without --preset, compare judges by the strict limits for the two images' engines and says
// which: an SES against the vdW spheres, the skin against the SES and a blank image against a
// real one all fail (exit 2); a re-render passes `exact`, GL against Embree `gl-vs-embree`.
TEST(Cli, CompareDefaultsToTheStrictPresetOfItsEngines) {
  const auto dir = testTempDir();
  const std::string mol = data("structures/1crn.pdb");
  const std::string camera = " --size 48x48 --eye 9,10,60 --look-at 9,10,7 --fov 40 --quiet --exr ";
  auto render = [&](const std::string& name, const std::string& args) {
    const std::string exr = (dir / (name + ".exr")).string();
    const Result r = run("render " + mol + " " + args + camera + exr);
    EXPECT_EQ(r.status, 0) << r.output;
    return exr;
  };
  const std::string ses = render("cmp_ses", ""), again = render("cmp_again", ""),
                    vdw = render("cmp_vdw", "--surface vdw"), skin = render("cmp_skin", "--surface mss --shrink 0.5"),
                    gl = render("cmp_gl", "--engine gl");
  const std::string blank = (dir / "cmp_blank.exr").string();
  ASSERT_EQ(run("render " + mol + " --size 48x48 --eye 9,10,60 --look-at 9,10,120 --fov 40 --quiet --exr " + blank).status, 0);

  const Result same = run("compare " + again + " " + ses);
  EXPECT_EQ(same.status, 0) << same.output;
  EXPECT_NE(same.output.find("--preset exact"), std::string::npos) << same.output;
  EXPECT_NE(same.output.find("PASS (exact)"), std::string::npos) << same.output;
  // (The blank image looks away from the molecule: another camera, so --ignore-camera.)
  for (const std::string& wrong : {vdw, skin, blank + " --ignore-camera"}) {
    const Result r = run("compare " + wrong + " " + ses);
    EXPECT_EQ(r.status, 2) << wrong << "\n" << r.output;
    EXPECT_NE(r.output.find("--preset exact"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("FAIL"), std::string::npos) << r.output;
  }
  const Result engines = run("compare " + gl + " " + ses);
  EXPECT_EQ(engines.status, 0) << engines.output;
  EXPECT_NE(engines.output.find("--preset gl-vs-embree"), std::string::npos) << engines.output;
  // Metrics alone, on purpose.
  const Result none = run("compare " + vdw + " " + ses + " --preset none");
  EXPECT_EQ(none.status, 0) << none.output;
  EXPECT_NE(none.output.find("no limits"), std::string::npos) << none.output;
}

// `--drop-cavities` keeps the outer component: its area is the full run's component 0.
TEST(Cli, DropCavitiesKeepsTheOuterSurface) {
  const Result all = run("area --format json " + data("structures/1crn.pdb"));
  const Result outer = run("area --format json --drop-cavities " + data("structures/1crn.pdb"));
  ASSERT_EQ(all.status, 0) << all.output;
  ASSERT_EQ(outer.status, 0) << outer.output;
  const auto a = nlohmann::json::parse(all.output), b = nlohmann::json::parse(outer.output);
  ASSERT_GE(a["ses"]["components"].size(), 2u);
  ASSERT_EQ(b["ses"]["components"].size(), 1u);
  EXPECT_FALSE(a["ses"]["components"][0]["cavity"].get<bool>());
  EXPECT_TRUE(a["ses"]["components"][1]["cavity"].get<bool>());
  EXPECT_LT(a["ses"]["components"][1]["volume"].get<double>(), 0.0);
  // The convex patches of atoms that also face the cavity are kept (drawn whole), with the
  // outer side's area alone: the kept list's area and volume are the outer surface's.
  const double outerArea = a["ses"]["components"][0]["area"].get<double>();
  EXPECT_NEAR(b["ses"]["total"].get<double>(), outerArea, 1e-9 * outerArea);
  EXPECT_NEAR(b["ses"]["volume"].get<double>(), a["ses"]["components"][0]["volume"].get<double>(),
              1e-9 * a["ses"]["volume"].get<double>());
  EXPECT_LT(b["ses"]["total"].get<double>(), a["ses"]["total"].get<double>());
}

// A cavity cannot be seen from outside: dropping the cavities changes no pixel's depth
// (1AON once showed 52 holes, up to 21.8 Å deep at 256², where pieces of outer surfaces cut
// off at self-intersection circles were labelled cavities).
TEST(Cli, DropCavitiesChangesNoPixel) {
  const auto dir = testTempDir();
  for (const char* file : {"structures/1crn.pdb", "paper/1vis.pdb.gz", "paper/1aon.pdb.gz"}) {
    const std::string all = (dir / "all.exr").string(), outer = (dir / "outer.exr").string();
    const std::string common = " --size 96x96 --quiet --exr ";
    ASSERT_EQ(run("render " + data(file) + common + all).status, 0) << file;
    ASSERT_EQ(run("render " + data(file) + " --drop-cavities" + common + outer).status, 0) << file;
    const auto a = surftrace::view::readExr(all), b = surftrace::view::readExr(outer);
    ASSERT_EQ(a.depth.size(), b.depth.size()) << file;
    std::size_t differ = 0;
    for (std::size_t k = 0; k < a.depth.size(); ++k)
      differ += !(a.depth[k] == b.depth[k] || (std::isinf(a.depth[k]) && std::isinf(b.depth[k]))) || a.kind[k] != b.kind[k];
    EXPECT_EQ(differ, 0u) << file;
  }
}

// A .stp whose checksum is right but whose content is impossible (a component index of
// 0xFFFFFFFF, which `area` once used as a vector index) is an error naming the file, the field
// and the value, from `area` and `info` alike: not a crash, not a number.
// The skin's patch list, whose file stores the patches by reference to the atoms (version 3)
// and derives them again on reading, renders as the skin built in memory from the structure:
// every buffer bit for bit, on both engines, through the structure's camera (`render` frames a
// skin's list without its structure otherwise: render_command.cpp, frameRender).
TEST(Cli, SkinPatchListRendersAsTheStructureDoes) {
  const auto dir = testTempDir();
  const std::string mol = data("paper/1grm.pdb.gz"), stp = (dir / "grm_mss.stp").string();
  ASSERT_EQ(run("build " + mol + " --surface mss --shrink 0.5 -o " + stp).status, 0);
  for (const std::string engine : {"embree", "gl"}) {
    const std::string a = (dir / ("skin_from_structure_" + engine + ".exr")).string();
    const std::string b = (dir / ("skin_from_patches_" + engine + ".exr")).string();
    const std::string camera = (dir / ("skin_camera_" + engine + ".json")).string();
    const std::string common = " --size 64x48 --quiet --engine " + engine + " --exr ";
    const Result r1 = run("render " + mol + " --surface mss --shrink 0.5 --view 1,-0.5,0.3 --camera-out " + camera +
                          common + a);
    ASSERT_EQ(r1.status, 0) << r1.output;
    const Result r2 = run("render " + stp + " --camera " + camera + common + b);
    ASSERT_EQ(r2.status, 0) << r2.output;
    expectSameImage(a, b, engine);
  }
}

TEST(Cli, DamagedStpBehindAValidChecksumIsAnErrorNotACrash) {
  const std::string stp = (testTempDir() / "1crn-damaged.stp").string();
  const Result b = run("build " + data("structures/1crn.pdb") + " -o " + stp);
  ASSERT_EQ(b.status, 0) << b.output;
  std::vector<unsigned char> bytes;
  {
    std::ifstream in(stp, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  // convex.component[0] := 0xFFFFFFFF: after the array's name (u32 length, text), its u32 type,
  // u32 width and u64 count.
  const std::string name = "convex.component";
  const auto at = std::search(bytes.begin(), bytes.end(), name.begin(), name.end());
  ASSERT_NE(at, bytes.end());
  const std::uint32_t bad = 0xFFFFFFFFu;
  std::memcpy(&*at + name.size() + 16, &bad, 4);
  // The CRC-32 of the body (after the 24-byte header, before the 4-byte checksum), recomputed.
  std::uint32_t crc = 0xFFFFFFFFu;
  for (std::size_t k = 24; k + 4 < bytes.size(); ++k) {
    crc ^= bytes[k];
    for (int bit = 0; bit < 8; ++bit) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  crc ^= 0xFFFFFFFFu;
  std::memcpy(bytes.data() + bytes.size() - 4, &crc, 4);
  std::ofstream(stp, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));

  for (const char* command : {"area ", "area --drop-cavities ", "info "}) {
    const Result r = run(command + stp);
    EXPECT_EQ(r.status, 1) << command << r.output;
    EXPECT_NE(r.output.find(stp + ": corrupt patch list: convex.component[0] = 4294967295"), std::string::npos)
        << command << r.output;
    EXPECT_NE(r.output.find("damaged"), std::string::npos) << command << r.output;
  }
}
