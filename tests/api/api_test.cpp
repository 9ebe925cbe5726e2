// The public API (include/surftrace/) against formulas: areas and volumes of spheres that do
// not touch and of two that overlap, the framing against the camera's own matrices, and the
// way a program reads, builds and writes through it.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include "surftrace/surftrace.hpp"
#include "temp_dir.hpp"

namespace {

constexpr double kPi = std::numbers::pi;

// The test's own folder (temp_dir.hpp).
struct TempFolder {
  std::filesystem::path path = surftrace::test::testTempDir();
};

// An XYZR file of the given spheres (x y z r per line).
std::string writeXyzr(const TempFolder& folder, const std::string& name, const std::vector<glm::dvec4>& atoms) {
  const std::filesystem::path file = folder.path / name;
  std::ofstream out(file);
  out.precision(17);
  for (const glm::dvec4& a : atoms) out << a.x << ' ' << a.y << ' ' << a.z << ' ' << a.w << '\n';
  return file.string();
}

TEST(PublicApi, SeparateAtomsHaveTheAreasAndVolumesOfTheirSpheres) {
  // Three atoms further apart than two probe diameters: the SES is each vdW sphere, the SAS
  // each sphere of radius r + rp, the skin at any s each sphere (its balls do not meet).
  const TempFolder folder;
  const std::vector<glm::dvec4> atoms = {{0, 0, 0, 1.5}, {20, 0, 0, 1.7}, {0, 25, 3, 1.2}};
  const surftrace::Molecule molecule = surftrace::readStructure(writeXyzr(folder, "three.xyzr", atoms));
  ASSERT_EQ(molecule.size(), 3u);
  const double rp = 1.4;
  surftrace::SurfaceRequest ses;
  ses.probeRadius = rp;
  const surftrace::SurfaceAreas a = surftrace::surfaceAreas(surftrace::buildSurface(molecule, ses), molecule.centers);
  double area = 0.0, sas = 0.0, volume = 0.0;
  for (std::size_t i = 0; i < atoms.size(); ++i) {
    const double r = atoms[i].w;
    EXPECT_NEAR(a.perAtom[i], 4 * kPi * r * r, 1e-9) << i;
    EXPECT_NEAR(a.sasPerAtom[i], 4 * kPi * (r + rp) * (r + rp), 1e-9) << i;
    area += 4 * kPi * r * r;
    sas += 4 * kPi * (r + rp) * (r + rp);
    volume += 4.0 / 3.0 * kPi * r * r * r;
  }
  EXPECT_EQ(a.surface, surftrace::SurfaceKind::Ses);
  EXPECT_NEAR(a.total, area, 1e-9);
  EXPECT_NEAR(a.sas, sas, 1e-9);
  EXPECT_NEAR(a.volume, volume, 1e-9);
  ASSERT_EQ(a.components.size(), 3u);
  for (const surftrace::ComponentArea& c : a.components) EXPECT_FALSE(c.cavity);
  ASSERT_EQ(a.kindNames.size(), a.byKind.size());
  EXPECT_NEAR(a.byKind[0], area, 1e-9);  // all convex
}

TEST(PublicApi, TheSkinAtOneIsTheUnionOfTwoOverlappingBalls) {
  // Two balls whose spheres cross in a circle at distance x from the first centre: the union's
  // area is both spheres less the caps inside the other, 2πr·h each (Archimedes).
  const TempFolder folder;
  const double r1 = 1.5, r2 = 1.7, d = 2.0;
  const surftrace::Molecule molecule =
      surftrace::readStructure(writeXyzr(folder, "two.xyzr", {{0, 0, 0, r1}, {d, 0, 0, r2}}));
  surftrace::SurfaceRequest skin;
  skin.surface = surftrace::SurfaceKind::Mss;
  skin.shrinkFactor = 1.0;
  const surftrace::PatchList list = surftrace::buildSurface(molecule, skin);
  EXPECT_EQ(list.params.surface, surftrace::SurfaceKind::Vdw);  // built as the vdW spheres
  const surftrace::SurfaceAreas a = surftrace::surfaceAreas(list, molecule.centers);
  const double x = (d * d + r1 * r1 - r2 * r2) / (2 * d);
  const double h1 = r1 - x, h2 = r2 - (d - x);
  EXPECT_NEAR(a.perAtom[0], 4 * kPi * r1 * r1 - 2 * kPi * r1 * h1, 1e-9);
  EXPECT_NEAR(a.perAtom[1], 4 * kPi * r2 * r2 - 2 * kPi * r2 * h2, 1e-9);
  EXPECT_NEAR(a.total, a.perAtom[0] + a.perAtom[1], 1e-9);
  // Volume: both balls less the two caps' volumes πh²(3r − h)/3.
  const double volume = 4.0 / 3.0 * kPi * (r1 * r1 * r1 + r2 * r2 * r2) - kPi * h1 * h1 * (3 * r1 - h1) / 3 -
                        kPi * h2 * h2 * (3 * r2 - h2) / 3;
  EXPECT_NEAR(a.volume, volume, 1e-9);
}

TEST(PublicApi, AreasOfSpheresWithoutPatchesOfTheirOwnAreRefused) {
  const TempFolder folder;
  const surftrace::Molecule molecule = surftrace::readStructure(writeXyzr(folder, "one.xyzr", {{0, 0, 0, 1.5}}));
  surftrace::SurfaceRequest sas;
  sas.surface = surftrace::SurfaceKind::Sas;
  EXPECT_THROW(surftrace::surfaceAreas(surftrace::buildSurface(molecule, sas), molecule.centers),
               std::invalid_argument);
}

// Where a point lands in normalised device coordinates of the camera's own GL matrices.
glm::dvec3 ndc(const surftrace::Camera& camera, const glm::dvec3& p) {
  const glm::dvec4 clip = camera.projectionMatrix() * camera.viewMatrix() * glm::dvec4(p, 1.0);
  return glm::dvec3(clip) / clip.w;
}

TEST(PublicApi, AFramedCameraSeesAllOfWhatTheSurfaceCanReach) {
  const surftrace::Molecule molecule =
      surftrace::readStructure(std::string(SURFTRACE_TEST_DATA) + "/structures/1crn.pdb");
  surftrace::SurfaceRequest request;
  const surftrace::PatchList list = surftrace::buildSurface(molecule, request);
  surftrace::Camera base;
  base.width = 320;
  base.height = 200;
  for (const char* view : {"front", "left", "top"}) {
    surftrace::Framing framing;
    framing.direction = surftrace::namedViewDirection(view);
    const surftrace::Camera camera = surftrace::frameSurface(base, framing, list, molecule);
    ASSERT_TRUE(camera.hasDepthRange());
    // Every atom's ball grown by the probe (how far the SES reaches) is in view: the ends of
    // its diameters along the camera's axes land inside the clip volume.
    const std::vector<double> reach = request.reach(molecule.radii);
    double widest = 0.0;
    for (std::size_t i = 0; i < molecule.size(); ++i)
      for (const glm::dvec3& axis : {camera.right(), camera.trueUp(), camera.forward()})
        for (double sign : {-1.0, 1.0}) {
          const glm::dvec3 p = ndc(camera, molecule.centers[i] + sign * reach[i] * axis);
          EXPECT_LE(std::abs(p.x), 1.0) << view << " atom " << i;
          EXPECT_LE(std::abs(p.y), 1.0) << view << " atom " << i;
          EXPECT_LE(std::abs(p.z), 1.0) << view << " atom " << i;
          widest = std::max({widest, std::abs(p.x), std::abs(p.y)});
        }
    EXPECT_GT(widest, 0.8) << view << ": framed, not merely in view";
  }
}

TEST(PublicApi, AFixedCameraIsKeptAndAJsonRoundTripKeepsIt) {
  const TempFolder folder;
  const surftrace::Molecule molecule = surftrace::readStructure(writeXyzr(folder, "one.xyzr", {{1, 2, 3, 1.5}}));
  const surftrace::PatchList list = surftrace::buildSurface(molecule, {});
  surftrace::Camera fixed;
  fixed.eye = {0, 0, 40};
  fixed.lookAt = {1, 2, 3};
  surftrace::Framing framing;
  framing.fixed = fixed;
  const surftrace::Camera camera = surftrace::frameSurface(surftrace::Camera{}, framing, list, molecule);
  EXPECT_EQ(camera.eye, fixed.eye);
  EXPECT_EQ(camera.lookAt, fixed.lookAt);
  // The depth range is taken from the scene (the camera had none): it holds the atom's ball
  // grown by the probe, whose centre is the look-at point.
  ASSERT_TRUE(camera.hasDepthRange());
  const double centre = glm::length(fixed.lookAt - fixed.eye), reach = 1.5 + 1.4;
  EXPECT_LE(camera.zNear, centre - reach);
  EXPECT_GE(camera.zFar, centre + reach);
  const std::string path = (folder.path / "camera.json").string();
  surftrace::writeCamera(path, camera);
  const surftrace::Camera back = surftrace::readCamera(path);
  EXPECT_EQ(back.eye, camera.eye);
  EXPECT_EQ(back.zFar, camera.zFar);
}

TEST(PublicApi, APatchListFileComesBackAndIsToldFromAStructure) {
  const TempFolder folder;
  const std::string xyzr = writeXyzr(folder, "two.xyzr", {{0, 0, 0, 1.5}, {2.5, 0, 0, 1.6}});
  const surftrace::Molecule molecule = surftrace::readStructure(xyzr);
  const surftrace::PatchList list = surftrace::buildSurface(molecule, {});
  const std::string stp = (folder.path / "two.stp").string();
  surftrace::writePatchList(stp, list, {molecule.centers, molecule.radii});
  EXPECT_TRUE(surftrace::isPatchListPath(stp));
  EXPECT_FALSE(surftrace::isPatchListPath(xyzr));
  const surftrace::PatchList back = surftrace::readPatchList(stp);
  EXPECT_EQ(surftrace::surfaceAreas(back, molecule.centers).total, surftrace::surfaceAreas(list, molecule.centers).total);
}

}  // namespace
