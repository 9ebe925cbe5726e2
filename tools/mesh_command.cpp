// `surftrace mesh`: a triangle mesh of the exact surface (PLY, OBJ, GLB) with every vertex on
// the surface, closed and outward-oriented per component, and a certified maximum deviation.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/vec4.hpp>
#include <tbb/parallel_for.h>

#include "build/io/mesh_writer.hpp"
#include "build/io/output_file.hpp"
#include "build/mesh/mesher.hpp"
#include "build/mesh/surface_distance.hpp"
#include "commands.hpp"
#include "option_checks.hpp"
#include "progress_bar.hpp"
#include "surface_input.hpp"
#include "surftrace/surface.hpp"
#include "trace/mss_patch.hpp"

namespace surftrace::tools {
namespace {

struct MeshOptions {
  std::string path;
  build::ReadOptions read;
  SurfaceOptions surface;
  int threads = 0;
  std::string output;
  double maxError = 0.1;
  double grid = 0.0;  // 0: chosen from the surface
  std::string component = "all";
};

// The marching-tetrahedra grid spacing: below the field's reach, and fine enough that every
// component of the surface has grid vertices inside it and outside it. SES: every cavity holds
// a probe ball of radius rp, which holds a grid vertex once h < 2rp/√3; rp/2 leaves a margin.
// vdW and SAS: half the smallest sphere radius, so that every sphere holds grid vertices.
// Skin: half the smallest skin sphere radius √(1 − s)·r (ORACLES C.4: atom spheres shrink
// by √(1 − s)); skin cavities smaller than that can be missed, as can SAS voids.
double gridSpacing(const MeshOptions& o, const build::Molecule& m, double reach) {
  if (o.grid > 0.0) return o.grid;
  const double rMin = m.radii.empty() ? 1.0 : *std::min_element(m.radii.begin(), m.radii.end());
  double h = 0.5;
  if (o.surface.surface == "ses") h = o.surface.probe / 2.0;
  else if (o.surface.surface == "vdw") h = rMin / 2.0;
  else if (o.surface.surface == "sas") h = (rMin + o.surface.probe) / 2.0;
  else h = std::sqrt(1.0 - o.surface.shrink) * rMin / 2.0;
  return std::min({h, 0.7, 0.9 * reach});
}

// Which components --component keeps, by meshComponents' numbering.
std::vector<bool> selectComponents(const std::string& which, const std::vector<build::mesh::MeshComponent>& c) {
  std::vector<bool> keep(c.size(), false);
  if (which == "all") keep.assign(c.size(), true);
  else if (which == "outer" || which == "cavities")
    for (std::size_t k = 0; k < c.size(); ++k) keep[k] = (c[k].volume > 0.0) == (which == "outer");
  else {
    char* end = nullptr;
    const unsigned long n = std::strtoul(which.c_str(), &end, 10);
    if (which.empty() || *end != '\0')
      throw std::invalid_argument("--component " + which + ": expected all, outer, cavities or a component number");
    bool found = false;
    for (std::size_t k = 0; k < c.size(); ++k)
      if (c[k].surfaceComponent == n) keep[k] = found = true;
    if (!found)
      throw std::invalid_argument("--component " + which + ": the surface has no such component (it has " +
                                  std::to_string(c.size()) + "; `surftrace mesh` without --component lists them)");
  }
  return keep;
}

void runMesh(const MeshOptions& o) {
  // The vdW and SAS surfaces are refused before any work rather than left to run: their creases
  // are bridged by triangles whose split points never reach the crease (the refinement grows
  // without bound: 1CRN's SAS went from 50k to 13M triangles at 0.1 Å). The skin is smooth (C¹,
  // no creases) and is meshed; where it has a tunnel or pocket narrower than the grid (near a
  // change of its topology) the refinement stops with the place named.
  if (o.surface.surface != "ses" && o.surface.surface != "mss")
    throw std::invalid_argument("--surface " + o.surface.surface +
                                ": mesh makes SES and skin meshes only so far (the refinement does not yet converge "
                                "at the creases of the vdW and SAS surfaces); use --surface ses or mss, or render the " +
                                o.surface.surface + " surface exactly with `render`");
  build::meshFormatOf(o.output);  // a name with no known extension fails before any work
  build::prepareOutputPath(o.output, "-o", build::OutputContent::Binary);
  const auto limit = limitThreads(o.threads);
  const auto start = std::chrono::steady_clock::now();
  const build::Molecule m = readInput(o.path, "", 0, o.read);
  const build::PatchList patches = buildWithNotes(m, o.surface.request());
  const double buildSeconds = secondsSince(start);
  const auto meshStart = std::chrono::steady_clock::now();
  const std::unique_ptr<build::mesh::SurfaceDistance> field =
      build::mesh::makeSurfaceDistance(patches, m.centers, m.radii);
  build::mesh::MeshParams params;
  params.maxError = o.maxError;
  params.gridSpacing = gridSpacing(o, m, field->reach());
  params.features = build::mesh::thinFeatures(patches, params.gridSpacing);
  params.followFolds = !patches.mss.kind.empty();
  ProgressBar bar(true, "meshing");
  params.progress = [&bar](double f) { bar.update(f); };
  const std::vector<glm::dvec3> seeds = build::mesh::surfaceSeeds(patches);
  build::mesh::MeshResult r = build::mesh::meshSurface(*field, seeds, params);
  bar.clear();
  // A skin vertex belongs to the atom whose ball owns it, of all the atoms (least power distance,
  // as the renderers name it: trace::skinOwner); the field knows only its simplex's atoms, whose
  // best is where the search starts.
  if (!patches.skinAtoms.center.empty()) {
    const trace::SkinAtomBalls balls = trace::skinAtomBalls(patches);
    tbb::parallel_for(std::size_t{0}, r.mesh.positions.size(), [&](std::size_t v) {
      r.mesh.atom[v] = trace::skinOwner(&balls, glm::uvec4(r.mesh.atom[v], ~0u, ~0u, ~0u), r.mesh.positions[v]);
    });
  }
  const double meshSeconds = secondsSince(meshStart);
  std::vector<build::mesh::MeshComponent> components = build::mesh::meshComponents(r.mesh);
  if (o.component != "all") {
    r.mesh = build::mesh::keepComponents(r.mesh, selectComponents(o.component, components));
    components = build::mesh::meshComponents(r.mesh);
  }
  const auto writeStart = std::chrono::steady_clock::now();
  build::writeMesh(o.output, r.mesh);
  const double writeSeconds = secondsSince(writeStart);

  std::FILE* out = build::isStandardOutput(o.output) ? stderr : stdout;
  double area = 0.0, volume = 0.0;
  std::size_t outer = 0, open = 0;
  for (const auto& c : components) area += c.area, volume += c.volume, outer += c.volume > 0.0, open += !c.closed;
  std::fprintf(out, "mesh            %s: %zu vertices, %zu triangles, %zu components (%zu outer, %zu cavities)%s\n",
               o.output.c_str(), r.mesh.vertexCount(), r.mesh.triangleCount(), components.size(), outer,
               components.size() - outer, open ? (", " + std::to_string(open) + " NOT CLOSED").c_str() : "");
  std::fprintf(out, "max deviation   %.6f Å certified (--max-error %g Å; grid %.3f Å, %d refinement rounds)\n",
               r.certifiedError, o.maxError, params.gridSpacing, r.rounds);
  if (r.refinedCells)
    std::fprintf(out, "thin parts      %zu grid cells subdivided where the body or a gap is thinner than the grid\n",
                 r.refinedCells);
  if (r.badTriangles)
    std::fprintf(out, "warning         %zu triangles face against the surface's normals\n", r.badTriangles);
  // The exact area and volume where the patches give them (SES, skin): of the whole surface,
  // or with --component of the surface components kept (the mesh's pieces name them).
  std::optional<SurfaceAreas> exact;
  try {
    exact = surfaceAreas(patches, m.centers);
  } catch (const std::invalid_argument&) {
  }
  double exactArea = exact ? exact->total : 0.0, exactVolume = exact ? exact->volume : 0.0;
  if (exact && o.component != "all") {
    exactArea = exactVolume = 0.0;
    std::vector<bool> counted(exact->components.size(), false);
    for (const auto& c : components) {
      if (c.surfaceComponent >= counted.size()) exact.reset();  // a piece the areas do not list
      if (!exact) break;
      if (counted[c.surfaceComponent]) continue;
      counted[c.surfaceComponent] = true;
      exactArea += exact->components[c.surfaceComponent].area;
      exactVolume += exact->components[c.surfaceComponent].volume;
    }
  }
  if (exact && exactArea > 0.0) {
    const char* of = o.component == "all" ? "" : " of the kept components";
    std::fprintf(out, "area            %.4f Å² (exact%s %.4f Å², %+.4f%%)\n", area, of, exactArea,
                 100.0 * (area - exactArea) / exactArea);
    std::fprintf(out, "volume          %.4f Å³ (exact%s %.4f Å³, %+.4f%%)\n", volume, of, exactVolume,
                 100.0 * (volume - exactVolume) / std::abs(exactVolume));
  } else {
    std::fprintf(out, "area            %.4f Å²\nvolume          %.4f Å³\n", area, volume);
  }
  const std::size_t shown = std::min<std::size_t>(components.size(), 20);
  for (std::size_t k = 0; k < shown; ++k) {
    const auto& c = components[k];
    std::fprintf(out, "  component %-4u %-7s %8zu triangles, Euler characteristic %lld, area %.3f Å², volume %.3f Å³\n",
                 c.surfaceComponent, c.volume > 0.0 ? "outer" : "cavity", c.triangles, c.euler, c.area, c.volume);
  }
  if (shown < components.size()) std::fprintf(out, "  ... and %zu more components\n", components.size() - shown);
  std::fprintf(out, "time            read and build %.1f ms, mesh %.1f ms (%zu grid cells), write %.1f ms\n",
               buildSeconds * 1e3, meshSeconds * 1e3, r.gridCells, writeSeconds * 1e3);
}

}  // namespace

void addMeshCommand(CLI::App& app) {
  auto o = std::make_shared<MeshOptions>();
  auto* cmd = app.add_subcommand(
      "mesh",
      "A triangle mesh of the exact surface: every vertex on it (exact normals, atom ids, patch kinds, components), "
      "closed per component, outward-oriented, and within a certified --max-error of it");
  cmd->add_option("FILE", o->path, "Structure file (PDB, mmCIF, PQR, XYZR, XYZ; .gz allowed)")->required();
  addSurfaceOptions(*cmd, o->surface, SurfaceChoice::Any);
  cmd->add_option("-o,--output", o->output,
                  "Mesh file: .ply (binary, with per-vertex normals, atom_id, patch_kind, component), .obj "
                  "(positions, normals) or .glb (glTF: normals and the attributes _ATOM_ID, _PATCH_KIND, _COMPONENT)")
      ->required();
  cmd->add_option("--max-error", o->maxError,
                  "Largest distance in Å of any point of the mesh from the exact surface, certified for each "
                  "triangle from the SES patch's curvature or by sampling it; smaller values give more triangles (about 1/ε) and take longer")
      ->check(positive())
      ->default_val(0.1);
  cmd->add_option("--component", o->component,
                  "Which surface components to write: all, outer (outer surfaces), cavities (inner surfaces of "
                  "buried cavities), or the component number N that the listing shows")
      ->default_val("all");
  cmd->add_option("--grid", o->grid,
                  "Spacing in Å of the grid that finds the surface (default: from the probe or the smallest radius); "
                  "finer finds smaller cavities, coarser is faster")
      ->check(positive());
  cmd->add_option("--threads", o->threads, "Worker threads (default: all cores); results do not depend on it")
      ->check(wholeIn(0, 4096));
  addMoleculeOptions(*cmd, o->read);
  cmd->callback([o] { runMesh(*o); });
}

}  // namespace surftrace::tools
