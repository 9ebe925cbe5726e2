// surftrace.read, surftrace.Molecule and Molecule.select: the stage "read" from Python, and the
// checks on every array that enters from numpy.
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/stl.h>

#include "bindings.hpp"

namespace surftrace::python {

static_assert(sizeof(glm::dvec3) == 3 * sizeof(double), "Molecule::centers is viewed as an (n, 3) float64 array");

py::array readOnlyView(std::shared_ptr<const void> owner, const double* data, std::vector<py::ssize_t> shape) {
  // The capsule holds a reference to the owner for as long as numpy holds the array.
  auto* keep = new std::shared_ptr<const void>(std::move(owner));
  py::capsule base(keep, [](void* p) { delete static_cast<std::shared_ptr<const void>*>(p); });
  // An empty vector may have no storage: numpy then makes its own (empty) array.
  py::array view(py::dtype::of<double>(), std::move(shape), {}, data, data ? py::handle(base) : py::handle());
  // The molecule is shared and const: a write through the view would change it under every
  // surface built from it.
  view.attr("setflags")(py::arg("write") = false);
  return view;
}

namespace {

std::string typeName(py::handle object) { return py::str(py::type::handle_of(object).attr("__name__")); }

// `object` as a numpy array of numbers in float64, C order (a copy only where it is not one).
py::array_t<double, py::array::c_style | py::array::forcecast> numbers(py::handle object, const std::string& what) {
  if (object.is_none()) throw py::type_error(what + ": expected an array of numbers, got None");
  py::array a = py::array::ensure(object);
  if (!a) throw py::type_error(what + ": expected an array of numbers, got " + typeName(object));
  const char kind = a.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u')
    throw py::type_error(what + ": expected numbers (float64, float32 or integers), got dtype " +
                         std::string(py::str(a.dtype())));
  auto converted = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!converted) throw py::type_error(what + ": dtype " + std::string(py::str(a.dtype())) + " does not convert to float64");
  return converted;
}

std::string shapeText(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t k = 0; k < a.ndim(); ++k) s += (k ? ", " : "") + std::to_string(a.shape(k));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

std::string numberText(double v) { return std::string(py::str(py::float_(v))); }

}  // namespace

std::vector<glm::dvec3> centresFrom(py::handle array, const std::string& what, std::optional<std::size_t> rows) {
  const auto a = numbers(array, what);
  if (a.ndim() != 2 || a.shape(1) != 3)
    throw py::value_error(what + ": expected shape (n, 3), got " + shapeText(a));
  const auto n = static_cast<std::size_t>(a.shape(0));
  if (rows && n != *rows)
    throw py::value_error(what + ": expected " + std::to_string(*rows) + " rows (one per atom), got " +
                          std::to_string(n));
  std::vector<glm::dvec3> out(n);
  const double* p = a.data();
  for (std::size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(p[3 * i + k]))
        throw py::value_error(what + "[" + std::to_string(i) + ", " + std::to_string(k) + "] is " +
                              numberText(p[3 * i + k]) + ": every coordinate must be finite");
    out[i] = {p[3 * i], p[3 * i + 1], p[3 * i + 2]};
  }
  return out;
}

std::vector<double> valuesFrom(py::handle array, const std::string& what, std::optional<std::size_t> rows) {
  const auto a = numbers(array, what);
  if (a.ndim() != 1) throw py::value_error(what + ": expected shape (n,), got " + shapeText(a));
  const auto n = static_cast<std::size_t>(a.shape(0));
  if (rows && n != *rows)
    throw py::value_error(what + ": expected " + std::to_string(*rows) + " values (one per atom), got " +
                          std::to_string(n));
  std::vector<double> out(a.data(), a.data() + n);
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(out[i]))
      throw py::value_error(what + "[" + std::to_string(i) + "] is " + numberText(out[i]) + ": every value must be finite");
  return out;
}

std::string pathFrom(py::handle path) {
  py::object text = py::module_::import("os").attr("fspath")(path);
  if (!py::isinstance<py::str>(text))
    throw py::type_error("expected a path as str or os.PathLike, got " + typeName(path));
  return text.cast<std::string>();
}

py::object moleculeObject(std::shared_ptr<const Molecule> molecule) { return py::cast(PyMolecule{std::move(molecule)}); }

namespace {

// Per-atom strings from a sequence of str (a list, a numpy array of str), `rows` of them.
std::vector<std::string> stringsFrom(py::handle values, const std::string& what, std::size_t rows) {
  if (py::isinstance<py::str>(values) || !py::isinstance<py::sequence>(values))
    throw py::type_error(what + ": expected a sequence of str (one per atom), got " + typeName(values));
  std::vector<std::string> out;
  for (py::handle item : values) {
    if (!py::isinstance<py::str>(item))
      throw py::type_error(what + "[" + std::to_string(out.size()) + "]: expected str, got " + typeName(item));
    out.push_back(item.cast<std::string>());
  }
  if (out.size() != rows)
    throw py::value_error(what + ": expected " + std::to_string(rows) + " values (one per atom), got " +
                          std::to_string(out.size()));
  return out;
}

// Per-atom whole numbers (residue numbers) from any integer array.
std::vector<int> integersFrom(py::handle values, const std::string& what, std::size_t rows) {
  py::array a = py::array::ensure(values);
  if (!a || (a.dtype().kind() != 'i' && a.dtype().kind() != 'u'))
    throw py::type_error(what + ": expected integers (one per atom), got " +
                         (a ? "dtype " + std::string(py::str(a.dtype())) : typeName(values)));
  const auto v = valuesFrom(a, what, rows);
  std::vector<int> out(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (v[i] < std::numeric_limits<int>::min() || v[i] > std::numeric_limits<int>::max())
      throw py::value_error(what + "[" + std::to_string(i) + "] = " + numberText(v[i]) + " does not fit a residue number");
    out[i] = static_cast<int>(v[i]);
  }
  return out;
}

std::shared_ptr<const Molecule> moleculeFromArrays(py::handle centres, py::handle radii, py::handle elements,
                                                   py::handle names, py::handle resids, py::handle chains) {
  auto m = std::make_shared<Molecule>();
  m->source = "surftrace.Molecule";
  m->centers = centresFrom(centres, "centres", std::nullopt);
  const std::size_t n = m->centers.size();
  if (n == 0) throw py::value_error("centres: the molecule has no atoms (shape (0, 3))");
  m->radii = valuesFrom(radii, "radii", n);
  for (std::size_t i = 0; i < n; ++i)
    if (!(m->radii[i] > 0.0))
      throw py::value_error("radii[" + std::to_string(i) + "] is " + numberText(m->radii[i]) +
                            ": every radius must be > 0 (Å)");
  m->atoms.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    m->atoms[i].serial = static_cast<int>(i + 1);
    m->atoms[i].fileIndex = i;
  }
  if (!elements.is_none()) {
    const auto v = stringsFrom(elements, "elements", n);
    for (std::size_t i = 0; i < n; ++i) {
      m->atoms[i].element = v[i];
      m->atoms[i].elementSource = v[i].empty() ? build::ElementSource::None : build::ElementSource::File;
    }
  }
  if (!names.is_none()) {
    const auto v = stringsFrom(names, "names", n);
    for (std::size_t i = 0; i < n; ++i) m->atoms[i].name = v[i];
  }
  if (!resids.is_none()) {
    const auto v = integersFrom(resids, "resids", n);
    for (std::size_t i = 0; i < n; ++i) m->atoms[i].residueNumber = v[i];
  }
  if (!chains.is_none()) {
    const auto v = stringsFrom(chains, "chains", n);
    for (std::size_t i = 0; i < n; ++i) m->atoms[i].chain = v[i];
  }
  m->fileAtomCount = n;
  m->radiiSet = "file";
  // The limits every reader holds a molecule to (coordinates and radii in Å, not in nm or m).
  build::validateMolecule(*m);
  return m;
}

// The atoms `indices` of `m` (ascending), with everything else the molecule says about itself.
std::shared_ptr<const Molecule> subset(const Molecule& m, const std::vector<std::uint32_t>& indices) {
  auto out = std::make_shared<Molecule>();
  out->source = m.source;
  out->format = m.format;
  out->modelCount = m.modelCount;
  out->modelUsed = m.modelUsed;
  out->fileAtomCount = m.fileAtomCount;
  out->radiiSet = m.radiiSet;
  out->radiusSources = m.radiusSources;
  out->elementsFromNames = m.elementsFromNames;
  out->elementsFromMasses = m.elementsFromMasses;
  out->martini = m.martini;
  out->beadRadius = m.beadRadius;
  out->inputCrc32 = m.inputCrc32;
  out->skipped = m.skipped;
  out->bondRecords = m.bondRecords;
  out->notes = m.notes;
  out->centers.reserve(indices.size());
  out->radii.reserve(indices.size());
  out->atoms.reserve(indices.size());
  for (std::uint32_t i : indices) {
    out->centers.push_back(m.centers[i]);
    out->radii.push_back(m.radii[i]);
    out->atoms.push_back(m.atoms[i]);
  }
  return out;
}

MoleculeFormat formatFrom(const std::string& name) {
  static const std::pair<const char*, MoleculeFormat> kFormats[] = {
      {"auto", MoleculeFormat::Auto}, {"pdb", MoleculeFormat::Pdb}, {"mmcif", MoleculeFormat::Mmcif},
      {"cif", MoleculeFormat::Mmcif}, {"pqr", MoleculeFormat::Pqr}, {"xyzr", MoleculeFormat::Xyzr},
      {"xyz", MoleculeFormat::Xyz},   {"gro", MoleculeFormat::Gro}, {"psf", MoleculeFormat::Psf}};
  for (const auto& [text, format] : kFormats)
    if (name == text) return format;
  throw py::value_error("format: '" + name + "' is not one of auto, pdb, mmcif, cif, pqr, xyzr, xyz, gro, psf");
}

double positiveOrThrow(double value, const char* what) {
  if (!(value > 0.0) || !std::isfinite(value))
    throw py::value_error(std::string(what) + ": expected a finite number > 0 (Å), got " + numberText(value));
  return value;
}

PyMolecule readFile(py::handle path, int model, py::handle chains, bool water, bool hydrogens,
                                     py::handle radii, std::optional<double> defaultRadius, const std::string& format,
                                     std::optional<double> beadRadius, bool dropZeroRadius, py::handle trajectory,
                                     std::size_t frame) {
  ReadOptions options;
  options.format = formatFrom(format);
  if (model < 1) throw py::value_error("model: expected 1 or more (models count from 1), got " + std::to_string(model));
  options.model = model;
  options.keepWater = water;
  options.keepHydrogens = hydrogens;
  if (py::isinstance<py::str>(chains)) {
    // "A,B" as on the command line.
    const std::string text = chains.cast<std::string>();
    for (std::size_t start = 0; start <= text.size();) {
      const std::size_t comma = std::min(text.find(',', start), text.size());
      if (comma > start) options.chains.push_back(text.substr(start, comma - start));
      start = comma + 1;
    }
  } else if (!chains.is_none()) {
    options.chains = stringsFrom(chains, "chains", py::len(chains));
  }
  if (!radii.is_none()) {
    // "protor" and "naccess" name FreeSASA's classifiers, as on the command line (--radii).
    const auto preset = py::isinstance<py::str>(radii) ? build::radiusPresetNamed(radii.cast<std::string>())
                                                       : std::nullopt;
    if (preset) options.radiiPreset = preset;
    else options.radiiFile = pathFrom(radii);
  }
  if (defaultRadius) options.defaultRadius = positiveOrThrow(*defaultRadius, "default_radius");
  if (beadRadius) options.beadRadius = positiveOrThrow(*beadRadius, "bead_radius");
  options.dropZeroRadius = dropZeroRadius;
  const std::string file = pathFrom(path);
  if (trajectory.is_none()) {
    if (frame != 0) throw py::value_error("frame: only with a trajectory");
    py::gil_scoped_release unlocked;
    return PyMolecule{std::make_shared<const Molecule>(readStructure(file, options))};
  }
  const std::string frames = pathFrom(trajectory);
  py::gil_scoped_release unlocked;
  return PyMolecule{std::make_shared<const Molecule>(readTrajectoryFrame(file, frames, frame, options))};
}

template <class Field>
py::list strings(const Molecule& m, Field field) {
  py::list out(m.atoms.size());
  for (std::size_t i = 0; i < m.atoms.size(); ++i) out[i] = py::str(m.atoms[i].*field);
  return out;
}

template <class T, class Get>
py::array_t<T> column(const Molecule& m, Get get) {
  py::array_t<T> out(static_cast<py::ssize_t>(m.atoms.size()));
  T* p = out.mutable_data();
  for (std::size_t i = 0; i < m.atoms.size(); ++i) p[i] = get(m.atoms[i]);
  return out;
}

}  // namespace

void bindMolecules(py::module_& m) {
  // Bad input files (and molecules that break a reader's limits): a ValueError naming the file,
  // the line and the value.
  py::register_exception<build::InputError>(m, "InputError", PyExc_ValueError);

  py::class_<PyMolecule>(m, "Molecule", R"(Atoms: centres (Å), radii (Å) and the records they came from.

Molecule(centres, radii, elements=None, names=None, resids=None, chains=None) makes one from
arrays: centres (n, 3) and radii (n,) of any numeric dtype (float32 and integers are widened
to float64 exactly; any strides), finite, radii > 0; elements, names and chains sequences of
str, resids integers, n of each. surftrace.read() reads one from a file.)")
      .def(py::init([](py::handle centres, py::handle radii, py::handle elements, py::handle names,
                       py::handle resids, py::handle chains) {
             return PyMolecule{moleculeFromArrays(centres, radii, elements, names, resids, chains)};
           }),
           py::arg("centres"), py::arg("radii"), py::arg("elements") = py::none(), py::arg("names") = py::none(),
           py::arg("resids") = py::none(), py::arg("chains") = py::none())
      .def("__len__", [](const PyMolecule& self) { return self.molecule->size(); })
      .def("__repr__",
           [](const PyMolecule& self) {
             return "<surftrace.Molecule: " + std::to_string(self.molecule->size()) + " atoms from " +
                    self.molecule->source + ">";
           })
      .def(
          "select",
          [](const PyMolecule& self, const std::string& selection) {
            return PyMolecule{subset(*self.molecule, selectAtoms(*self.molecule, selection))};
          },
          py::arg("selection"),
          R"(The atoms `selection` picks, as a new Molecule, in the selection language of the command line
(MDAnalysis's select_atoms subset: name, resname, resid, chain, element, index, atom, protein,
backbone, water, all; not, and, or, parentheses). ValueError, quoting the selection with a caret
under the word it could not read, or saying what each term matched when nothing is selected.)")
      .def_property_readonly(
          "centres",
          [](const PyMolecule& self) {
            const Molecule& mol = *self.molecule;
            return readOnlyView(self.molecule, mol.centers.empty() ? nullptr : &mol.centers[0].x,
                                {static_cast<py::ssize_t>(mol.size()), 3});
          },
          "(n, 3) float64, Å: a read-only view of the molecule's own memory (no copy)")
      .def_property_readonly(
          "radii",
          [](const PyMolecule& self) {
            return readOnlyView(self.molecule, self.molecule->radii.data(), {static_cast<py::ssize_t>(self.molecule->size())});
          },
          "(n,) float64, Å: a read-only view of the molecule's own memory (no copy)")
      .def_property_readonly("elements", [](const PyMolecule& self) { return strings(*self.molecule, &build::AtomRecord::element); },
                             "Element symbols (list of str; '' where unknown)")
      .def_property_readonly("names", [](const PyMolecule& self) { return strings(*self.molecule, &build::AtomRecord::name); },
                             "Atom names (list of str)")
      .def_property_readonly("resnames", [](const PyMolecule& self) { return strings(*self.molecule, &build::AtomRecord::residue); },
                             "Residue names (list of str)")
      .def_property_readonly("chains", [](const PyMolecule& self) { return strings(*self.molecule, &build::AtomRecord::chain); },
                             "Chain identifiers (a PSF's segment ids; list of str)")
      .def_property_readonly(
          "resids", [](const PyMolecule& self) { return column<std::int64_t>(*self.molecule, [](const auto& a) { return a.residueNumber; }); },
          "Residue numbers (int64 array)")
      .def_property_readonly(
          "serials", [](const PyMolecule& self) { return column<std::int64_t>(*self.molecule, [](const auto& a) { return a.serial; }); },
          "Serial numbers in the file (int64 array)")
      .def_property_readonly(
          "indices",
          [](const PyMolecule& self) {
            return column<std::int64_t>(*self.molecule, [](const auto& a) { return static_cast<std::int64_t>(a.fileIndex); });
          },
          "Each atom's 0-based position among the file's atoms before any choice or selection (int64 "
          "array): MDAnalysis's atom index on the same topology, so u.atoms[mol.indices] are these atoms")
      .def_property_readonly(
          "occupancies", [](const PyMolecule& self) { return column<double>(*self.molecule, [](const auto& a) { return a.occupancy; }); })
      .def_property_readonly(
          "bfactors", [](const PyMolecule& self) { return column<double>(*self.molecule, [](const auto& a) { return a.bFactor; }); })
      .def_property_readonly(
          "charges", [](const PyMolecule& self) { return column<double>(*self.molecule, [](const auto& a) { return a.charge; }); },
          "PQR charges (0 elsewhere)")
      .def_property_readonly("source", [](const PyMolecule& self) { return self.molecule->source; }, "The path read")
      .def_property_readonly("format", [](const PyMolecule& self) { return std::string(build::formatName(self.molecule->format)); })
      .def_property_readonly("notes", [](const PyMolecule& self) { return self.molecule->notes; },
                             "What the reader assumed where the file was odd but readable (list of str)")
      .def_property_readonly("file_atom_count", [](const PyMolecule& self) { return self.molecule->fileAtomCount; },
                             "Atoms of the model read, before any choice or selection")
      .def_property_readonly("radii_set", [](const PyMolecule& self) { return self.molecule->radiiSet; });

  m.def("read", &readFile, py::arg("path"), py::kw_only(), py::arg("model") = 1, py::arg("chains") = py::none(),
        py::arg("water") = false, py::arg("hydrogens") = true, py::arg("radii") = py::none(),
        py::arg("default_radius") = py::none(), py::arg("format") = "auto", py::arg("bead_radius") = py::none(),
        py::arg("drop_zero_radius") = false, py::arg("trajectory") = py::none(), py::arg("frame") = 0,
        R"(Reads a structure file (PDB, mmCIF, PQR, XYZR, XYZ, GRO; .gz too) into a Molecule, with the choices
of the command line's molecule options: model (--model, from 1), chains ("A,B" or a list:
--chains), water (--keep-water), hydrogens (False: --no-hydrogens), radii (a radius table:
--radii), default_radius (--default-radius), format ("auto", "pdb", "mmcif", "pqr", "xyzr",
"xyz", "gro", "psf": --input-format), bead_radius (--bead-radius), drop_zero_radius
(--drop-zero-radius). With trajectory (DCD, XTC, GRO, XYZ, multi-model PDB/mmCIF), `path` is
its topology (PSF too) and the atoms are at frame `frame` (from 0). The GIL is released while
reading. surftrace.InputError (a ValueError) names the file, the line and the value on bad input.)");
}

}  // namespace surftrace::python
