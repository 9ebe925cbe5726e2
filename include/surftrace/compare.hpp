// Comparing a rendering with a reference of the same view: `surftrace compare` as one call. The
// test is SurfTrace's buffers, or another renderer's depth (and normal) buffers, from files or
// held in memory (memoryChannels: e.g. glReadPixels' result), read in their declared conventions;
// the result holds the figures, the verdict with its hints, the JSON report, and makes the
// difference image and the HTML page. Declared in view/comparison.hpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "build/io/mesh_reader.hpp"
#include "build/mesh/triangle_mesh.hpp"
#include "surftrace/molecule.hpp"
#include "surftrace/surface.hpp"
#include "view/comparison.hpp"

namespace surftrace {

// What is compared.
using view::CompareReference;
using view::CompareTest;
using view::ForeignBuffers;
using view::FrameBuffers;
using view::ImageChannels;
using view::ImageMetadata;
// How another renderer's buffers are read.
using view::DepthConvention;
using view::ForeignBufferOptions;
using view::NormalEncoding;
using view::NormalSpace;
using view::RowOrigin;
using view::depthConventionNamed;
using view::normalEncodingNamed;
using view::normalSpaceNamed;
using view::rowOriginNamed;
// Reading them from files or memory.
using view::compareReference;
using view::hasFrameBufferChannels;  // whether a file is SurfTrace's EXR or another renderer's buffers
using view::memoryChannels;
using view::readImageChannels;       // another renderer's buffer from any file OpenImageIO reads
using view::readCompareReference;
using view::readCompareTest;
using view::readForeignTest;
using view::readSurfTraceTest;
// The comparison and what it returns.
using view::compare;
using view::CompareResult;
using view::CompareSettings;
using view::CompareThresholds;
using view::FrameComparison;
using view::kComparePresets;
using view::KindErrors;
using view::TestChannels;
using view::WorstPixel;
// What it draws.
using view::comparisonPage;
using view::differenceImage;
using view::differenceLegend;
using view::EncodedImage;
using view::encodeDifference;
using view::writeDifference;

// Meshes from other programs (OBJ, PLY, STL, OFF, glTF/GLB) as the test: read, moved into the
// structure's frame, drawn exactly (Embree triangles, distances in double) through the
// reference's own pixel-centre rays, and judged as another renderer's buffers are.
using build::isMeshPath;          // by the file's extension
using build::readMesh;            // InputError naming the file when it cannot be read
using build::parseMeshTransform;  // --mesh-transform: a file of 16 numbers or "m00,m01,...", row-major
using build::transformMesh;
using build::mesh::TriangleMesh;
// `mesh` (read from `name`) drawn along `reference`'s camera rays. std::invalid_argument when
// the reference records no camera.
CompareTest meshTest(const std::string& name, const TriangleMesh& mesh, const CompareReference& reference);
// The mesh in `path`, moved by `transform` when given, drawn as meshTest draws it.
CompareTest readMeshTest(const std::string& path, const CompareReference& reference,
                         const std::optional<glm::dmat4>& transform = std::nullopt);

// A mesh against the exact surface all around (`compare MESH STRUCTURE --views N`): the exact
// surface rendered by Embree from `views` directions spread evenly over the sphere (a Fibonacci
// lattice), orthographic and framed tightly, and the mesh drawn through each view's rays.
struct MeshViewsSettings {
  int views = 26;
  int width = 512, height = 512;
  // Called after each view with (views done, views): for a progress bar.
  std::function<void(std::size_t, std::size_t)> progress;
};

// One of the worst places: where a distance estimate is largest.
struct MeshPlace {
  glm::dvec3 point{0.0};    // on the exact surface (the mesh's hit where only the mesh is hit)
  std::uint32_t atom = ~0u;  // the reference's atom there (or the nearest hit's), 0-based
  double distance = 0.0;    // the estimate, Å
  std::string what;         // "mesh -> exact", "exact -> mesh"; "(silhouette)" when only one is hit
  int view = 0;             // from 0
  int x = 0, y = 0;         // the pixel in that view
};

// The distance estimates of one direction, over every view's pixels.
struct DistanceFigures {
  std::size_t samples = 0;
  double median = 0.0, p99 = 0.0, max = 0.0;
};

struct MeshViewsResult {
  int views = 0, width = 0, height = 0;
  std::vector<glm::dvec3> directions;  // the view directions (unit, towards the molecule)
  std::size_t pixels = 0, referenceHits = 0, silhouette = 0;  // over all views
  std::size_t coverageMismatch = 0, meshOnly = 0, exactOnly = 0;  // outside the silhouette bands
  std::size_t depthSamples = 0;
  // Where both are hit (off the silhouette bands and occlusion edges):
  DistanceFigures alongRay;     // |d| = |t_mesh − t_exact|: an upper bound of either point's distance
                                // to the other surface, loose where the ray is oblique
  // How far mesh points lie from the exact surface, and the reverse, from rays within 45° of
  // the normal where both are hit: mesh -> exact is the distance from the mesh's hit to the
  // exact surface's nearest point (exact within the surface field's reach, build/mesh/
  // surface_distance.hpp; never above |d|), exact -> mesh the distance from the exact hit to the
  // mesh's nearest triangle (exact). Where only one is hit: the distance across the image to
  // the other's outline less half a pixel diagonal (a lower bound: orthographic projection never
  // lengthens a distance).
  DistanceFigures meshToExact;
  DistanceFigures exactToMesh;
  std::vector<KindErrors> perKind;   // signed t_mesh − t_exact per reference patch kind (< 0: mesh in front)
  std::vector<MeshPlace> worst;      // largest estimates first
  double seconds = 0.0;

  // The lines `compare` prints.
  std::string summary() const;
  std::string json() const;
  // The figure --max-error judges: the larger of the two directions' p99 (or max).
  double error(bool useMax) const;
};

// `patches` is the exact surface of `molecule` (buildSurface). std::invalid_argument for fewer
// than 1 view or an empty image.
MeshViewsResult compareMeshViews(const TriangleMesh& mesh, const PatchList& patches, const Molecule& molecule,
                                 const MeshViewsSettings& settings = {});

}  // namespace surftrace
