// SES builder state: what SesBuilder keeps between build() and update() (private to src/build).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <type_traits>
#include <vector>

#include <glm/vec3.hpp>
#include <tbb/enumerable_thread_specific.h>

#include "build/ses/contour_buildup.hpp"
#include "build/neighbour_grid.hpp"
#include "build/patch_list.hpp"
#include "build/ses/ses_assembly.hpp"
#include "build/ses/ses_contours.hpp"
#include "build/ses/ses_types.hpp"

namespace surftrace::build {

// The passes over atoms and probes are in contour_buildup.cpp (vertexPassOf, contourPassOf,
// fullBuild, partialUpdate and its steps), ses_planes.cpp (planesOf) and ses_components.cpp
// (buildIncidence, findExtremeAtom, labelComponents). The state is grouped by the pass that
// writes it, in the order they run: atoms, vertices, incidence, contours and faces,
// probeNeighbours (the planes themselves and all patches are in out); then the working
// memory of the passes (pass), of a partial update (update) and of the component
// labelling (componentScratch).
struct SesBuilder::State {
  SesParams params;  // build()'s, fixed until the next build()

  // The molecule as every pass sees it (through atomView()). Written by build() (centres,
  // radii), fullBuild (extended radii, burial, grid) and partialUpdate's markNearMove
  // (centres of moved atoms, grid) and selectOwners (burial near the move). Read by every
  // pass.
  struct AtomData {
    std::vector<glm::dvec3> centers;
    std::vector<double> radii;          // van der Waals radii
    std::vector<double> extendedRadii;  // radii + probe radius: the SAS spheres (R in the passes)
    std::vector<char> buried;           // extended sphere inside another's: no part in the surface
    NeighbourGrid grid;  // atom pairs: a superset of those whose extended spheres cut (buildGrid)
  } atoms;

  // Vertex pass (vertexPassOf; fullBuild swaps its output in, updateVertices splices it):
  // each owner's concave patches (its SAS vertices, owner = lowest atom of the triple) go to
  // out.concave in owner segments; these arrays lie beside them, and beside the owners.
  // Read by buildIncidence, the contour pass (through contourPassInput()), planesOf (the
  // probes, in out.concave) and labelComponents.
  struct VertexPassArrays {
    std::vector<std::uint32_t> concaveBegin;       // per owner, n + 1: its segment of out.concave
    std::vector<std::uint8_t> probeIsPlus;         // per concave patch: the probe is p+ of its triple
    std::vector<std::uint8_t> boundaryEdges;       // per concave patch: IJ 1, JK 2, KI 4 (7 unless merged)
    std::vector<std::uint32_t> backToMergedFirst;  // per concave patch: distance back to its merged vertex's first
    std::vector<std::uint32_t> freeCircleBegin;    // per owner, n + 1: its segment of freeCircleOther
    std::vector<std::uint32_t> freeCircleOther;    // per free circle (owner, other): other > owner
    std::vector<detail::CapState> capState;        // per atom: how the neighbours' caps cover its sphere
  } vertices;

  // Who touches what (buildIncidence, after each vertex pass): per atom, the concave patches
  // it is an atom of and the other atoms of its free circles, each list in patch order.
  // Read by the contour pass (through contourPassInput()) and labelComponents.
  struct AtomIncidence {
    std::vector<std::uint32_t> concaveBegin;     // per atom, n + 1: its segment of `concave`
    std::vector<std::uint32_t> concave;          // indices into out.concave
    std::vector<std::uint32_t> freeCircleBegin;  // per atom, n + 1: its segment of `freeCircleOther`
    std::vector<std::uint32_t> freeCircleOther;  // the other atom of each of its free circles
  } incidence;

  // Contour pass (contourPassOf; fullBuild swaps its output in, updateContours splices it):
  // each atom's convex patch and the tori of its circles (the atom the lower one) go to
  // out.convex and out.tori in atom segments; these arrays lie beside them. Read by
  // labelComponents (torusFace) and partialUpdate (the segments).
  struct ContourPassArrays {
    std::vector<std::uint32_t> convexBegin;  // per atom, n + 1: its segment of out.convex (0 or 1 patch)
    std::vector<std::uint32_t> toriBegin;    // per atom, n + 1: its segment of out.tori
    std::vector<std::uint32_t> torusFace;    // per torus: the face of its atom I that it bounds
  } contours;

  // Faces: the connected pieces of each atom's exposed region. The contour pass writes each
  // atom's own entries in place (through contourPassInput()); findExtremeAtom picks the
  // extreme atom before it. Read by labelComponents, which joins faces into components.
  struct AtomFaces {
    std::vector<std::uint32_t> count;           // per atom: its faces
    std::vector<std::uint32_t> concaveFace;     // per entry of incidence.concave: the face it bounds (~0u: none)
    std::vector<std::uint32_t> freeCircleFace;  // per entry of incidence.freeCircleOther: the face it bounds
    std::uint32_t extremeAtom = 0;  // the atom whose extended sphere reaches furthest in +x
    std::uint32_t extremeFace = 0;  // its face facing +x: on the outer surface
  } faces;

  // The probes' own neighbour grid, rebuilt over out.concave.probe whenever the probes
  // change (fullBuild, updatePlanes); its neighbour relation is exactly |p − q| < 2 rp.
  // Read by planesOf (the clipping planes), updatePlanes (the probes near a changed one)
  // and labelComponents (probes whose spheres cut each other's patch).
  struct ProbeNeighbours {
    std::vector<double> radii;  // rp for every probe: the grid's input
    NeighbourGrid grid;
  } probeNeighbours;

  PatchList out;          // the patch list that build() and update() return
  SesUpdateStats stats;   // what the last build() or update() recomputed
  bool built = false;     // update() needs a build() first (takePatches() empties out)

  // The passes' working memory, reused so that a trajectory does not allocate per frame.
  // vertexPassOf, contourPassOf and planesOf each run over `selection` in parallel chunks
  // (runChunks), each chunk appending to its thread's buffer in threadScratch and noting
  // where in a piece; gatherPieces concatenates the pieces, in order, into the fresh arrays.
  // fullBuild swaps those into place; partialUpdate's steps compare and splice them.
  struct PassBuffers {
    tbb::enumerable_thread_specific<detail::Scratch> threadScratch;
    std::vector<std::uint32_t> selection;  // the atoms (or probes) the next pass runs over, ascending
    std::vector<detail::Piece<detail::VertexBuf>> vertexPieces;
    std::vector<detail::Piece<detail::ContourBuf>> contourPieces;
    std::vector<detail::Piece<detail::PlaneBuf>> planePieces;
    std::array<std::vector<std::size_t>, 3> gatherOffsets;  // per field group: where each piece goes
    detail::VertexBuf freshVertices;   // the vertex pass's output for the atoms selected
    detail::ContourBuf freshContours;  // the contour pass's output for the atoms selected
    // planesOf's output for the probes selected: per probe its count and start, the planes.
    std::vector<std::uint32_t> freshPlaneCount, freshPlaneBegin;
    std::vector<Plane> freshPlanes;
  } pass;

  // partialUpdate's bookkeeping between its steps (markNearMove, selectOwners,
  // updateVertices, updateContours, updatePlanes, in that order) and the buffers its
  // splices go through; nothing in it is read after the update.
  static constexpr std::uint8_t kNearMove = 1, kRedoVertices = 2, kRedoContour = 4;  // marks
  struct PartialUpdate {
    std::vector<std::uint8_t> marks;           // per atom: kNearMove | kRedoVertices | kRedoContour
    std::vector<std::uint32_t> changedOwners;  // owners whose vertex-pass output changed (updateVertices)
    std::vector<glm::dvec3> removedProbes;     // the old probes of the changed owners (for updatePlanes)
    // Segment starts of the two segment groups spliced (concave patches and free circles;
    // convex patches and tori): of the fresh output, and of the spliced arrays.
    std::array<std::vector<std::uint32_t>, 2> freshBegin, splicedBegin;
    // The arrays as they were before updateVertices' splice: the vertex segments and the
    // clipping planes (for updatePlanes), the incidence segments and their faces (for
    // updateContours, which keeps the faces of the atoms it does not recompute).
    std::vector<std::uint32_t> oldConcaveBegin, oldClipBegin, oldClipCount;
    std::vector<std::uint32_t> oldIncidenceConcaveBegin, oldConcaveFace, oldIncidenceFreeCircleBegin, oldFreeCircleFace;
    // The clipping planes rebuilt (updatePlanes): which probes get fresh ones, the old index
    // of the others (~0u for the new probes), the new counts, starts and planes.
    std::vector<std::uint8_t> dirtyProbes;
    std::vector<std::uint32_t> oldProbeIndex, newClipCount, newClipBegin;
    std::vector<Plane> newPlanes;
    // The buffers a splice of an array of T goes through (spliceBuffer).
    std::vector<glm::dvec3> spliceVec3;
    std::vector<double> spliceDouble;
    std::vector<std::uint32_t> spliceU32;
    std::vector<std::uint8_t> spliceU8;

    template <class T> std::vector<T>& spliceBuffer() {
      if constexpr (std::is_same_v<T, glm::dvec3>) return spliceVec3;
      else if constexpr (std::is_same_v<T, double>) return spliceDouble;
      else if constexpr (std::is_same_v<T, std::uint32_t>) return spliceU32;
      else {
        static_assert(std::is_same_v<T, std::uint8_t>);
        return spliceU8;
      }
    }
  } update;

  // labelComponents' working memory: a union-find over the faces of all atoms, numbered
  // atom after atom. Its result is every patch's component, in out.
  struct ComponentScratch {
    std::vector<std::uint32_t> faceBegin;         // per atom, n + 1: the number of its first face
    std::vector<std::uint32_t> faceParent;        // per face: its parent in the union-find
    std::vector<std::uint32_t> faceLabel;         // per root face: its component (~0u: none yet)
    std::vector<std::uint32_t> concavePatchFace;  // per concave patch: a face it bounds (~0u: none)
  } componentScratch;

  detail::Atoms atomView() const {
    return {atoms.centers, atoms.radii, atoms.extendedRadii, atoms.buried, params.probeRadius};
  }
  // What the contour pass reads, and the face arrays it writes in place.
  detail::Incidence contourPassInput() {
    const auto& cv = out.concave;
    return {cv.probe,
            cv.atomI,
            cv.atomJ,
            cv.atomK,
            vertices.probeIsPlus,
            vertices.boundaryEdges,
            vertices.backToMergedFirst,
            incidence.concaveBegin,
            incidence.concave,
            incidence.freeCircleBegin,
            incidence.freeCircleOther,
            vertices.capState,
            faces.concaveFace,
            faces.freeCircleFace,
            faces.count,
            faces.extremeAtom,
            &faces.extremeFace};
  }
  void findExtremeAtom();
  // Whether atom i's extended sphere lies inside another's: only atoms closer than the
  // difference of the radii can contain it, a small search (a superset, then the exact test).
  bool buriedByContainment(std::uint32_t i, std::vector<std::uint32_t>& near) const;
  void buildGrid();

  // Every array the vertex pass produces: visit(member of VertexBuf, the array that keeps it
  // (in `out` or beside it), its segment group: 0 per concave patch, 1 per free circle).
  // Every array the contour pass produces likewise (ContourBuf; 0 convex patches, 1 tori).
  // These lists alone serve the gather of the pieces, the swap of a full build, and the
  // comparison and splice of a partial update.
  template <class Visit> void forEachVertexArray(Visit&& visit) {
    using B = detail::VertexBuf;
    auto& cv = out.concave;
    visit(&B::probe, cv.probe, 0);
    visit(&B::dirI, cv.dirI, 0);
    visit(&B::dirJ, cv.dirJ, 0);
    visit(&B::dirK, cv.dirK, 0);
    visit(&B::atomI, cv.atomI, 0);
    visit(&B::atomJ, cv.atomJ, 0);
    visit(&B::atomK, cv.atomK, 0);
    visit(&B::plus, vertices.probeIsPlus, 0);
    visit(&B::edges, vertices.boundaryEdges, 0);
    visit(&B::group, vertices.backToMergedFirst, 0);
    visit(&B::freeOther, vertices.freeCircleOther, 1);
  }
  template <class Visit> void forEachContourArray(Visit&& visit) {
    using B = detail::ContourBuf;
    auto& cx = out.convex;
    auto& tr = out.tori;
    visit(&B::convexCenter, cx.center, 0);
    visit(&B::convexRadius, cx.radius, 0);
    visit(&B::convexAtom, cx.atom, 0);
    visit(&B::convexArea, cx.area, 0);
    visit(&B::convexVectorArea, cx.vectorArea, 0);
    visit(&B::torusCenter, tr.center, 1);
    visit(&B::torusAxis, tr.axis, 1);
    visit(&B::torusE1, tr.e1, 1);
    visit(&B::bigRadius, tr.bigRadius, 1);
    visit(&B::thetaI, tr.thetaI, 1);
    visit(&B::thetaJ, tr.thetaJ, 1);
    visit(&B::phiExtent, tr.phiExtent, 1);
    visit(&B::torusI, tr.atomI, 1);
    visit(&B::torusJ, tr.atomJ, 1);
    visit(&B::torusFace, contours.torusFace, 1);
  }
  // Replaces, in every array of forEachArray, the segments of the atoms in pass.selection by
  // those of `fresh` (whose segment starts are update.freshBegin); begin holds the old starts
  // of the two groups and gets the new ones.
  template <class Fresh, class ForEachArray>
  void spliceFresh(const Fresh& fresh, ForEachArray&& forEachArray, std::array<std::vector<std::uint32_t>*, 2> begin) {
    const auto& changed = pass.selection;
    const auto& freshBegin = update.freshBegin;
    auto& splicedBegin = update.splicedBegin;
    for (std::size_t g = 0; g < 2; ++g) detail::newStarts(*begin[g], changed, freshBegin[g], splicedBegin[g]);
    const detail::Splice splice[2] = {{*begin[0], splicedBegin[0], changed, freshBegin[0]},
                                      {*begin[1], splicedBegin[1], changed, freshBegin[1]}};
    forEachArray([&](auto member, auto& kept, std::size_t g) {
      using T = typename std::remove_cvref_t<decltype(kept)>::value_type;
      splice[g](kept, fresh.*member, update.spliceBuffer<T>());
    });
    for (std::size_t g = 0; g < 2; ++g) begin[g]->swap(splicedBegin[g]);
  }

  void fullBuild();
  void partialUpdate(std::span<const std::uint32_t> moved, std::span<const glm::dvec3> newCenters);
  // partialUpdate's steps, in order.
  void markNearMove(std::span<const std::uint32_t> moved, std::span<const glm::dvec3> newCenters);
  void selectOwners();
  void updateVertices();
  void updateContours();
  void updatePlanes();
  void vertexPassOf(std::span<const std::uint32_t> owners);
  void contourPassOf(std::span<const std::uint32_t> atomList);
  void planesOf(std::span<const std::uint32_t> probes);
  void buildIncidence();
  void labelComponents();
};

}  // namespace surftrace::build
