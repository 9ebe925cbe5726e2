// SES components: who touches which vertex and free circle, and the labelling of connected surfaces.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include <glm/geometric.hpp>

#include "build/ses/clip_planes.hpp"
#include "build/ses/ses_assembly.hpp"
#include "build/ses/ses_builder_state.hpp"

namespace surftrace::build {

using namespace detail;

// Per atom, the concave patches and free circles it belongs to (a counting sort, so each
// list is in patch order).
void SesBuilder::State::buildIncidence() {
  const std::size_t n = atoms.centers.size();
  const auto& cv = out.concave;
  const std::size_t v = cv.size();
  incidence.concaveBegin.assign(n + 2, 0);
  for (std::size_t k = 0; k < v; ++k) {
    ++incidence.concaveBegin[cv.atomI[k] + 2];
    ++incidence.concaveBegin[cv.atomJ[k] + 2];
    ++incidence.concaveBegin[cv.atomK[k] + 2];
  }
  for (std::size_t i = 0; i < n; ++i) incidence.concaveBegin[i + 2] += incidence.concaveBegin[i + 1];
  incidence.concave.resize(incidence.concaveBegin[n + 1]);
  // incidence.concaveBegin[i + 1] is atom i's cursor; afterwards it is atom i's end = i + 1's start.
  for (std::size_t k = 0; k < v; ++k) {
    const auto id = static_cast<std::uint32_t>(k);
    incidence.concave[incidence.concaveBegin[cv.atomI[k] + 1]++] = id;
    incidence.concave[incidence.concaveBegin[cv.atomJ[k] + 1]++] = id;
    incidence.concave[incidence.concaveBegin[cv.atomK[k] + 1]++] = id;
  }
  incidence.concaveBegin.pop_back();
  incidence.freeCircleBegin.assign(n + 2, 0);
  for (std::size_t x = 0; x < n; ++x) {
    for (std::uint32_t f = vertices.freeCircleBegin[x]; f < vertices.freeCircleBegin[x + 1]; ++f) {
      ++incidence.freeCircleBegin[x + 2];
      ++incidence.freeCircleBegin[vertices.freeCircleOther[f] + 2];
    }
  }
  for (std::size_t i = 0; i < n; ++i) incidence.freeCircleBegin[i + 2] += incidence.freeCircleBegin[i + 1];
  incidence.freeCircleOther.resize(incidence.freeCircleBegin[n + 1]);
  for (std::size_t x = 0; x < n; ++x) {
    for (std::uint32_t f = vertices.freeCircleBegin[x]; f < vertices.freeCircleBegin[x + 1]; ++f) {
      const std::uint32_t o = vertices.freeCircleOther[f];
      incidence.freeCircleOther[incidence.freeCircleBegin[x + 1]++] = o;
      incidence.freeCircleOther[incidence.freeCircleBegin[o + 1]++] = static_cast<std::uint32_t>(x);
    }
  }
  incidence.freeCircleBegin.pop_back();
}

// The atom whose extended sphere reaches furthest in +x: the SAS point there is exposed,
// so the SES patch of that atom facing +x is on the outer surface.
void SesBuilder::State::findExtremeAtom() {
  double best = -std::numeric_limits<double>::infinity();
  faces.extremeAtom = 0;
  for (std::size_t i = 0; i < atoms.centers.size(); ++i) {
    if (atoms.buried[i]) continue;
    const double reach = atoms.centers[i].x + atoms.extendedRadii[i];
    if (reach > best) best = reach, faces.extremeAtom = static_cast<std::uint32_t>(i);
  }
  faces.extremeFace = 0;
}

// SES components: the faces of all atoms (nodes), joined where they share a vertex (its
// three atoms' faces) or a free circle (its two atoms' faces); tori and concave patches
// take their faces' component. The outer component, 0, is the extreme atom's face facing
// +x; the others are numbered in order of their first patch (convex, tori, concave). Two
// probes whose spheres cut each other's patch join their faces' components too (below).
// An atom exposed to two components (a one-atom wall around a cavity) has one convex
// patch; it takes the lower number, and computeAreas gives each other component the part
// its tori bound.
void SesBuilder::State::labelComponents() {
  const std::size_t n = atoms.centers.size();
  auto& cv = out.concave;
  std::vector<std::uint32_t>& faceBegin = componentScratch.faceBegin;
  prefix(std::span<const std::uint32_t>(faces.count.data(), n), faceBegin);
  const std::size_t faceTotal = n == 0 ? 0 : faceBegin[n];
  std::vector<std::uint32_t>& parent = componentScratch.faceParent;
  parent.resize(faceTotal);
  for (std::size_t f = 0; f < faceTotal; ++f) parent[f] = static_cast<std::uint32_t>(f);
  auto find = [&](std::uint32_t f) {
    while (parent[f] != f) f = parent[f] = parent[parent[f]];
    return f;
  };
  auto unite = [&](std::uint32_t f, std::uint32_t g) {
    f = find(f);
    g = find(g);
    if (f != g) parent[std::max(f, g)] = std::min(f, g);
  };
  std::vector<std::uint32_t>& vertexFace = componentScratch.concavePatchFace;
  vertexFace.assign(cv.size(), ~0u);
  for (std::size_t x = 0; x < n; ++x) {
    if (faces.count[x] == 0) continue;
    for (std::uint32_t k = incidence.concaveBegin[x]; k < incidence.concaveBegin[x + 1]; ++k) {
      if (faces.concaveFace[k] == ~0u) continue;  // a merged vertex with no arc of x
      const std::uint32_t f = faceBegin[x] + faces.concaveFace[k];
      std::uint32_t& v = vertexFace[incidence.concave[k]];
      if (v == ~0u) v = f;
      else unite(v, f);
    }
    for (std::uint32_t k = incidence.freeCircleBegin[x]; k < incidence.freeCircleBegin[x + 1]; ++k) {
      const std::uint32_t o = incidence.freeCircleOther[k];
      if (o < x || faces.count[o] == 0) continue;
      for (std::uint32_t m = incidence.freeCircleBegin[o]; m < incidence.freeCircleBegin[o + 1]; ++m)
        if (incidence.freeCircleOther[m] == x)
          unite(faceBegin[x] + faces.freeCircleFace[k], faceBegin[o] + faces.freeCircleFace[m]);
    }
  }
  // The triangles of a merged vertex are one patch.
  for (std::size_t v = 0; v < cv.size(); ++v) {
    if (vertices.backToMergedFirst[v] == 0) continue;
    std::uint32_t& first = vertexFace[v - vertices.backToMergedFirst[v]];
    if (vertexFace[v] == ~0u) continue;
    if (first == ~0u) first = vertexFace[v];
    else unite(first, vertexFace[v]);
  }
  for (std::size_t v = 0; v < cv.size(); ++v)
    if (vertices.backToMergedFirst[v] != 0) vertexFace[v] = vertexFace[v - vertices.backToMergedFirst[v]];
  // Self-intersections (ORACLES A.5): where probe w's sphere cuts v's triangle (the
  // condition under which planesOf gives v w's plane), the surface crosses from v's patch
  // to w's along their intersection circle, so they are one surface even where no vertex
  // joins their atoms' faces (a cavity sealed by clipped concave patches and the halves of
  // spindle tori). Joining when the cap merely may meet the triangle can only merge
  // components, never leave one open.
  const double twoRp = 2.0 * params.probeRadius;
  auto& row = pass.threadScratch.local().row;
  for (std::size_t v = 0; v < cv.size(); ++v) {
    if (vertexFace[v] == ~0u) continue;
    row.clear();
    probeNeighbours.grid.neighbours(static_cast<std::uint32_t>(v), row);
    const TriangleCone cone({cv.dirI[v], cv.dirJ[v], cv.dirK[v]});
    for (const std::uint32_t w : row) {
      if (vertexFace[w] == ~0u) continue;
      const glm::dvec3 d = cv.probe[w] - cv.probe[v];
      if (!(glm::dot(d, d) > 0.0)) continue;
      const double len = glm::length(d);
      if (cone.capMeets(d / len, len / twoRp)) unite(vertexFace[v], vertexFace[w]);
    }
  }
  std::vector<std::uint32_t>& label = componentScratch.faceLabel;
  label.assign(faceTotal, ~0u);
  std::uint32_t components = 0;
  auto labelOf = [&](std::uint32_t f) {
    std::uint32_t& l = label[find(f)];
    if (l == ~0u) l = components++;
    return l;
  };
  if (n > 0 && faces.extremeAtom < n && faces.count[faces.extremeAtom] > 0)
    labelOf(faceBegin[faces.extremeAtom] + std::min(faces.extremeFace, faces.count[faces.extremeAtom] - 1));
  out.convex.component.resize(out.convex.size());
  for (std::size_t k = 0; k < out.convex.size(); ++k) {
    const std::uint32_t x = out.convex.atom[k];
    std::uint32_t lowest = ~0u;
    for (std::uint32_t f = faceBegin[x]; f < faceBegin[x + 1]; ++f) lowest = std::min(lowest, labelOf(f));
    out.convex.component[k] = lowest == ~0u ? 0 : lowest;
  }
  out.tori.component.resize(out.tori.size());
  for (std::size_t t = 0; t < out.tori.size(); ++t)
    out.tori.component[t] = labelOf(faceBegin[out.tori.atomI[t]] + contours.torusFace[t]);
  cv.component.resize(cv.size());
  for (std::size_t v = 0; v < cv.size(); ++v) {
    if (vertexFace[v] != ~0u) {
      cv.component[v] = labelOf(vertexFace[v]);
    } else if (vertices.backToMergedFirst[v] != 0) {
      cv.component[v] = cv.component[v - vertices.backToMergedFirst[v]];
    } else {
      // A merged vertex with no arc at all (a probe trapped where it touches all its atoms,
      // the centre of a cube) is a component of its own; any other vertex without a face, 0.
      const bool merged =
          vertices.boundaryEdges[v] != 7 || (v + 1 < cv.size() && vertices.backToMergedFirst[v + 1] == 1);
      cv.component[v] = merged ? components++ : 0;
    }
  }
  out.componentCount = components;
}

}  // namespace surftrace::build
