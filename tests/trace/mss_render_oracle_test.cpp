// Rendered molecular-skin images against the skin function from its definition (ORACLES D.3):
// every hit is certified on the skin in the mixed cell of its patch's simplex, no ray passes
// a point of the skin body before its hit (or at all, when it misses), and random views of
// closed molecules show no back-facing first hit (a hole would) — a check that fails when
// every other hyperboloid is left out.
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "build/io/molecule.hpp"
#include "build/mss/mss_builder.hpp"
#include "oracles/skin_certificate.hpp"
#include "trace/render.hpp"

namespace surftrace::trace {
namespace {

using view::Camera;
using view::FrameBuffers;
using view::Projection;
using view::RenderOptions;

constexpr double kTolerance = 1e-9;  // |G| and the certificate gap, relative to the weights

build::Molecule molecule(const std::string& file) {
  return build::readMolecule(std::string(SURFTRACE_TEST_DATA) + "/" + file);
}

Camera framed(const build::PatchList& list, const glm::dvec3& direction, int size, Projection projection) {
  Camera c;
  c.width = c.height = size;
  c.projection = projection;
  return view::frameSpheres(c, list.mss.center, list.mss.boundRadius, direction);
}

glm::dvec3 randomDirection(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  glm::dvec3 d;
  do d = {n(rng), n(rng), n(rng)};
  while (glm::length(d) < 1e-3);
  return glm::normalize(d);
}

// The simplex of a skin hit, from the scene row of its kind.
std::vector<unsigned> simplexOf(const ScenePatches& patches, const SceneHit& h) {
  std::vector<unsigned> out;
  patches.forEachKind([&](const auto& k) {
    using Row = typename std::remove_reference_t<decltype(k)>::Row;
    if constexpr (std::is_same_v<typename Row::Patch, MssPatch>) {
      if (Row::kind != h.kind) return;
      const glm::uvec4 a = k.atoms[h.patch];
      for (int m = 0; m < 4; ++m)
        if (a[m] != ~0u) out.push_back(a[m]);
    }
  });
  return out;
}

struct SkinCase {
  const char* file;
  double s;
};

class RenderOnSkin : public testing::TestWithParam<SkinCase> {};

TEST_P(RenderOnSkin, HitsAreCertifiedAndNoRayCrossesTheBody) {
  const SkinCase& sc = GetParam();
  const build::Molecule m = molecule(sc.file);
  const build::PatchList list = build::buildMss(m.centers, m.radii, {sc.s});
  const PatchScene scene(ScenePatches::fromPatchList(list));
  // The box of every patch's bounding ball: no skin outside it.
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (std::size_t k = 0; k < list.mss.size(); ++k) {
    lo = glm::min(lo, list.mss.center[k] - list.mss.boundRadius[k]);
    hi = glm::max(hi, list.mss.center[k] + list.mss.boundRadius[k]);
  }
  std::mt19937_64 rng(5);
  int hits = 0, checked = 0, undecided = 0;
  double worstValue = 0.0;
  for (int viewIndex = 0; viewIndex < 2; ++viewIndex) {
    RenderOptions o;
    o.camera = framed(list, randomDirection(rng), 32, viewIndex == 0 ? Projection::Perspective : Projection::Orthographic);
    const FrameBuffers f = render(scene, o, {});
    for (int y = 0; y < f.height; ++y)
      for (int x = 0; x < f.width; ++x) {
        const std::size_t p = static_cast<std::size_t>(y) * f.width + x;
        const Ray ray = o.camera.ray(x + 0.5, y + 0.5);
        const double len = glm::length(ray.dir);
        const glm::dvec3 d = ray.dir / len;
        // Where the ray is inside the box (slab test), in Å along d.
        double tBegin = 0.0, tEnd = std::numeric_limits<double>::infinity();
        for (int k = 0; k < 3; ++k) {
          const double a = (lo[k] - ray.org[k]) / d[k], b = (hi[k] - ray.org[k]) / d[k];
          tBegin = std::max(tBegin, std::min(a, b));
          tEnd = std::min(tEnd, std::max(a, b));
        }
        const SceneHit h = scene.intersect1(ray, 0.0, std::numeric_limits<double>::infinity());
        ASSERT_EQ(h.valid(), f.kind[p] != 0) << "pixel " << x << "," << y;
        if (h.valid()) {
          ++hits;
          const glm::dvec3 point = ray.org + h.hit.t * ray.dir;
          const std::vector<unsigned> simplex = simplexOf(scene.patches(), h);
          ASSERT_FALSE(simplex.empty());
          const oracle::SkinCertificate c = oracle::certifySkinPoint(m.centers, m.radii, sc.s, simplex, point);
          const double value = std::abs(c.value) / c.scale;
          worstValue = std::max(worstValue, value);
          // A hit flagged as grazing or at a seam may lie a rounding outside its own cell.
          const bool seam = h.hit.flags & (kHitGrazing | kHitNearBoundary);
          EXPECT_LE(value, kTolerance) << sc.file << " pixel " << x << "," << y;
          if (!seam) {
            EXPECT_GE(c.minLambda, -kTolerance) << sc.file << " pixel " << x << "," << y;
            EXPECT_GE(c.minGap / c.scale, -kTolerance) << sc.file << " pixel " << x << "," << y;
          }
          tEnd = h.hit.t * len - 1e-3;
        }
        for (double t = tBegin; t < tEnd; t += 0.3) {
          const int sign = oracle::skinSign(m.centers, m.radii, sc.s, ray.org + t * d);
          ++checked;
          if (sign == 0) {
            ++undecided;
          } else if (sign < 0) {
            ADD_FAILURE() << sc.file << " s = " << sc.s << " pixel " << x << "," << y << ": the ray enters the skin body at t = "
                          << t << (h.valid() ? " before its hit" : " but the pixel is a miss");
            break;
          }
        }
      }
  }
  std::printf("[ stats    ] %s s = %.1f: %d hits certified (worst |G|/w %.2g), %d body samples, %d undecided\n", sc.file,
              sc.s, hits, worstValue, checked, undecided);
  EXPECT_GT(hits, 300);
  EXPECT_LT(undecided, checked / 100);
}

// The BVH, whose skin boxes are cut by the cell planes (cellBounds), finds what a plain loop
// over every patch finds (same depth; another patch only at a tie), and a 16-ray packet finds
// exactly, bit for bit, what each of its rays finds alone.
TEST_P(RenderOnSkin, SceneMatchesAPlainLoopAndPacketsMatchSingleRays) {
  const build::PatchList list = build::buildMss(molecule(GetParam().file).centers, molecule(GetParam().file).radii,
                                                build::MssParams{GetParam().s});
  const PatchScene scene(ScenePatches::fromPatchList(list));
  const ScenePatches& patches = scene.patches();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::mt19937_64 rng(23);
  int hits = 0, compared = 0;
  for (int v = 0; v < 3; ++v) {
    const Camera cam = framed(list, randomDirection(rng), 40, Projection::Perspective);
    for (int y = 0; y + 4 <= cam.height; y += 4)
      for (int x = 0; x + 4 <= cam.width; x += 4) {
        Ray rays[16];
        bool valid[16];
        for (int j = 0; j < 16; ++j) {
          valid[j] = true;
          rays[j] = cam.ray(x + j % 4 + 0.5, y + j / 4 + 0.5);
        }
        SceneHit packet[16];
        scene.intersect16(rays, valid, 0.0, packet);
        for (int j = 0; j < 16; ++j) {
          const SceneHit single = scene.intersect1(rays[j], 0.0, kInf);
          const SceneHit loop = patches.intersectAll(rays[j], 0.0, kInf);
          ++compared;
          ASSERT_EQ(loop.valid(), packet[j].valid()) << "view " << v << " pixel " << x + j % 4 << "," << y + j / 4;
          ASSERT_EQ(single.valid(), packet[j].valid());
          if (!loop.valid()) continue;
          ++hits;
          EXPECT_EQ(single.hit.t, packet[j].hit.t);
          EXPECT_EQ(single.kind, packet[j].kind);
          EXPECT_EQ(single.patch, packet[j].patch);
          EXPECT_EQ(single.hit.flags, packet[j].hit.flags);
          const double scale = glm::length(rays[j].dir);
          EXPECT_NEAR(loop.hit.t * scale, packet[j].hit.t * scale, 1e-9) << "view " << v;
          if (loop.kind != packet[j].kind || loop.patch != packet[j].patch) {
            const SceneHit other = patches.intersectPatch(packet[j].kind, packet[j].patch, rays[j], 0.0, kInf);
            EXPECT_NEAR(other.hit.t * scale, loop.hit.t * scale, 1e-9);
          }
        }
      }
  }
  EXPECT_GT(hits, 1000);
  EXPECT_GT(compared, hits);
}

INSTANTIATE_TEST_SUITE_P(Molecules, RenderOnSkin,
                         testing::Values(SkinCase{"structures/1crn.pdb", 0.3}, SkinCase{"structures/1crn.pdb", 0.5},
                                         SkinCase{"paper/1grm.pdb.gz", 0.5}));

// Back-facing first hits over random views: a ray that meets the skin from inside went through
// a hole. Counted on the full list (must be none) and with every other edge hyperboloid left
// out (must be many: the sweep can fail).
int backFacingFirstHits(const build::PatchList& list, int views, std::uint64_t seed) {
  const PatchScene scene(ScenePatches::fromPatchList(list));
  std::mt19937_64 rng(seed);
  int backFacing = 0;
  for (int v = 0; v < views; ++v) {
    RenderOptions o;
    o.camera = framed(list, randomDirection(rng), 48, Projection::Perspective);
    for (int y = 0; y < o.camera.height; ++y)
      for (int x = 0; x < o.camera.width; ++x) {
        const Ray ray = o.camera.ray(x + 0.5, y + 0.5);
        const SceneHit h = scene.intersect1(ray, 0.0, std::numeric_limits<double>::infinity());
        if (!h.valid() || (h.hit.flags & kHitGrazing)) continue;
        if (glm::dot(h.hit.normal, glm::normalize(ray.dir)) > 0.0) ++backFacing;
      }
  }
  return backFacing;
}

TEST(RenderOnSkin, WatertightUnderRandomViewsAndTheSweepCanFail) {
  for (const char* file : {"structures/1crn.pdb", "paper/1grm.pdb.gz"}) {
    const build::Molecule m = molecule(file);
    for (double s : {0.3, 0.5}) {
      const build::PatchList list = build::buildMss(m.centers, m.radii, {s});
      EXPECT_EQ(backFacingFirstHits(list, 6, 17), 0) << file << " s = " << s;
    }
  }
  // Mutation: every other edge hyperboloid removed.
  const build::Molecule m = molecule("structures/1crn.pdb");
  build::PatchList holed = build::buildMss(m.centers, m.radii, {0.5});
  build::PatchList kept = holed;
  std::size_t out = 0, edge = 0;
  for (std::size_t k = 0; k < holed.mss.size(); ++k) {
    const bool drop = holed.mss.kind[k] == static_cast<std::uint32_t>(build::MssKind::Edge) && edge++ % 2 == 0;
    if (drop) continue;
    build::forEachArray([&](const char* group, const char*, auto& dst, const auto& src) {
      if (std::string(group) == "mss") dst[out] = src[k];
    }, kept, holed);
    ++out;
  }
  build::forEachArray([&](const char* group, const char*, auto& v) {
    if (std::string(group) == "mss") v.resize(out);
  }, kept);
  EXPECT_GT(backFacingFirstHits(kept, 6, 17), 20);
}

}  // namespace
}  // namespace surftrace::trace
