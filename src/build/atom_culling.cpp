// Contained and near-coincident atoms left out before a union-of-balls surface is built,
// and near-coincident clusters found, in time linear in the atom count.
#include "build/atom_culling.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <numeric>

#include <glm/geometric.hpp>

#include "build/core/assert.hpp"
#include "build/ses/sas_geometry.hpp"

namespace surftrace::build {
namespace {

// Candidates an atom looks at, in each pass. A cluster of N near-coincident atoms puts all of
// them in one cell; this cap is what keeps the passes linear there. 64 is far more than a
// real molecule ever offers (no atom has another within the containment reach, usually
// 0.7 Å, and none within kClusterRadius).
constexpr std::size_t kMaxCandidates = 64;
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

struct CellKey {
  std::int64_t x, y, z;
  bool operator==(const CellKey&) const = default;
};

// Atoms binned into cubic cells of a given edge, found through an open-addressing table of
// the occupied cells (no bounding box: a far outlier costs nothing). Each cell holds a list
// of atoms in the order they are added.
class CellLists {
 public:
  CellLists(std::span<const glm::dvec3> centers, double edge) : centers_(centers), inv_(1.0 / edge) {
    const std::size_t n = centers.size();
    cellOf_.resize(n);
    std::size_t size = 16;
    while (size < 2 * n) size *= 2;
    table_.assign(size, kNone);
    for (std::size_t i = 0; i < n; ++i) cellOf_[i] = insert(keyOf(centers[i]));
    head_.assign(keys_.size(), kNone);
    tail_.assign(keys_.size(), kNone);
    next_.assign(n, kNone);
  }

  // Appends atom i to its cell's list.
  void add(std::uint32_t i) {
    const std::uint32_t c = cellOf_[i];
    if (tail_[c] == kNone) head_[c] = i;
    else next_[tail_[c]] = i;
    tail_[c] = i;
  }

  // visit(j) for the atoms listed in every cell that overlaps the box of half-width `reach`
  // about p, each cell's in list order, until visit returns false.
  template <class Visit> void forEachNear(const glm::dvec3& p, double reach, Visit&& visit) const {
    const CellKey lo = keyOf(p - reach), hi = keyOf(p + reach);
    for (std::int64_t z = lo.z; z <= hi.z; ++z)
      for (std::int64_t y = lo.y; y <= hi.y; ++y)
        for (std::int64_t x = lo.x; x <= hi.x; ++x) {
          const std::uint32_t c = find({x, y, z});
          if (c == kNone) continue;
          for (std::uint32_t j = head_[c]; j != kNone; j = next_[j])
            if (!visit(j)) return;
        }
  }

 private:
  CellKey keyOf(const glm::dvec3& p) const {
    // |x| <= 1e6 Å (validateMolecule) over an edge of at least 1e-5 Å: far inside int64.
    auto axis = [&](double x) {
      return static_cast<std::int64_t>(std::clamp(std::floor(x * inv_), -0x1p60, 0x1p60));
    };
    return {axis(p.x), axis(p.y), axis(p.z)};
  }
  // The cells of one 4x4x4 block take 64 consecutive slots: the block is hashed, the cell's
  // place in it kept. The 8 cells a query looks at then lie in one or two blocks, a cache line
  // or two of the table, where a hash of each cell put them in 8 random lines: with a million
  // atoms (a 16 MB table) those misses made culling 3 times as costly per atom as for 1AON.
  std::size_t slotOf(const CellKey& k) const {
    std::uint64_t h = static_cast<std::uint64_t>(k.x >> 2) * 0x9E3779B97F4A7C15ull ^
                      static_cast<std::uint64_t>(k.y >> 2) * 0xC2B2AE3D27D4EB4Full ^
                      static_cast<std::uint64_t>(k.z >> 2) * 0x165667B19E3779F9ull;
    h ^= h >> 29;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 32;
    const auto within = static_cast<std::uint64_t>((k.x & 3) | (k.y & 3) << 2 | (k.z & 3) << 4);
    return static_cast<std::size_t>(h << 6 | within) & (table_.size() - 1);
  }
  std::uint32_t find(const CellKey& k) const {
    for (std::size_t s = slotOf(k);; s = (s + 1) & (table_.size() - 1)) {
      if (table_[s] == kNone) return kNone;
      if (keys_[table_[s]] == k) return table_[s];
    }
  }
  std::uint32_t insert(const CellKey& k) {
    for (std::size_t s = slotOf(k);; s = (s + 1) & (table_.size() - 1)) {
      if (table_[s] == kNone) {
        table_[s] = static_cast<std::uint32_t>(keys_.size());
        keys_.push_back(k);
        return table_[s];
      }
      if (keys_[table_[s]] == k) return table_[s];
    }
  }

  std::span<const glm::dvec3> centers_;
  double inv_;
  std::vector<CellKey> keys_;          // per cell
  std::vector<std::uint32_t> table_;   // cell index, or kNone for an empty slot
  std::vector<std::uint32_t> cellOf_;  // per atom
  std::vector<std::uint32_t> head_, tail_, next_;
};

// The Hausdorff distance of two balls.
double ballDistance(const glm::dvec3& ci, double ri, const glm::dvec3& cj, double rj) {
  return glm::distance(ci, cj) + std::abs(ri - rj);
}

// Looks for a near-coincident cluster among the kept atoms: the first (lowest index) with
// more than kMaxClusterAtoms kept atoms within kClusterRadius, or with more candidates than
// kMaxCandidates in the cells about it (8 Å³: 8 atoms an Å³, a density no structure has
// either; proteins hold 0.12).
void findCluster(std::span<const glm::dvec3> c, std::span<const double> r, CullResult& out) {
  const std::vector<std::uint32_t>& kept = out.kept;
  if (kept.size() <= kMaxClusterAtoms) return;
  CellLists cells(c, 2.0 * kClusterRadius);  // a query box spans at most 2 cells per axis
  for (const std::uint32_t i : kept) cells.add(i);
  const double reach2 = kClusterRadius * kClusterRadius;
  std::uint32_t found = kNone;
  std::size_t crowded = 0;
  double largestSpread = 0.0;
  // Every kept atom is looked at, not only up to the first cluster: one merge distance in the
  // error then resolves all of them (1,000 clusters of 3 atoms would otherwise take 1,000 runs).
  for (const std::uint32_t i : kept) {
    std::size_t near = 0, seen = 0;
    double spread = 0.0;
    cells.forEachNear(c[i], kClusterRadius, [&](std::uint32_t j) {
      ++seen;
      const glm::dvec3 d = c[j] - c[i];
      if (glm::dot(d, d) <= reach2) ++near, spread = std::max(spread, ballDistance(c[j], r[j], c[i], r[i]));
      return seen <= kMaxCandidates;
    });
    out.candidates += seen;
    if (near > kMaxClusterAtoms || seen > kMaxCandidates) {
      if (found == kNone) found = i;
      ++crowded;
      largestSpread = std::max(largestSpread, spread);
    }
  }
  if (found == kNone) return;
  // Its extent, over every input atom (one pass): for the message and the merge distance
  // that would resolve it.
  NearCluster cl;
  cl.atom = found;
  for (std::size_t j = 0; j < c.size(); ++j) {
    const glm::dvec3 d = c[j] - c[found];
    if (glm::dot(d, d) > reach2) continue;
    const bool isKept = out.fate[j] == AtomFate::Kept;
    ++cl.atoms;
    cl.kept += isKept ? 1 : 0;
    cl.center += c[j];
    if (isKept) cl.spread = std::max(cl.spread, ballDistance(c[j], r[j], c[found], r[found]));
  }
  cl.center /= static_cast<double>(cl.atoms);
  cl.crowdedAtoms = crowded;
  cl.largestSpread = std::max(largestSpread, cl.spread);
  out.cluster = cl;
}

}  // namespace

CullResult cullAtoms(std::span<const glm::dvec3> c, std::span<const double> r, const CullParams& params) {
  SURFTRACE_ASSERT(c.size() == r.size());
  SURFTRACE_ASSERT(params.mergeWithin >= kMinMergeDistance && std::isfinite(params.mergeWithin));
  SURFTRACE_ASSERT(c.size() < kNone);
  const std::size_t n = c.size();
  CullResult out;
  out.inputCount = n;
  if (n == 0) return out;

  // The radii the containment test sees, rounded as contour-buildup rounds its extended radii.
  std::vector<double> R(n);
  for (std::size_t i = 0; i < n; ++i) R[i] = r[i] + params.inflate;
  const auto [rMin, rMax] = std::minmax_element(R.begin(), R.end());
  const double tau = params.mergeWithin;
  // A container of i lies within R_j − R_i <= R_max − R_i of it, a keeper within tau.
  const double maxReach = std::max(*rMax - *rMin, tau) * (1.0 + 1e-9);

  // Largest first, so that a container is decided before what it contains and is the first
  // candidate looked at; equal balls by index, so the lowest stays.
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return R[a] > R[b]; });

  // Cells twice the reach: a query box then spans at most 2 cells per axis, 8 lookups instead
  // of 27 (1AON: 20 ms instead of 45, beside an 800 ms build).
  CellLists cells(c, 2.0 * maxReach);
  out.fate.assign(n, AtomFate::Kept);
  for (const std::uint32_t i : order) {
    const double reach = std::max(*rMax - R[i], tau) * (1.0 + 1e-9);
    std::uint32_t keeper = kNone;
    bool inside = false;
    double distance = 0.0;
    std::size_t seen = 0;
    // Only kept atoms are listed: a container that is itself contained has its own container
    // listed, which contains i as well (containment is transitive, and decided exactly).
    cells.forEachNear(c[i], reach, [&](std::uint32_t j) {
      if (++seen > kMaxCandidates) return false;
      // Equal balls are inside each other only when they coincide; saying so directly spares
      // the exact fallback that near-coincident centres would take every time.
      if (params.dropContained && (R[j] == R[i] ? c[j] == c[i] : sphereInside(c[i], R[i], c[j], R[j]))) {
        keeper = j;
        inside = true;
        return false;
      }
      const double h = ballDistance(c[i], r[i], c[j], r[j]);
      if (h <= tau) {
        keeper = j;
        distance = h;
        return false;
      }
      return true;
    });
    out.candidates += std::min(seen, kMaxCandidates);
    if (keeper == kNone) {
      cells.add(i);
    } else if (inside) {
      out.fate[i] = AtomFate::Contained;
      if (out.contained++ == 0) out.containedExample = i, out.containerExample = keeper;
    } else {
      out.fate[i] = AtomFate::Merged;
      if (out.merged++ == 0 || distance > out.mergedDistance)
        out.mergedDistance = distance, out.mergedExample = i, out.keeperExample = keeper;
    }
  }
  out.kept.reserve(n - out.contained - out.merged);
  for (std::size_t i = 0; i < n; ++i)
    if (out.fate[i] == AtomFate::Kept) out.kept.push_back(static_cast<std::uint32_t>(i));
  findCluster(c, r, out);
  return out;
}

}  // namespace surftrace::build
