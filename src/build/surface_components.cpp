// The SES's outer surfaces alone, or its cavities alone: components dropped from a patch list.
#include "build/surface_components.hpp"

#include <algorithm>
#include <cstring>
#include <vector>

#include "build/ses/surface_area.hpp"

namespace surftrace::build {

namespace {

// The patches of `in` that the masks keep, into `out` (a copy of `in`, its convex labels and
// areas already set): tori and concave patches relabelled, the kept concave patches'
// clipping planes packed in order, every array of a kind filtered alike.
void keepPatches(const PatchList& in, PatchList& out, const std::vector<bool>& keepConvex, const std::vector<bool>& keepTori,
                 const std::vector<bool>& keepConcave, const std::vector<std::uint32_t>& relabel) {
  for (std::size_t t = 0; t < in.tori.size(); ++t)
    if (keepTori[t]) out.tori.component[t] = relabel[in.tori.component[t]];
  for (std::size_t k = 0; k < in.concave.size(); ++k)
    if (keepConcave[k]) out.concave.component[k] = relabel[in.concave.component[k]];
  // Kept concave patches' clipping planes, packed in order, with their begin indices moved.
  out.clipPlanes.clear();
  for (std::size_t k = 0; k < in.concave.size(); ++k) {
    if (!keepConcave[k]) continue;
    out.concave.clipBegin[k] = static_cast<std::uint32_t>(out.clipPlanes.size());
    out.clipPlanes.insert(out.clipPlanes.end(), in.clipPlanes.begin() + in.concave.clipBegin[k],
                          in.clipPlanes.begin() + in.concave.clipBegin[k] + in.concave.clipCount[k]);
  }
  // Every array of a kind loses the same entries: the visitor reaches fields added later too.
  forEachArray([&](const char* group, const char*, auto& v) {
    const std::vector<bool>* keep = std::strcmp(group, "convex") == 0    ? &keepConvex
                                    : std::strcmp(group, "tori") == 0    ? &keepTori
                                    : std::strcmp(group, "concave") == 0 ? &keepConcave
                                                                          : nullptr;
    if (!keep) return;
    std::size_t kept = 0;
    for (std::size_t k = 0; k < v.size(); ++k)
      if ((*keep)[k]) v[kept++] = v[k];
    v.resize(kept);
  }, out);
}

}  // namespace

PatchList outerComponent(const PatchList& in) {
  // New label of each component: outer ones in order, ~0u for cavities.
  const SurfaceAreas areas = computeAreas(in);
  std::vector<std::uint32_t> relabel(std::max<std::size_t>(in.componentCount, areas.components.size()), ~0u);
  std::uint32_t outer = 0;
  for (std::size_t c = 0; c < relabel.size(); ++c)
    if (c == 0 || (c < areas.components.size() && areas.components[c].outer())) relabel[c] = outer++;
  auto keepOuter = [&](const std::vector<std::uint32_t>& component) {
    std::vector<bool> keep(component.size());
    for (std::size_t k = 0; k < component.size(); ++k) keep[k] = component[k] < relabel.size() && relabel[component[k]] != ~0u;
    return keep;
  };
  std::vector<bool> keepConvex = keepOuter(in.convex.component);
  const std::vector<bool> keepTori = keepOuter(in.tori.component), keepConcave = keepOuter(in.concave.component);
  // A convex patch carries its atom's lowest label; it stays, with the outer label, when a
  // torus of its atom is on an outer surface.
  std::vector<std::uint32_t> atomOuter(in.params.atomCount, ~0u);
  for (std::size_t t = 0; t < in.tori.size(); ++t)
    if (keepTori[t])
      for (const std::uint32_t x : {in.tori.atomI[t], in.tori.atomJ[t]})
        if (x < atomOuter.size()) atomOuter[x] = std::min(atomOuter[x], relabel[in.tori.component[t]]);
  PatchList out = in;
  for (std::size_t k = 0; k < in.convex.size(); ++k) {
    const std::uint32_t x = in.convex.atom[k];
    if (keepConvex[k]) out.convex.component[k] = relabel[in.convex.component[k]];
    else if (x < atomOuter.size() && atomOuter[x] != ~0u) keepConvex[k] = true, out.convex.component[k] = atomOuter[x];
  }
  // A kept convex patch that also faces a dropped cavity is drawn whole (its cavity side is
  // hidden from outside), but its area and vector area are the outer side's alone, so that
  // the list's areas are the outer surfaces' (computeAreas splits them the same way).
  const std::vector<std::vector<ConvexPart>> parts = convexPartsOfOtherComponents(in);
  for (std::size_t k = 0; k < in.convex.size(); ++k) {
    if (!keepConvex[k]) continue;
    const bool ownDropped = !(in.convex.component[k] < relabel.size() && relabel[in.convex.component[k]] != ~0u);
    if (ownDropped) {
      // Labelled by a cavity, kept for an outer side: its area is that outer side's.
      double area = 0.0;
      glm::dvec3 vectorArea(0.0);
      for (const ConvexPart& part : parts[k])
        if (part.component < relabel.size() && relabel[part.component] != ~0u) area += part.area, vectorArea += part.vectorArea;
      out.convex.area[k] = area;
      out.convex.vectorArea[k] = vectorArea;
      continue;
    }
    for (const ConvexPart& part : parts[k])
      if (!(part.component < relabel.size() && relabel[part.component] != ~0u)) {
        out.convex.area[k] = std::max(0.0, out.convex.area[k] - part.area);
        out.convex.vectorArea[k] -= part.vectorArea;
      }
  }
  keepPatches(in, out, keepConvex, keepTori, keepConcave, relabel);
  out.componentCount = in.componentCount > 0 ? outer : 0u;
  return out;
}

PatchList cavityComponents(const PatchList& in) {
  // New label of each component: cavities in order, ~0u for the outer surfaces.
  const SurfaceAreas areas = computeAreas(in);
  std::vector<std::uint32_t> relabel(std::max<std::size_t>(in.componentCount, areas.components.size()), ~0u);
  std::uint32_t cavities = 0;
  for (std::size_t c = 0; c < relabel.size(); ++c)
    if (c < areas.components.size() && !areas.components[c].outer()) relabel[c] = cavities++;
  auto keepCavity = [&](const std::vector<std::uint32_t>& component) {
    std::vector<bool> keep(component.size());
    for (std::size_t k = 0; k < component.size(); ++k) keep[k] = component[k] < relabel.size() && relabel[component[k]] != ~0u;
    return keep;
  };
  const std::vector<bool> keepConvex = keepCavity(in.convex.component), keepTori = keepCavity(in.tori.component),
                          keepConcave = keepCavity(in.concave.component);
  // Only patches labelled by a cavity: the convex patch of an atom that faces the outside
  // too carries the outer label and is left out, since every renderer draws a convex patch
  // as its whole sphere, and that one's outer side would be drawn. A kept convex patch that
  // also faces an outer surface keeps the cavities' part of its area alone.
  PatchList out = in;
  const std::vector<std::vector<ConvexPart>> parts = convexPartsOfOtherComponents(in);
  for (std::size_t k = 0; k < in.convex.size(); ++k) {
    if (!keepConvex[k]) continue;
    out.convex.component[k] = relabel[in.convex.component[k]];
    for (const ConvexPart& part : parts[k])
      if (!(part.component < relabel.size() && relabel[part.component] != ~0u)) {
        out.convex.area[k] = std::max(0.0, out.convex.area[k] - part.area);
        out.convex.vectorArea[k] -= part.vectorArea;
      }
  }
  keepPatches(in, out, keepConvex, keepTori, keepConcave, relabel);
  out.componentCount = cavities;
  return out;
}

}  // namespace surftrace::build
