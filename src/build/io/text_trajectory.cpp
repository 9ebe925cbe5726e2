// Trajectories in text files: GRO and XYZ frames one after another and the models of a PDB
// or mmCIF file, gzipped or not, indexed once when opened and read one frame at a time.
#include "build/io/trajectory.hpp"


#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <new>
#include <optional>
#include <string_view>
#include <utility>

#include "build/core/assert.hpp"
#include "build/io/error.hpp"
#include "build/io/file_formats.hpp"
#include "build/io/line_cursor.hpp"
#include "build/io/pdb_records.hpp"
#include "build/io/text_fields.hpp"
#include "build/io/topology_formats.hpp"

namespace surftrace::build {

namespace detail {
// Defined in gemmi_impl.cpp, the one translation unit that compiles gemmi.
std::vector<std::vector<glm::dvec3>> readMmcifModelsWithGemmi(
    const std::string& text, const std::string& path, std::optional<std::array<double, 6>>& cell);
}  // namespace detail

namespace {

using namespace text;

namespace fs = std::filesystem;
using Cell = std::array<double, 6>;
using pdb::isAtomRecord;
using pdb::isEndRecord;
using pdb::recordIs;
using detail::frameName;

// ---------------------------------------------------------------------------------------------
// Frame index

struct Span {
  std::size_t offset = 0;  // first byte of the frame
  std::size_t end = 0;     // one past its last byte (PDB)
  int line = 0;            // 1-based line of its first byte
  std::size_t atoms = 0;
  std::optional<Cell> cell;  // PDB: CRYST1
};

// XYZ: a count line, a comment line, then that many atom lines; blank lines between frames.
std::vector<Span> indexXyz(const std::string& text, const std::string& path, std::string& note) {
  std::vector<Span> spans;
  const auto stop = [&](int line, const std::string& why) {
    detail::endFrameIndex(path, line, why, spans.size(), note);
  };
  LineCursor cursor(text, 0, 1);
  std::string_view line;
  for (;;) {
    bool found = false;
    while ((found = cursor.next(line)) && trim(line).empty()) {
    }
    if (!found) break;
    Span span;
    span.offset = cursor.lineOffset();
    span.line = cursor.number();
    const std::string frame = frameName(spans.size());
    const std::optional<long long> count = parseWhole<long long>(line);
    if (!count || *count < 0) {
      stop(span.line, "expected the atom count of " + frame + ", got " + inQuotes(trim(line)));
      break;
    }
    span.atoms = static_cast<std::size_t>(*count);
    const std::size_t present = cursor.skip(span.atoms + 1);
    if (present < span.atoms + 1) {
      stop(span.line, "the atom count of " + frame + " is " + std::to_string(span.atoms) +
                          ", but the file ends " + std::to_string(present) +
                          " lines later, before its comment line and atoms are complete");
      break;
    }
    span.end = cursor.offset();
    spans.push_back(span);
  }
  if (spans.empty()) throw InputError(path, 0, "no XYZ frame (the file is blank)");
  return spans;
}

// CRYST1 a b c alpha beta gamma in columns 7-54; none for the 1 Å cube that stands for "no
// cell" in NMR entries, or for a record that does not read.
std::optional<Cell> cryst1(std::string_view line) {
  const std::size_t columns[7] = {6, 15, 24, 33, 40, 47, 54};
  Cell cell{};
  for (std::size_t i = 0; i < 6; ++i) {
    if (line.size() <= columns[i]) return std::nullopt;
    const std::optional<double> v = parseWhole<double>(
        line.substr(columns[i], std::min(line.size(), columns[i + 1]) - columns[i]));
    if (!v || !std::isfinite(*v)) return std::nullopt;
    cell[i] = *v;
  }
  if (cell == Cell{1.0, 1.0, 1.0, 90.0, 90.0, 90.0}) return std::nullopt;
  return cell;
}

// PDB: each MODEL record starts a frame and ENDMDL (or the next MODEL) ends it; a file without
// MODEL records is one frame. END ends the file, as for readMolecule. A CRYST1 record before
// the first model gives every frame its cell, one inside a model that model's.
std::vector<Span> indexPdb(const std::string& text, const std::string& path, std::string& note) {
  std::vector<Span> spans;
  Span implicit;  // the whole file, while no MODEL record has been seen
  implicit.line = 1;
  std::optional<Span> open;
  std::optional<Cell> headerCell;
  std::size_t outside = 0;  // atom records outside every model
  bool models = false;
  LineCursor cursor(text, 0, 1);
  std::string_view line;
  std::size_t stopAt = text.size();
  const auto close = [&](std::size_t end) {
    open->end = end;
    spans.push_back(*open);
    open.reset();
  };
  while (cursor.next(line)) {
    if (recordIs(line, "MODEL")) {
      if (!models) outside = implicit.atoms;
      models = true;
      if (open) close(cursor.lineOffset());
      open = Span{cursor.lineOffset(), 0, cursor.number(), 0, headerCell};
    } else if (recordIs(line, "ENDMDL")) {
      if (open) close(cursor.offset());
    } else if (isEndRecord(line)) {
      stopAt = cursor.lineOffset();
      break;
    } else if (isAtomRecord(line)) {
      if (open)
        ++open->atoms;
      else if (!models)
        ++implicit.atoms;
      else
        ++outside;
    } else if (recordIs(line, "CRYST1")) {
      if (open)
        open->cell = cryst1(line);
      else
        headerCell = cryst1(line);
    }
  }
  if (open) close(stopAt);
  if (!models) {
    implicit.end = stopAt;
    implicit.cell = headerCell;
    spans.push_back(implicit);
  } else if (outside > 0) {
    note = path + ": " + std::to_string(outside) +
           " ATOM/HETATM records lie outside every MODEL ... ENDMDL block and belong to no frame";
  }
  if (spans.front().atoms == 0)
    throw InputError(
        path, spans.front().line,
        models ? "the first MODEL has no ATOM or HETATM records" : "no ATOM or HETATM records");
  return spans;
}

TrajectoryFormat formatOf(const fs::path& path, const std::string& name) {
  const std::string ext = formatExtension(path);
  const std::optional<TrajectoryFormat> format = formatsOfExtension(ext).trajectory;
  if (format && *format != TrajectoryFormat::Dcd && *format != TrajectoryFormat::Xtc) return *format;
  throw InputError(name, 0,
                   "cannot tell the text trajectory format from the extension " +
                       inQuotes(ext.empty() ? "" : "." + ext) +
                       "; expected .gro, .xyz, .pdb, .ent, .cif or .mmcif, optionally with .gz");
}

// ---------------------------------------------------------------------------------------------
// The reader

class TextFrames final : public FrameSource {
 public:
  TextFrames(const fs::path& file, TrajectoryFormat format)
      : FrameSource(file.string()), format_(format) {
    text_ = text::readTextFile(file, path());
    std::string note;
    switch (format_) {
      case TrajectoryFormat::Gro:
        for (const detail::GroFrameSpan& g : detail::indexGroFrames(text_, path(), note))
          spans_.push_back(Span{g.offset, 0, g.line, g.atoms, std::nullopt});
        break;
      case TrajectoryFormat::Xyz:
        spans_ = indexXyz(text_, path(), note);
        break;
      case TrajectoryFormat::Pdb:
        spans_ = indexPdb(text_, path(), note);
        break;
      case TrajectoryFormat::Mmcif:
        // gemmi parses the whole document anyway, so every model is kept (3 doubles an atom).
        models_ = detail::readMmcifModelsWithGemmi(text_, path(), cifCell_);
        text_ = std::string();
        for (const auto& model : models_) spans_.push_back(Span{0, 0, 0, model.size(), cifCell_});
        break;
      default:
        throw InputError(path(), 0, "DCD and XTC are binary formats, not text trajectories");
    }
    if (!note.empty()) notes_.push_back(note);
    atoms_ = spans_.front().atoms;
    std::size_t differing = 0;
    for (std::size_t k = 1; k < spans_.size(); ++k) {
      if (spans_[k].atoms == atoms_) continue;
      if (differing++ == 0)
        notes_.push_back(path() + ": " + frameName(k) + " has " + std::to_string(spans_[k].atoms) +
                         " atoms, frame 0 has " + std::to_string(atoms_) +
                         "; frames of another atom count cannot be read");
    }
  }

  std::size_t atomCount() const override { return atoms_; }
  std::size_t frameCount() const override { return spans_.size(); }

  void read(std::size_t index, Frame& frame) override {
    if (index >= spans_.size())
      throw InputError(path(), 0,
                       frameName(index) + " was asked for, but the file has " +
                           std::to_string(spans_.size()) +
                           (spans_.size() == 1 ? " frame" : " frames"));
    const Span& span = spans_[index];
    if (span.atoms != atoms_)
      throw InputError(path(), span.line,
                       frameName(index) + " has " + std::to_string(span.atoms) +
                           " atoms, but frame 0 has " + std::to_string(atoms_) +
                           "; every frame must hold the same atoms");
    frame.time = static_cast<double>(index);
    frame.step = static_cast<long long>(index);
    frame.cell = span.cell;
    switch (format_) {
      case TrajectoryFormat::Gro:
        detail::readGroFrame(text_, path(),
                             detail::GroFrameSpan{span.offset, span.line, span.atoms}, index, frame,
                             nullptr);
        break;
      case TrajectoryFormat::Xyz:
        readXyz(span, index, frame);
        break;
      case TrajectoryFormat::Pdb:
        readPdb(span, index, frame);
        break;
      case TrajectoryFormat::Mmcif:
        frame.positions = models_[index];
        break;
      default:
        SURFTRACE_ASSERT(false);
    }
  }

 private:
  void readXyz(const Span& span, std::size_t index, Frame& frame) const {
    LineCursor cursor(text_, span.offset, span.line);
    cursor.skip(2);  // the count and the comment
    frame.positions.resize(span.atoms);
    std::string_view line;
    for (std::size_t i = 0; i < span.atoms; ++i) {
      if (!cursor.next(line))
        throw InputError(path(), cursor.number(),
                         "the file ends inside " + frameName(index));  // the index says not
      const std::vector<std::string_view> f = splitFields(line);
      if (f.size() < 4)
        throw InputError(path(), cursor.number(),
                         "expected 'element x y z' for atom " + std::to_string(i + 1) + " of " +
                             std::to_string(span.atoms) + " of " + frameName(index) + ", got " +
                             inQuotes(trim(line)) + " (is the frame cut short?)");
      for (std::size_t k = 0; k < 3; ++k)
        frame.positions[i][static_cast<int>(k)] = coordinate(
            f[k + 1], "xyz"[k], index, cursor.number(), "field " + std::to_string(k + 2));
    }
  }

  void readPdb(const Span& span, std::size_t index, Frame& frame) const {
    frame.positions.resize(span.atoms);
    LineCursor cursor(text_, span.offset, span.line);
    std::string_view line;
    std::size_t i = 0;
    while (cursor.offset() < span.end && cursor.next(line)) {
      if (!isAtomRecord(line)) continue;
      if (line.size() < 54)
        throw InputError(path(), cursor.number(),
                         "the ATOM/HETATM record of " + frameName(index) + " ends at column " +
                             std::to_string(line.size()) + "; expected x, y, z in columns 31-54");
      SURFTRACE_ASSERT(i < span.atoms);
      for (std::size_t k = 0; k < 3; ++k) {
        const std::size_t first = 30 + 8 * k;
        frame.positions[i][static_cast<int>(k)] =
            coordinate(line.substr(first, 8), "xyz"[k], index, cursor.number(),
                       "columns " + std::to_string(first + 1) + "-" + std::to_string(first + 8));
      }
      ++i;
    }
    SURFTRACE_ASSERT(i == span.atoms);
  }

  double coordinate(std::string_view field, char axis, std::size_t index, int line,
                    const std::string& where) const {
    const std::optional<double> v = parseWhole<double>(field);
    if (!v)
      throw InputError(path(), line,
                       std::string("expected a number for ") + axis + " (" + where + ") in " +
                           frameName(index) + ", got " + inQuotes(field));
    if (!std::isfinite(*v))
      throw InputError(path(), line,
                       std::string(1, axis) + " (" + where + ") in " + frameName(index) +
                           " is not finite: " + inQuotes(trim(field)));
    return *v;
  }

  TrajectoryFormat format_;
  std::string text_;  // decompressed; empty for mmCIF, whose models are kept instead
  std::vector<Span> spans_;
  std::vector<std::vector<glm::dvec3>> models_;
  std::optional<Cell> cifCell_;
  std::size_t atoms_ = 0;
};

}  // namespace

std::unique_ptr<FrameSource> openTextTrajectory(const std::filesystem::path& path,
                                                TrajectoryFormat format) {
  if (format == TrajectoryFormat::Auto) format = formatOf(path, path.string());
  return std::make_unique<TextFrames>(path, format);
}

}  // namespace surftrace::build
