// SES contour-buildup: buildSes and SesBuilder (full build, partial update), which run the per-atom passes.
//
// Contour-buildup in two per-atom passes (Lindow et al. 2010, Sect. 4.1). The passes live in
// ses_vertices.cpp and ses_contours.cpp, the single-precision pre-tests in ses_kernels.cpp,
// the clipping planes in ses_planes.cpp, the components in ses_components.cpp and the
// block concatenation in ses_assembly.hpp.
//
// Vertex pass: every SAS vertex {i < j < k} is computed, tested and emitted once, by its
// owner i (the lowest atom), from circle (i, j). The probe positions are pure functions of
// the sorted triple (sas_geometry.hpp), so they agree bit for bit with what any atom of the
// triple would compute. The owner also finds the free circles (i, j): those no third sphere
// touches.
// Contour pass: each atom gathers the vertices and free circles that touch it, orders the
// vertices along each of its circles and joins them into exposed arcs. The arcs give the
// tori (from the lower atom of the circle) and the convex patch's area by Gauss–Bonnet.
// Because one decision per vertex serves all three atoms, the contours of neighbouring
// atoms cannot disagree.
//
// Most of the work is deciding which neighbour spheres cut, bury or miss a circle, and
// whether a vertex lies inside another sphere. That is done on the owner's unit sphere
// (circle (i, j) and sphere k are the boundary of cap a and the cap b) in single precision,
// four caps at a time, and only taken when clear by a margin far above rounding; the rest
// takes the tests of ORACLES A.2 in double precision with an error bound, and where a sign
// is within its bound, in exact arithmetic (sas_geometry.hpp, exact_predicates.hpp). So
// every decision (spheres cutting or containing, a circle inside a sphere, a probe
// position existing or lying inside a sphere) is that of the real numbers the inputs
// denote, and on real molecules the tori, concave patches and planes are bit for bit those
// of the first implementation, which tested every vertex against every common neighbour.
//
// Every output array is a concatenation of per-atom (per-probe for the planes) segments
// in atom order, which is what makes the list independent of the thread count and lets
// SesBuilder::update splice recomputed segments between kept ones. The contour pass also
// splits each atom's exposed region into its connected faces, from which the SES
// components are labelled.
#include "build/ses/contour_buildup.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "build/core/assert.hpp"
#include "build/moved_atoms.hpp"
#include "build/neighbour_grid.hpp"
#include "build/ses/sas_geometry.hpp"
#include "build/ses/ses_assembly.hpp"
#include "build/ses/ses_builder_state.hpp"
#include "build/ses/ses_contours.hpp"
#include "build/ses/ses_types.hpp"
#include "build/ses/ses_vertices.hpp"

namespace surftrace::build {

using namespace detail;

namespace {

// An atom whose extended sphere lies inside another's contributes nothing to the SAS or
// the SES. Identical atoms: the lowest index survives (ORACLES E.1, E.2).
bool isBuriedByContainment(std::uint32_t i, std::span<const std::uint32_t> row, std::span<const glm::dvec3> c,
                           std::span<const double> R) {
  for (const std::uint32_t j : row) {
    if (R[j] < R[i]) continue;  // d + R_i >= R_i > R_j: j cannot contain i
    // Clearly farther apart than R_j − R_i (the usual case): no square root needed.
    const glm::dvec3 v = c[j] - c[i];
    const double reach = (R[j] - R[i]) + 1e-9;
    if (glm::dot(v, v) > reach * reach * (1.0 + 1e-12)) continue;
    // Inside, touching allowed (decided exactly); of identical spheres the lowest survives.
    if (sphereInside(c[i], R[i], c[j], R[j]) && !(j > i && c[i] == c[j] && R[i] == R[j])) return true;
  }
  return false;
}

}  // namespace

// Whether atom i's extended sphere lies inside another's: only atoms closer than the
// difference of the radii can contain it, a small search (a superset, then the exact test).
bool SesBuilder::State::buriedByContainment(std::uint32_t i, std::vector<std::uint32_t>& near) const {
  near.clear();
  atoms.grid.atomsNear(atoms.centers[i], 1e-6 - atoms.radii[i], near);
  std::erase(near, i);
  return isBuriedByContainment(i, near, atoms.centers, atoms.extendedRadii);
}

// The grid lists atoms i, j as neighbours when d < r_i + r_j + 2 rp in double; every pair
// whose extended spheres cut exactly (spheresCut, on the rounded R = r + rp) must be among
// them. A reach longer by 2^-40 of rp + r_max covers the few roundings on either side (each
// at most 2^-53 relative) many times over, and adds no pair of any real molecule.
void SesBuilder::State::buildGrid() {
  double rMax = 0.0;
  for (const double r : atoms.radii) rMax = std::max(rMax, r);
  const double rp = params.probeRadius;
  atoms.grid.build(atoms.centers, atoms.radii, rp + 0x1p-40 * (rp + rMax));
}

// The vertex pass for `owners` (ascending) into pass.freshVertices (owner counts in its
// concaveCount and freeCount, one per owner).
void SesBuilder::State::vertexPassOf(std::span<const std::uint32_t> owners) {
  const Atoms a = atomView();
  runChunks(pass.threadScratch, owners.size(), pass.vertexPieces,
            [](Scratch& s) -> VertexBuf& { return s.vertexOut; },
            [&](std::size_t k, Scratch& s, VertexBuf& buf) {
              const std::uint32_t x = owners[k];
              if (atoms.buried[x]) {
                buf.concaveCount.push_back(0);
                buf.freeCount.push_back(0);
                vertices.capState[x] = CapState::Covered;
                return;
              }
              s.row.clear();
              atoms.grid.neighbours(x, s.row);
              vertexPass(a, x, s.row, s, buf, vertices.capState[x]);
            });
  gatherPieces(pass.vertexPieces, pass.gatherOffsets, [&](auto&& field) {
    forEachVertexArray(
        [&](auto member, auto&, std::size_t g) { field(Field{member, &(pass.freshVertices.*member), g}); });
    field(Field{&VertexBuf::concaveCount, &pass.freshVertices.concaveCount, 2});
    field(Field{&VertexBuf::freeCount, &pass.freshVertices.freeCount, 2});
  });
}

void SesBuilder::State::contourPassOf(std::span<const std::uint32_t> list_) {
  const Atoms a = atomView();
  const Incidence inc = contourPassInput();
  runChunks(pass.threadScratch, list_.size(), pass.contourPieces,
            [](Scratch& s) -> ContourBuf& { return s.contourOut; },
            [&](std::size_t k, Scratch& s, ContourBuf& buf) {
              const std::uint32_t x = list_[k];
              if (atoms.buried[x]) {
                buf.convexCount.push_back(0);
                buf.toriCount.push_back(0);
                faces.count[x] = 0;
                return;
              }
              contourPass(a, inc, x, s, buf);
            });
  gatherPieces(pass.contourPieces, pass.gatherOffsets, [&](auto&& field) {
    forEachContourArray(
        [&](auto member, auto&, std::size_t g) { field(Field{member, &(pass.freshContours.*member), g}); });
    field(Field{&ContourBuf::convexCount, &pass.freshContours.convexCount, 2});
    field(Field{&ContourBuf::toriCount, &pass.freshContours.toriCount, 2});
  });
}

void SesBuilder::State::fullBuild() {
  const std::size_t n = atoms.centers.size();
  const double rp = params.probeRadius;
  out.clearKeepingMemory();  // the arrays swapped out below then refill without allocating
  out.params.surface = SurfaceKind::Ses;
  out.params.probeRadius = rp;
  out.params.atomCount = static_cast<std::uint32_t>(n);
  atoms.extendedRadii.resize(n);
  for (std::size_t i = 0; i < n; ++i) atoms.extendedRadii[i] = atoms.radii[i] + rp;
  atoms.buried.assign(n, 0);
  vertices.capState.assign(n, CapState::None);

  buildGrid();
  // Burial by containment first: every pass after reads it for all neighbours.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kBlock), [&](const auto& range) {
    auto& near = pass.threadScratch.local().row;
    for (std::size_t i = range.begin(); i != range.end(); ++i)
      atoms.buried[i] = buriedByContainment(static_cast<std::uint32_t>(i), near);
  });

  pass.selection.resize(n);
  for (std::size_t i = 0; i < n; ++i) pass.selection[i] = static_cast<std::uint32_t>(i);

  // Vertex pass over every atom: the fresh arrays are the patch list's.
  vertexPassOf(pass.selection);
  forEachVertexArray([&](auto member, auto& kept, std::size_t) { kept.swap(pass.freshVertices.*member); });
  // The threads' buffers of a full pass, once gathered, would hold its output a second time
  // through the passes after it: the vertex buffers through the contour pass, where a large
  // molecule's build peaks (a sixth of that peak), the contour buffers through the planes. A
  // partial update reserves its own, smaller ones.
  for (Scratch& s : pass.threadScratch) s.vertexOut = VertexBuf{};
  prefix(pass.freshVertices.concaveCount, vertices.concaveBegin);
  prefix(pass.freshVertices.freeCount, vertices.freeCircleBegin);

  buildIncidence();
  faces.concaveFace.assign(incidence.concave.size(), 0);
  faces.freeCircleFace.assign(incidence.freeCircleOther.size(), 0);
  faces.count.assign(n, 0);
  findExtremeAtom();

  contourPassOf(pass.selection);
  forEachContourArray([&](auto member, auto& kept, std::size_t) { kept.swap(pass.freshContours.*member); });
  for (Scratch& s : pass.threadScratch) s.contourOut = ContourBuf{};
  prefix(pass.freshContours.convexCount, contours.convexBegin);
  prefix(pass.freshContours.toriCount, contours.toriBegin);

  // Clipping planes of every probe.
  auto& cv = out.concave;
  const std::size_t probes = cv.size();
  probeNeighbours.radii.assign(probes, rp);
  probeNeighbours.grid.build(cv.probe, probeNeighbours.radii, 0.0);
  pass.selection.resize(probes);
  for (std::size_t i = 0; i < probes; ++i) pass.selection[i] = static_cast<std::uint32_t>(i);
  planesOf(pass.selection);
  out.clipPlanes.swap(pass.freshPlanes);
  cv.clipCount.swap(pass.freshPlaneCount);
  cv.clipBegin.resize(probes);
  std::uint32_t at = 0;
  for (std::size_t k = 0; k < probes; ++k) {
    cv.clipBegin[k] = at;
    at += cv.clipCount[k];
  }

  labelComponents();
}

// Lindow et al. 2010, end of Sect. 4.1: only atoms within reach of a moved atom's old or
// new position can change. An owner's vertices depend on its neighbours and their burial;
// an atom's contour on the vertices and free circles that touch it; a probe's planes on
// the probes within 2 rp. Each is recomputed exactly as a full build would, and the fresh
// segments are spliced between the old ones, so the arrays equal a full build's.
void SesBuilder::State::partialUpdate(std::span<const std::uint32_t> moved, std::span<const glm::dvec3> newCenters) {
  const std::size_t n = atoms.centers.size();
  stats = SesUpdateStats{};
  stats.moved = moved.size();
  if (moved.empty()) return;
  // Past a fraction of the atoms the bookkeeping costs more than it saves.
  if (moved.size() * 8 > n) {
    for (std::size_t k = 0; k < moved.size(); ++k) atoms.centers[moved[k]] = newCenters[k];
    fullBuild();
    stats.owners = stats.contours = n;
    stats.probes = out.concave.size();
    stats.full = true;
    return;
  }
  markNearMove(moved, newCenters);
  selectOwners();
  updateVertices();
  updateContours();
  updatePlanes();
  labelComponents();
}

// Near: the moved atoms and their neighbours at the old positions (the grid still holds
// them) and, after the move, at the new ones. Moves the atoms and rebuilds the grid.
void SesBuilder::State::markNearMove(std::span<const std::uint32_t> moved, std::span<const glm::dvec3> newCenters) {
  update.marks.assign(atoms.centers.size(), 0);
  auto& rowBuf = pass.threadScratch.local().row;
  for (const std::uint32_t m : moved) {
    update.marks[m] |= kNearMove;
    rowBuf.clear();
    atoms.grid.neighbours(m, rowBuf);
    for (const std::uint32_t j : rowBuf) update.marks[j] |= kNearMove;
  }
  for (std::size_t k = 0; k < moved.size(); ++k) atoms.centers[moved[k]] = newCenters[k];
  buildGrid();
  for (const std::uint32_t m : moved) {
    rowBuf.clear();
    atoms.grid.neighbours(m, rowBuf);
    for (const std::uint32_t j : rowBuf) update.marks[j] |= kNearMove;
  }
}

// Burial can change only near the move; where it does, the neighbours' vertices change.
// Selects the owners whose vertex pass runs again.
void SesBuilder::State::selectOwners() {
  const std::size_t n = atoms.centers.size();
  auto& rowBuf = pass.threadScratch.local().row;
  for (std::size_t i = 0; i < n; ++i) {
    if (!(update.marks[i] & kNearMove)) continue;
    update.marks[i] |= kRedoVertices;
    const auto x = static_cast<std::uint32_t>(i);
    const char now = buriedByContainment(x, rowBuf) ? 1 : 0;
    if (now != atoms.buried[i]) {
      atoms.buried[i] = now;
      rowBuf.clear();
      atoms.grid.neighbours(x, rowBuf);
      for (const std::uint32_t j : rowBuf) update.marks[j] |= kRedoVertices;
    }
  }
  pass.selection.clear();
  for (std::size_t i = 0; i < n; ++i)
    if (update.marks[i] & kRedoVertices) pass.selection.push_back(static_cast<std::uint32_t>(i));
  stats.owners = pass.selection.size();
}

// Vertex pass of the owners selected; an owner whose output differs changes the contours
// of every atom its old and new vertices and free circles touch, and the planes near them.
// Splices the fresh segments in and rebuilds the incidence.
void SesBuilder::State::updateVertices() {
  vertexPassOf(pass.selection);
  prefix(pass.freshVertices.concaveCount, update.freshBegin[0]);
  prefix(pass.freshVertices.freeCount, update.freshBegin[1]);
  auto& cv = out.concave;
  const VertexBuf& fresh = pass.freshVertices;
  auto& marks = update.marks;
  const std::vector<std::uint32_t>* const oldBegin[2] = {&vertices.concaveBegin, &vertices.freeCircleBegin};
  update.changedOwners.clear();
  for (std::size_t t = 0; t < pass.selection.size(); ++t) {
    const std::uint32_t x = pass.selection[t];
    marks[x] |= kRedoContour;
    bool unchanged = true;
    forEachVertexArray([&](auto member, const auto& kept, std::size_t g) {
      using T = typename std::remove_cvref_t<decltype(kept)>::value_type;
      const std::size_t o0 = (*oldBegin[g])[x], o1 = (*oldBegin[g])[x + 1];
      const std::size_t f0 = update.freshBegin[g][t], f1 = update.freshBegin[g][t + 1];
      unchanged = unchanged && sameBits<T>(std::span<const T>(kept).subspan(o0, o1 - o0),
                                           std::span<const T>(fresh.*member).subspan(f0, f1 - f0));
    });
    if (unchanged) continue;
    const std::size_t o0 = vertices.concaveBegin[x], o1 = vertices.concaveBegin[x + 1];
    const std::size_t f0 = update.freshBegin[0][t], f1 = update.freshBegin[0][t + 1];
    const std::size_t g0 = vertices.freeCircleBegin[x], g1 = vertices.freeCircleBegin[x + 1];
    const std::size_t h0 = update.freshBegin[1][t], h1 = update.freshBegin[1][t + 1];
    update.changedOwners.push_back(x);
    // (The triangles of a merged vertex need not have their owner as atom I.)
    for (std::size_t v = o0; v < o1; ++v)
      marks[cv.atomI[v]] |= kRedoContour, marks[cv.atomJ[v]] |= kRedoContour, marks[cv.atomK[v]] |= kRedoContour;
    for (std::size_t v = f0; v < f1; ++v)
      marks[fresh.atomI[v]] |= kRedoContour, marks[fresh.atomJ[v]] |= kRedoContour,
          marks[fresh.atomK[v]] |= kRedoContour;
    for (std::size_t f = g0; f < g1; ++f) marks[vertices.freeCircleOther[f]] |= kRedoContour;
    for (std::size_t f = h0; f < h1; ++f) marks[fresh.freeOther[f]] |= kRedoContour;
  }

  // Old probes of changed owners, before the splice: their planes' partners need updates.
  auto& removed = update.removedProbes;
  removed.clear();
  for (const std::uint32_t x : update.changedOwners)
    removed.insert(removed.end(), cv.probe.begin() + vertices.concaveBegin[x],
                   cv.probe.begin() + vertices.concaveBegin[x + 1]);
  update.oldConcaveBegin = vertices.concaveBegin;
  update.oldClipBegin = cv.clipBegin;
  update.oldClipCount = cv.clipCount;

  spliceFresh(pass.freshVertices, [&](auto&& visit) { forEachVertexArray(visit); },
              {&vertices.concaveBegin, &vertices.freeCircleBegin});
  update.oldIncidenceConcaveBegin.swap(incidence.concaveBegin);
  update.oldConcaveFace.swap(faces.concaveFace);
  update.oldIncidenceFreeCircleBegin.swap(incidence.freeCircleBegin);
  update.oldFreeCircleFace.swap(faces.freeCircleFace);
  buildIncidence();
  // The extreme atom's contour gives the outer face: recompute it too.
  findExtremeAtom();
  if (!atoms.centers.empty()) marks[faces.extremeAtom] |= kRedoContour;
}

// Contours of the atoms touched. The others keep their faces; their incidence lists hold
// the same vertices in the same order, only moved.
void SesBuilder::State::updateContours() {
  const std::size_t n = atoms.centers.size();
  pass.selection.clear();
  for (std::size_t i = 0; i < n; ++i)
    if (update.marks[i] & kRedoContour) pass.selection.push_back(static_cast<std::uint32_t>(i));
  stats.contours = pass.selection.size();
  faces.concaveFace.resize(incidence.concave.size());
  faces.freeCircleFace.resize(incidence.freeCircleOther.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      if (update.marks[i] & kRedoContour) continue;
      const auto& ob = update.oldIncidenceConcaveBegin;
      const auto& fb = update.oldIncidenceFreeCircleBegin;
      SURFTRACE_ASSERT(ob[i + 1] - ob[i] == incidence.concaveBegin[i + 1] - incidence.concaveBegin[i]);
      SURFTRACE_ASSERT(fb[i + 1] - fb[i] == incidence.freeCircleBegin[i + 1] - incidence.freeCircleBegin[i]);
      std::copy(update.oldConcaveFace.begin() + ob[i], update.oldConcaveFace.begin() + ob[i + 1],
                faces.concaveFace.begin() + incidence.concaveBegin[i]);
      std::copy(update.oldFreeCircleFace.begin() + fb[i], update.oldFreeCircleFace.begin() + fb[i + 1],
                faces.freeCircleFace.begin() + incidence.freeCircleBegin[i]);
    }
  });
  contourPassOf(pass.selection);
  prefix(pass.freshContours.convexCount, update.freshBegin[0]);
  prefix(pass.freshContours.toriCount, update.freshBegin[1]);
  spliceFresh(pass.freshContours, [&](auto&& visit) { forEachContourArray(visit); },
              {&contours.convexBegin, &contours.toriBegin});
}

// Clipping planes: those of the changed owners' new probes, and of every probe within
// 2 rp of a removed or added probe; the others keep their lists (their neighbours kept
// their relative order).
void SesBuilder::State::updatePlanes() {
  const std::size_t n = atoms.centers.size();
  auto& cv = out.concave;
  const std::size_t probes = cv.size();
  probeNeighbours.radii.assign(probes, params.probeRadius);
  probeNeighbours.grid.build(cv.probe, probeNeighbours.radii, 0.0);
  auto& dirty = update.dirtyProbes;
  dirty.assign(probes, 0);
  for (const std::uint32_t x : update.changedOwners)
    for (std::uint32_t v = vertices.concaveBegin[x]; v < vertices.concaveBegin[x + 1]; ++v) dirty[v] = 1;
  auto& rowBuf = pass.threadScratch.local().row;
  auto markNear = [&](const glm::dvec3& p) {
    rowBuf.clear();
    probeNeighbours.grid.atomsNear(p, params.probeRadius, rowBuf);
    for (const std::uint32_t v : rowBuf) dirty[v] = 1;
  };
  for (const glm::dvec3& p : update.removedProbes) markNear(p);
  for (const std::uint32_t x : update.changedOwners)
    for (std::uint32_t v = vertices.concaveBegin[x]; v < vertices.concaveBegin[x + 1]; ++v) markNear(cv.probe[v]);
  pass.selection.clear();
  for (std::size_t v = 0; v < probes; ++v)
    if (dirty[v]) pass.selection.push_back(static_cast<std::uint32_t>(v));
  stats.probes = pass.selection.size();
  planesOf(pass.selection);
  // Old index of each new probe of an unchanged owner: same place within the owner.
  const auto& oldConcaveBegin = update.oldConcaveBegin;
  auto& oldProbeIndex = update.oldProbeIndex;
  oldProbeIndex.assign(probes, ~0u);
  for (std::size_t x = 0; x < n; ++x) {
    const std::uint32_t len = vertices.concaveBegin[x + 1] - vertices.concaveBegin[x];
    if (len == 0 || len != oldConcaveBegin[x + 1] - oldConcaveBegin[x]) continue;
    for (std::uint32_t k = 0; k < len; ++k) oldProbeIndex[vertices.concaveBegin[x] + k] = oldConcaveBegin[x] + k;
  }
  auto& clipCount = update.newClipCount;
  auto& clipBegin = update.newClipBegin;
  clipCount.resize(probes);
  clipBegin.resize(probes);
  std::size_t d = 0;
  std::uint32_t at = 0;
  for (std::size_t v = 0; v < probes; ++v) {
    clipBegin[v] = at;
    if (dirty[v]) {
      clipCount[v] = pass.freshPlaneCount[d++];
    } else {
      SURFTRACE_ASSERT(oldProbeIndex[v] != ~0u);
      clipCount[v] = update.oldClipCount[oldProbeIndex[v]];
    }
    at += clipCount[v];
  }
  auto& planes = update.newPlanes;
  planes.resize(at);
  const auto& oldClipBegin = update.oldClipBegin;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, probes, 256), [&](const auto& range) {
    // Dirty probes before this range, to find their fresh planes.
    const auto& sel = pass.selection;
    std::size_t dd = static_cast<std::size_t>(std::lower_bound(sel.begin(), sel.end(), range.begin()) - sel.begin());
    for (std::size_t v = range.begin(); v != range.end(); ++v) {
      const Plane* from = dirty[v] ? pass.freshPlanes.data() + pass.freshPlaneBegin[dd++]
                                   : out.clipPlanes.data() + oldClipBegin[oldProbeIndex[v]];
      std::copy(from, from + clipCount[v], planes.begin() + clipBegin[v]);
    }
  });
  out.clipPlanes.swap(planes);
  cv.clipBegin.swap(clipBegin);
  cv.clipCount.swap(clipCount);
}

double maxProbeRadius(std::span<const double> radii) {
  double rMin = std::numeric_limits<double>::infinity();
  for (const double r : radii) rMin = std::min(rMin, r);
  return kMaxProbeToRadius * rMin;
}

void checkProbeRadius(double probeRadius, std::span<const double> radii) {
  if (radii.empty() || probeRadius <= maxProbeRadius(radii)) return;
  char text[512];
  std::snprintf(text, sizeof text,
                "probe radius %.6g Å is above the limit of %.6g Å (2^19 times the smallest atom radius, "
                "%.4g Å): past it the patch areas, differences of terms of order rp², lose more than 1e-5 "
                "of their value to double-precision rounding. At the limit the SES is already within "
                "2e-5 of the convex hull of the atoms, which larger probes tend to",
                probeRadius, maxProbeRadius(radii), maxProbeRadius(radii) / kMaxProbeToRadius);
  throw std::invalid_argument(text);
}

SesBuilder::SesBuilder() : s_(std::make_unique<State>()) {}
SesBuilder::~SesBuilder() = default;
SesBuilder::SesBuilder(SesBuilder&&) noexcept = default;
SesBuilder& SesBuilder::operator=(SesBuilder&&) noexcept = default;

const PatchList& SesBuilder::build(std::span<const glm::dvec3> centers, std::span<const double> radii,
                                   const SesParams& params) {
  const double rp = params.probeRadius;
  if (!std::isfinite(rp) || !(rp > 0.0))
    throw std::invalid_argument("probe radius must be finite and > 0, got " + std::to_string(rp));
  if (centers.size() != radii.size()) throw std::invalid_argument("centers and radii differ in length");
  checkProbeRadius(rp, radii);
  if (centers.size() >= std::numeric_limits<std::uint32_t>::max())
    throw std::invalid_argument("too many atoms: " + std::to_string(centers.size()));
  s_->params = params;
  s_->atoms.centers.assign(centers.begin(), centers.end());
  s_->atoms.radii.assign(radii.begin(), radii.end());
  s_->fullBuild();
  s_->built = true;
  s_->stats = SesUpdateStats{};
  s_->stats.moved = s_->stats.owners = s_->stats.contours = centers.size();
  s_->stats.probes = s_->out.concave.size();
  s_->stats.full = true;
  return s_->out;
}

const PatchList& SesBuilder::update(std::span<const std::uint32_t> moved, std::span<const glm::dvec3> newCenters) {
  if (!s_->built) throw std::logic_error("SesBuilder::update before build");
  if (moved.size() != newCenters.size()) throw std::invalid_argument("moved and newCenters differ in length");
  const std::size_t n = s_->atoms.centers.size();
  for (std::size_t k = 0; k < moved.size(); ++k) {
    if (moved[k] >= n) throw std::invalid_argument("moved atom " + std::to_string(moved[k]) + " out of range");
    const glm::dvec3& c = newCenters[k];
    if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z))
      throw std::invalid_argument("non-finite centre for atom " + std::to_string(moved[k]));
  }
  // The atoms that really move (a repeated index takes its last position), ascending.
  std::vector<std::uint32_t> order(moved.size());
  for (std::size_t k = 0; k < moved.size(); ++k) order[k] = static_cast<std::uint32_t>(k);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t u, std::uint32_t v) { return moved[u] < moved[v]; });
  std::vector<std::uint32_t> atoms;
  std::vector<glm::dvec3> where;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const std::uint32_t i = moved[order[k]];
    if (k + 1 < order.size() && moved[order[k + 1]] == i) continue;  // a later entry wins
    const glm::dvec3& c = newCenters[order[k]];
    if (std::memcmp(&c, &s_->atoms.centers[i], sizeof(glm::dvec3)) == 0) continue;
    atoms.push_back(i);
    where.push_back(c);
  }
  s_->partialUpdate(atoms, where);
  return s_->out;
}

const PatchList& SesBuilder::update(std::span<const glm::dvec3> centers) {
  if (!s_->built) throw std::logic_error("SesBuilder::update before build");
  if (centers.size() != s_->atoms.centers.size()) throw std::invalid_argument("frame has a different atom count");
  std::vector<std::uint32_t> moved;
  std::vector<glm::dvec3> where;
  movedAtoms(s_->atoms.centers, centers, moved, where);
  return update(moved, where);
}

const PatchList& SesBuilder::patches() const { return s_->out; }
const SesUpdateStats& SesBuilder::lastUpdate() const { return s_->stats; }
PatchList SesBuilder::takePatches() {
  s_->built = false;
  return std::move(s_->out);
}

PatchList buildSes(std::span<const glm::dvec3> centers, std::span<const double> radii, const SesParams& params) {
  SesBuilder builder;
  builder.build(centers, radii, params);
  return builder.takePatches();
}

}  // namespace surftrace::build
