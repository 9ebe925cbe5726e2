// SES clipping planes: the self-intersection planes between probe positions closer than 2 rp.
#include <cstdint>
#include <span>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "build/ses_assembly.hpp"
#include "build/ses_builder_state.hpp"

namespace surftrace::build {

using namespace detail;

// Self-intersections (ORACLES A.5): every pair of probe positions closer than 2 rp cuts
// both probe spheres along their bisector plane. The probe positions sit in a neighbour
// grid of their own (probeGrid: radius rp each, no probe), whose neighbour relation is
// exactly |p − q| < 2 rp. No cap on the number of planes per patch. Fills fp with the
// planes of the probes listed (ascending).
void SesBuilder::State::planesOf(std::span<const std::uint32_t> probes) {
  const auto& probe = out.concave.probe;
  runChunks(tls, probes.size(), planePieces, [](Scratch& s) -> PlaneBuf& { return s.planeOut; },
            [&](std::size_t k, Scratch& s, PlaneBuf& buf) {
              const std::uint32_t a = probes[k];
              s.row.clear();
              probeGrid.neighbours(a, s.row);
              std::uint32_t count = 0;
              for (const std::uint32_t b : s.row) {
                const glm::dvec3 v = probe[b] - probe[a];
                if (!(glm::dot(v, v) > 0.0)) continue;  // coincident probes (cospherical atoms): no plane
                buf.partner.push_back(b);
                ++count;
              }
              buf.count.push_back(count);
            });
  gatherPieces(planePieces, offsets, Field{&PlaneBuf::partner, &fpPartner, 0}, Field{&PlaneBuf::count, &fpCount, 2});
  prefix(fpCount, fpBegin);
  fpPlanes.resize(fpPartner.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, probes.size(), kBlock), [&](const auto& range) {
    for (std::size_t k = range.begin(); k != range.end(); ++k) {
      const glm::dvec3& pa = probe[probes[k]];
      for (std::uint32_t i = fpBegin[k]; i < fpBegin[k + 1]; ++i) {
        const glm::dvec3& pb = probe[fpPartner[i]];
        const glm::dvec3 v = pb - pa;
        const double len = glm::length(v);
        const glm::dvec3 nrm = v / len;
        const glm::dvec3 mid = 0.5 * (pa + pb);
        fpPlanes[i] = Plane(nrm, -glm::dot(nrm, mid));
      }
    }
  });
}

}  // namespace surftrace::build
