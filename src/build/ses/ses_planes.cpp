// SES clipping planes: the self-intersection planes between probe positions closer than 2 rp.
#include <cstdint>
#include <span>

#include <glm/geometric.hpp>

#include "build/ses/clip_planes.hpp"
#include "build/ses/ses_assembly.hpp"
#include "build/ses/ses_builder_state.hpp"

namespace surftrace::build {

using namespace detail;

// Self-intersections (ORACLES A.5): every pair of probe positions closer than 2 rp cuts
// both probe spheres along their bisector plane. The probe positions sit in a neighbour
// grid of their own (probeNeighbours: radius rp each, no probe), whose neighbour relation is
// exactly |p − q| < 2 rp. No cap on the number of planes per patch; a plane is stored with
// a concave patch unless it provably clips nothing of it (the cap it removes from the
// probe sphere misses the patch's spherical triangle, TriangleCone). On 1AON that
// keeps 1 plane in 20: the rest only cost memory here and a test per hit in every renderer.
// Fills pass.freshPlanes, freshPlaneCount and freshPlaneBegin with the planes of the probes
// listed (ascending).
void SesBuilder::State::planesOf(std::span<const std::uint32_t> probes) {
  const auto& cv = out.concave;
  const double twoRp = 2.0 * params.probeRadius;
  runChunks(pass.threadScratch, probes.size(), pass.planePieces,
            [](Scratch& s) -> PlaneBuf& { return s.planeOut; },
            [&](std::size_t k, Scratch& s, PlaneBuf& buf) {
              const std::uint32_t a = probes[k];
              s.row.clear();
              probeNeighbours.grid.neighbours(a, s.row);
              const glm::dvec3 pa = cv.probe[a];
              const TriangleCone cone({cv.dirI[a], cv.dirJ[a], cv.dirK[a]});
              std::uint32_t count = 0;
              for (const std::uint32_t b : s.row) {
                const glm::dvec3 pb = cv.probe[b];
                const glm::dvec3 v = pb - pa;
                if (!(glm::dot(v, v) > 0.0)) continue;  // coincident probes (cospherical atoms): no plane
                const double len = glm::length(v);
                const glm::dvec3 nrm = v / len;
                if (!cone.capMeets(nrm, len / twoRp)) continue;
                const glm::dvec3 mid = 0.5 * (pa + pb);
                buf.plane.emplace_back(nrm, -glm::dot(nrm, mid));
                ++count;
              }
              buf.count.push_back(count);
            });
  gatherPieces(pass.planePieces, pass.gatherOffsets, [&](auto&& field) {
    field(Field{&PlaneBuf::plane, &pass.freshPlanes, 0});
    field(Field{&PlaneBuf::count, &pass.freshPlaneCount, 2});
  });
  prefix(pass.freshPlaneCount, pass.freshPlaneBegin);
}

}  // namespace surftrace::build
