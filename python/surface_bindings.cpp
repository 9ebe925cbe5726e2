// surftrace.ses, skin, sas, vdw, load, Surface and Updater: the stage "build" from Python, its
// areas, and the same surface frame after frame (partial updates).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/stl.h>

#include "bindings.hpp"

namespace surftrace::python {

using view::PatchKind;

namespace {

// The areas of `s`'s list (the SAS's from the SES of the same request); see PySurface::areasOf.
SurfaceAreas computeAreas(const PySurface& s) {
  const PatchList& p = *s.patches;
  if (p.params.surface != SurfaceKind::Sas) {
    if (p.params.surface == SurfaceKind::Mss && !s.molecule)
      throw std::invalid_argument("the areas of a skin loaded from a file need its atoms (per-atom shares): build it "
                                  "with surftrace.skin(molecule) instead");
    return surfaceAreas(p, s.molecule ? std::span<const glm::dvec3>(s.molecule->centers) : std::span<const glm::dvec3>());
  }
  if (!s.molecule)
    throw std::invalid_argument("the areas of a SAS loaded from a file need its atoms: build it with "
                                "surftrace.sas(molecule) (its area is that of the SES of the same probe)");
  // The SES's contour buildup gives the SAS of the same probe, exactly, as `surftrace area` reports it.
  SurfaceRequest ses = s.request;
  ses.surface = SurfaceKind::Ses;
  ses.dropCavities = false;
  const SurfaceAreas a = surfaceAreas(buildSurface(*s.molecule, ses), {});
  SurfaceAreas out;
  out.surface = SurfaceKind::Sas;
  out.total = a.sas;
  out.perAtom = a.sasPerAtom;
  out.sas = a.sas;
  out.sasPerAtom = a.sasPerAtom;
  out.volume = std::nan("");
  return out;
}

}  // namespace

const SurfaceAreas& PySurface::areasOf() const {
  if (!areas) {
    std::shared_ptr<const SurfaceAreas> computed;
    {
      py::gil_scoped_release unlocked;
      computed = std::make_shared<const SurfaceAreas>(computeAreas(*this));
    }
    // Holding the GIL again: another thread may have computed them meanwhile (the same values).
    if (!areas) areas = std::move(computed);
  }
  return *areas;
}

namespace {

double probeOrThrow(double probe) {
  if (!(probe > 0.0) || !std::isfinite(probe))
    throw py::value_error("probe: expected a finite radius > 0 (Å), got " + std::string(py::str(py::float_(probe))));
  return probe;
}

double shrinkOrThrow(double shrink) {
  if (!validShrinkFactor(shrink))
    throw py::value_error("shrink: expected a shrink factor in [" + std::string(py::str(py::float_(kMinShrinkFactor))) +
                          ", " + std::string(py::str(py::float_(kMaxShrinkFactor))) + "], got " +
                          std::string(py::str(py::float_(shrink))));
  return shrink;
}

const std::shared_ptr<const Molecule>& moleculeOf(py::handle molecule) {
  if (!py::isinstance<PyMolecule>(molecule))
    throw py::type_error("expected a surftrace.Molecule, got " +
                         std::string(py::str(py::type::handle_of(molecule).attr("__name__"))));
  return molecule.cast<const PyMolecule&>().molecule;
}

PySurface buildFor(py::handle moleculeObj, const SurfaceRequest& request) {
  PySurface s;
  s.molecule = moleculeOf(moleculeObj);
  s.request = request;
  {
    py::gil_scoped_release unlocked;
    s.patches = std::make_shared<const PatchList>(buildSurface(*s.molecule, request, &s.notes));
  }
  return s;
}

SurfaceRequest request(SurfaceKind kind, double probe, double shrink, bool dropCavities, double mergeWithin) {
  if (!(mergeWithin >= build::kMinMergeDistance))
    throw py::value_error("merge_within: expected at least " + std::string(py::str(py::float_(build::kMinMergeDistance))) +
                          " Å, got " + std::string(py::str(py::float_(mergeWithin))));
  return SurfaceRequest{kind, probe, shrink, dropCavities, mergeWithin};
}

// The rows of view::kPatchKinds a list of this kind holds.
std::vector<PatchKind> kindsOf(SurfaceKind kind) {
  switch (kind) {
    case SurfaceKind::Ses:
      return {PatchKind::Convex, PatchKind::Toroidal, PatchKind::Concave};
    case SurfaceKind::Mss:
      return {PatchKind::SkinConvex, PatchKind::SkinEdge, PatchKind::SkinFace, PatchKind::SkinConcave};
    case SurfaceKind::Vdw:
    case SurfaceKind::Sas:
      break;
  }
  return {PatchKind::Convex};
}

py::array perAtomView(const PySurface& s, const std::vector<double>& values) {
  s.areasOf();
  return readOnlyView(s.areas, values.data(), {static_cast<py::ssize_t>(values.size())});
}

const SurfaceAreas& withVolume(const PySurface& s) {
  const SurfaceAreas& a = s.areasOf();
  if (a.surface == SurfaceKind::Sas)
    throw py::value_error("the SAS's volume and components are not computed: use surftrace.ses(molecule, probe) for the "
                          "volume the SES encloses");
  return a;
}

// The same surface frame after frame.
struct PyUpdater {
  PyUpdater(std::shared_ptr<const Molecule> first, const SurfaceRequest& r)
      : molecule(std::move(first)), request(r), builder(r), atomCount(molecule->size()),
        fileAtomCount(molecule->fileAtomCount) {}
  std::shared_ptr<const Molecule> molecule;  // the atoms' records and radii; centres of the last frame
  const SurfaceRequest request;
  SurfaceBuilder builder;
  const std::size_t atomCount, fileAtomCount;  // the same every frame (read without the lock)
  bool built = false;
  // One frame at a time: taken with the GIL released (never held while waiting for the GIL).
  std::mutex busy;
};

PySurface update(PyUpdater& u, py::handle positions, py::handle moved) {
  // The atoms and their records are the same every frame: only the centres change.
  const std::size_t n = u.atomCount, fileAtoms = u.fileAtomCount;
  const py::array given = py::array::ensure(positions);
  if (given && given.ndim() == 2 && n != fileAtoms && static_cast<std::size_t>(given.shape(0)) == fileAtoms)
    throw py::value_error("positions: " + std::to_string(fileAtoms) + " rows, one per atom of the file; the molecule "
                          "holds " + std::to_string(n) + " of them: pass positions[molecule.indices] (MDAnalysis: "
                          "u.atoms[molecule.indices].positions)");
  // float32 positions (MDAnalysis) widen exactly, as the trajectory readers widen a DCD's floats.
  std::vector<glm::dvec3> centres = centresFrom(positions, "positions", n);
  const bool movedGiven = !moved.is_none();
  std::vector<char> isMoved(movedGiven ? n : 0, 0);
  if (movedGiven) {
    const std::vector<double> v = valuesFrom(moved, "moved", std::nullopt);
    for (std::size_t k = 0; k < v.size(); ++k) {
      if (v[k] != std::floor(v[k]) || v[k] < 0 || v[k] >= static_cast<double>(n))
        throw py::value_error("moved[" + std::to_string(k) + "] = " + std::string(py::str(py::float_(v[k]))) +
                              " is not an atom index in [0, " + std::to_string(n) + ")");
      isMoved[static_cast<std::size_t>(v[k])] = 1;
    }
  }
  PySurface s;
  s.request = u.request;
  py::gil_scoped_release unlocked;
  std::lock_guard<std::mutex> lock(u.busy);
  auto next = std::make_shared<Molecule>(*u.molecule);
  next->centers = std::move(centres);
  build::validateMolecule(*next);
  std::vector<std::uint32_t> movedAtoms;
  for (std::size_t i = 0; i < isMoved.size(); ++i) {
    if (isMoved[i]) {
      movedAtoms.push_back(static_cast<std::uint32_t>(i));
    } else if (u.built && next->centers[i] != u.molecule->centers[i]) {
      // A partial update equals a full build only when every atom that moved is listed.
      throw std::invalid_argument("moved: atom " + std::to_string(i) +
                                  " moved but is not listed (list every atom that moved, or pass moved=None)");
    }
  }
  PatchList list = !u.built ? u.builder.build(*next)
                   : movedGiven ? u.builder.update(*next, movedAtoms)
                                : u.builder.update(*next);
  s.patches = std::make_shared<const PatchList>(std::move(list));
  s.molecule = next;
  u.molecule = std::move(next);
  u.built = true;
  return s;
}

}  // namespace

void bindSurfaces(py::module_& m) {
  py::class_<PySurface>(m, "Surface", R"(A surface's patch list, exact, and its areas (Å²) and volume (Å³), computed on first use.

kind is "ses", "mss" (the skin), "vdw" or "sas". The SES's and the skin's areas are their own;
the vdW surface's are those of the union of the balls; the SAS's area and per-atom areas are
those the SES of the same probe computes (a SES build on first use), and its volume and
components are not computed (ValueError). A surface loaded from a file has no molecule: its
SES areas are known, a loaded skin's or SAS's are not (ValueError).)")
      .def_property_readonly("kind", [](const PySurface& s) { return std::string(surfaceKindName(s.patches->params.surface)); })
      .def_property_readonly("probe", [](const PySurface& s) { return s.patches->params.probeRadius; }, "Probe radius (Å)")
      .def_property_readonly("shrink", [](const PySurface& s) { return s.patches->params.shrinkFactor; }, "Skin shrink factor")
      .def_property_readonly("molecule",
                             [](const PySurface& s) { return s.molecule ? moleculeObject(s.molecule) : py::object(py::none()); })
      .def_property_readonly("notes", [](const PySurface& s) { return s.notes; },
                             "What the build left out (atoms inside others, merged ones), one sentence each")
      .def_property_readonly("area", [](const PySurface& s) { return s.areasOf().total; }, "Total area, Å²")
      .def_property_readonly("volume", [](const PySurface& s) { return withVolume(s).volume; }, "Enclosed volume, Å³")
      .def_property_readonly(
          "atom_area", [](const PySurface& s) { return perAtomView(s, s.areasOf().perAtom); },
          "(n,) float64: each atom's share of the area, in the molecule's order (0 for atoms with no "
          "patch); a read-only view, no copy; sums to area")
      .def_property_readonly(
          "area_by_kind",
          [](const PySurface& s) {
            const SurfaceAreas& a = s.areasOf();
            py::dict out;
            for (std::size_t k = 0; k < a.byKind.size(); ++k) out[py::str(a.kindNames[k])] = a.byKind[k];
            return out;
          },
          "Area by patch kind: the SES's convex, toroidal, concave; the skin's (and vdW's) convex, edge, face, concave")
      .def_property_readonly("sas_area", [](const PySurface& s) { return s.areasOf().sas; },
                             "The SES (and SAS): the solvent-accessible area of the same probe, Å²")
      .def_property_readonly(
          "sas_atom_area", [](const PySurface& s) { return perAtomView(s, s.areasOf().sasPerAtom); },
          "The SES (and SAS): each atom's solvent-accessible area, (n,) float64")
      .def_property_readonly("area_error_estimate", [](const PySurface& s) { return s.areasOf().areaErrorEstimate; },
                             "The skin: estimated quadrature error of its area")
      .def_property_readonly("volume_error_estimate", [](const PySurface& s) { return s.areasOf().volumeErrorEstimate; })
      .def_property_readonly(
          "components",
          [](const PySurface& s) {
            py::list out;
            for (const ComponentArea& c : withVolume(s).components)
              out.append(py::dict(py::arg("area") = c.area, py::arg("volume") = c.volume, py::arg("cavity") = c.cavity));
            return out;
          },
          "The SES's closed pieces: dicts of area (Å²), volume (Å³, negative for a cavity) and cavity (bool); "
          "empty for the other surfaces")
      .def_property_readonly("component_areas",
                             [](const PySurface& s) {
                               std::vector<double> v;
                               for (const ComponentArea& c : withVolume(s).components) v.push_back(c.area);
                               return py::array_t<double>(static_cast<py::ssize_t>(v.size()), v.data());
                             })
      .def_property_readonly("component_volumes",
                             [](const PySurface& s) {
                               std::vector<double> v;
                               for (const ComponentArea& c : withVolume(s).components) v.push_back(c.volume);
                               return py::array_t<double>(static_cast<py::ssize_t>(v.size()), v.data());
                             })
      .def_property_readonly("cavities",
                             [](const PySurface& s) {
                               const auto& c = withVolume(s).components;
                               py::array_t<bool> out(static_cast<py::ssize_t>(c.size()));
                               for (std::size_t k = 0; k < c.size(); ++k) out.mutable_data()[k] = c[k].cavity;
                               return out;
                             })
      .def_property_readonly(
          "patch_counts",
          [](const PySurface& s) {
            py::dict out;
            for (PatchKind kind : kindsOf(s.patches->params.surface))
              out[py::str(view::kPatchKinds[view::kindRow(kind)].name)] = patchCount(*s.patches, kind);
            return out;
          },
          "Patches by kind (the names of the renderers' patch-kind channel)")
      .def(
          "save",
          [](const PySurface& s, py::handle path) {
            const std::string file = pathFrom(path);
            py::gil_scoped_release unlocked;
            PatchListAtoms atoms;
            if (s.molecule) atoms = {s.molecule->centers, s.molecule->radii};
            surftrace::writePatchList(file, *s.patches, atoms);
          },
          py::arg("path"), "Writes the patch list (.stp, with the atoms), whole or not at all: the bytes `surftrace build` writes")
      .def("__repr__", [](const PySurface& s) {
        const auto& p = s.patches->params;
        return "<surftrace.Surface " + std::string(surfaceKindName(p.surface)) + " of " + std::to_string(p.atomCount) +
               " atoms" + (s.molecule ? "" : ", loaded") + ">";
      });

  const double merge = build::kMinMergeDistance;
  m.def(
      "ses",
      [](py::handle mol, double probe, bool dropCavities, double mergeWithin) {
        return buildFor(mol, request(SurfaceKind::Ses, probeOrThrow(probe), 0.5, dropCavities, mergeWithin));
      },
      py::arg("molecule"), py::arg("probe") = 1.4, py::arg("drop_cavities") = false, py::arg("merge_within") = merge,
      "The solvent-excluded surface of probe radius `probe` (Å), as `surftrace build`/`area` build it; "
      "drop_cavities keeps the outer components only. The GIL is released while it builds.");
  m.def(
      "skin",
      [](py::handle mol, double shrink, double mergeWithin) {
        return buildFor(mol, request(SurfaceKind::Mss, 1.4, shrinkOrThrow(shrink), false, mergeWithin));
      },
      py::arg("molecule"), py::arg("shrink") = 0.5, py::arg("merge_within") = merge,
      "The molecular skin of shrink factor `shrink` (`--surface mss`); at shrink = 1 the union of the vdW balls.");
  m.def(
      "sas",
      [](py::handle mol, double probe, double mergeWithin) {
        return buildFor(mol, request(SurfaceKind::Sas, probeOrThrow(probe), 0.5, false, mergeWithin));
      },
      py::arg("molecule"), py::arg("probe") = 1.4, py::arg("merge_within") = merge,
      "The solvent-accessible surface: spheres of r + probe. Its area is the SES's SAS of the same probe "
      "(built on first use of .area); it has no volume here.");
  m.def(
      "vdw", [](py::handle mol, double mergeWithin) { return buildFor(mol, request(SurfaceKind::Vdw, 1.4, 0.5, false, mergeWithin)); },
      py::arg("molecule"), py::arg("merge_within") = merge,
      "The van der Waals spheres; its area and volume are those of the union of the balls.");
  m.def(
      "load",
      [](py::handle path) {
        const std::string file = pathFrom(path);
        PySurface s;
        try {
          py::gil_scoped_release unlocked;
          s.patches = std::make_shared<const PatchList>(readPatchList(file));
        } catch (const build::InputError&) {
          throw;
        } catch (const std::runtime_error& e) {
          // A file that cannot be opened: bad input, as surftrace.read says of one.
          throw py::value_error(e.what());
        }
        s.request = SurfaceRequest::of(s.patches->params);
        return s;
      },
      py::arg("path"), "A patch list from a .stp file, without its molecule.");

  py::class_<PyUpdater>(m, "Updater", R"(The same surface frame after frame, rebuilt only where atoms moved.

Updater(molecule, surface="ses", probe=1.4, shrink=0.5): surface "ses" or "skin" ("mss"; "vdw"
and "sas" are rebuilt whole). update(positions, moved=None) takes the atoms' new centres, (n, 3)
in the molecule's atom order (float32 from MDAnalysis is widened exactly, as the command line's
trajectory readers widen a DCD's), and returns the Surface of that frame, equal bit for bit to a
full build of it; `moved` (atom indices) names the atoms that moved, else they are found by
comparing with the last frame. The first call is a full build.)")
      .def(py::init([](py::handle mol, const std::string& surface, double probe, double shrink, double mergeWithin) {
             const SurfaceKind kind = surface == "skin" ? SurfaceKind::Mss : parseSurfaceKind(surface);
             const SurfaceRequest r = request(kind, probeOrThrow(probe), shrinkOrThrow(shrink), false, mergeWithin);
             return std::make_unique<PyUpdater>(moleculeOf(mol), r);
           }),
           py::arg("molecule"), py::arg("surface") = "ses", py::arg("probe") = 1.4, py::arg("shrink") = 0.5,
           py::arg("merge_within") = merge)
      .def("update", &update, py::arg("positions"), py::arg("moved") = py::none())
      .def_property_readonly(
          "recomputed",
          [](PyUpdater& u) {
            py::gil_scoped_release unlocked;
            std::lock_guard<std::mutex> lock(u.busy);
            return u.built ? u.builder.lastRecomputed() : std::size_t{0};
          },
          "Atoms recomputed by the last update (all of them for the first)")
      .def_property_readonly("molecule",
                             [](PyUpdater& u) {
                               std::shared_ptr<const Molecule> last;
                               {
                                 py::gil_scoped_release unlocked;
                                 std::lock_guard<std::mutex> lock(u.busy);
                                 last = u.molecule;
                               }
                               return moleculeObject(std::move(last));
                             },
                             "The molecule at the last frame");
}

}  // namespace surftrace::python
