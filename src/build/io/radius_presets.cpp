// FreeSASA's classifiers as radius presets (radius_presets.hpp). The tables are FreeSASA 2.1.2's
// share/protor.config and share/naccess.config (FreeSASA, Simon Mitternacht, MIT licence),
// generated from those files, sorted by residue and atom for a binary search; the element guess
// is src/classifier.c's symbol_radius table.
#include "build/io/radius_presets.hpp"

#include <algorithm>
#include <cctype>
#include <string>
#include <utility>

namespace surftrace::build {
namespace {

struct ClassifiedAtom {
  std::string_view residue, atom;
  double radius;
};

constexpr bool before(const ClassifiedAtom& a, const ClassifiedAtom& b) {
  return a.residue != b.residue ? a.residue < b.residue : a.atom < b.atom;
}

// clang-format off
namespace protor {
constexpr double kC3H0 = 1.61;
constexpr double kC3H1 = 1.76;
constexpr double kC4H1 = 1.88;
constexpr double kC4H2 = 1.88;
constexpr double kC4H3 = 1.88;
constexpr double kN2H0 = 1.64;
constexpr double kN2H2 = 1.64;
constexpr double kN3H0 = 1.64;
constexpr double kN3H1 = 1.64;
constexpr double kN3H2 = 1.64;
constexpr double kN4H3 = 1.64;
constexpr double kO1H0 = 1.42;
constexpr double kO2H0 = 1.46;
constexpr double kO2H1 = 1.46;
constexpr double kO2H2 = 1.46;
constexpr double kP4H0 = 1.80;
constexpr double kS2H0 = 1.77;
constexpr double kS2H1 = 1.77;
constexpr double kSE2H0 = 1.90;
constexpr double kSE2H1 = 1.90;
constexpr double kX1H0 = 1.50;
constexpr ClassifiedAtom kAtoms[] = {
    {"A", "C1'", kC4H1}, {"A", "C2", kC3H1}, {"A", "C2'", kC4H1}, {"A", "C3'", kC4H1},
    {"A", "C4", kC3H0}, {"A", "C4'", kC4H1}, {"A", "C5", kC3H0}, {"A", "C5'", kC4H2},
    {"A", "C6", kC3H0}, {"A", "C8", kC3H1}, {"A", "N1", kN2H0}, {"A", "N3", kN2H0},
    {"A", "N6", kN3H2}, {"A", "N7", kN2H0}, {"A", "N9", kN3H0}, {"A", "O2'", kO2H1},
    {"A", "O3'", kO2H1}, {"A", "O4'", kO2H0}, {"A", "O5'", kO2H0}, {"A", "OP1", kO1H0},
    {"A", "OP2", kO2H1}, {"A", "OP3", kO2H1}, {"A", "P", kP4H0}, {"ACE", "C", kC3H1},
    {"ACE", "CH3", kC4H3}, {"ACE", "O", kO1H0}, {"ALA", "C", kC3H0}, {"ALA", "CA", kC4H1},
    {"ALA", "CB", kC4H3}, {"ALA", "N", kN3H2}, {"ALA", "O", kO1H0}, {"ALA", "OXT", kO2H1},
    {"ARG", "C", kC3H0}, {"ARG", "CA", kC4H1}, {"ARG", "CB", kC4H2}, {"ARG", "CD", kC4H2},
    {"ARG", "CG", kC4H2}, {"ARG", "CZ", kC3H0}, {"ARG", "N", kN3H2}, {"ARG", "NE", kN3H1},
    {"ARG", "NH1", kN3H2}, {"ARG", "NH2", kN3H2}, {"ARG", "O", kO1H0}, {"ARG", "OXT", kO2H1},
    {"ASN", "C", kC3H0}, {"ASN", "CA", kC4H1}, {"ASN", "CB", kC4H2}, {"ASN", "CG", kC3H0},
    {"ASN", "N", kN3H2}, {"ASN", "ND2", kN3H2}, {"ASN", "O", kO1H0}, {"ASN", "OD1", kO1H0},
    {"ASN", "OXT", kO2H1}, {"ASP", "C", kC3H0}, {"ASP", "CA", kC4H1}, {"ASP", "CB", kC4H2},
    {"ASP", "CG", kC3H0}, {"ASP", "N", kN3H2}, {"ASP", "O", kO1H0}, {"ASP", "OD1", kO1H0},
    {"ASP", "OD2", kO2H1}, {"ASP", "OXT", kO2H1}, {"ASX", "C", kC3H0}, {"ASX", "CA", kC4H1},
    {"ASX", "CB", kC4H2}, {"ASX", "CG", kC3H0}, {"ASX", "N", kN3H2}, {"ASX", "O", kO1H0},
    {"ASX", "OXT", kO2H1}, {"ASX", "XD1", kX1H0}, {"ASX", "XD2", kX1H0}, {"C", "C1'", kC4H1},
    {"C", "C2", kC3H0}, {"C", "C2'", kC4H1}, {"C", "C3'", kC4H1}, {"C", "C4", kC3H0},
    {"C", "C4'", kC4H1}, {"C", "C5", kC3H1}, {"C", "C5'", kC4H2}, {"C", "C6", kC3H1},
    {"C", "N1", kN3H0}, {"C", "N3", kN2H0}, {"C", "N4", kN3H2}, {"C", "O2", kO1H0},
    {"C", "O2'", kO2H1}, {"C", "O3'", kO2H1}, {"C", "O4'", kO2H0}, {"C", "O5'", kO2H0},
    {"C", "OP1", kO1H0}, {"C", "OP2", kO2H1}, {"C", "OP3", kO2H1}, {"C", "P", kP4H0},
    {"CYS", "C", kC3H0}, {"CYS", "CA", kC4H1}, {"CYS", "CB", kC4H2}, {"CYS", "N", kN3H2},
    {"CYS", "O", kO1H0}, {"CYS", "OXT", kO2H1}, {"CYS", "SG", kS2H1}, {"DA", "C1'", kC4H1},
    {"DA", "C2", kC3H1}, {"DA", "C2'", kC4H2}, {"DA", "C3'", kC4H1}, {"DA", "C4", kC3H0},
    {"DA", "C4'", kC4H1}, {"DA", "C5", kC3H0}, {"DA", "C5'", kC4H2}, {"DA", "C6", kC3H0},
    {"DA", "C8", kC3H1}, {"DA", "N1", kN2H0}, {"DA", "N3", kN2H0}, {"DA", "N6", kN3H2},
    {"DA", "N7", kN2H0}, {"DA", "N9", kN3H0}, {"DA", "O3'", kO2H1}, {"DA", "O4'", kO2H0},
    {"DA", "O5'", kO2H0}, {"DA", "OP1", kO1H0}, {"DA", "OP2", kO2H1}, {"DA", "OP3", kO2H1},
    {"DA", "P", kP4H0}, {"DC", "C1'", kC4H1}, {"DC", "C2", kC3H0}, {"DC", "C2'", kC4H2},
    {"DC", "C3'", kC4H1}, {"DC", "C4", kC3H0}, {"DC", "C4'", kC4H1}, {"DC", "C5", kC3H1},
    {"DC", "C5'", kC4H2}, {"DC", "C6", kC3H1}, {"DC", "N1", kN3H0}, {"DC", "N3", kN2H0},
    {"DC", "N4", kN3H2}, {"DC", "O2", kO1H0}, {"DC", "O3'", kO2H1}, {"DC", "O4'", kO2H0},
    {"DC", "O5'", kO2H0}, {"DC", "OP1", kO1H0}, {"DC", "OP2", kO2H1}, {"DC", "OP3", kO2H1},
    {"DC", "P", kP4H0}, {"DG", "C1'", kC4H1}, {"DG", "C2", kC3H0}, {"DG", "C2'", kC4H2},
    {"DG", "C3'", kC4H1}, {"DG", "C4", kC3H0}, {"DG", "C4'", kC4H1}, {"DG", "C5", kC3H0},
    {"DG", "C5'", kC4H2}, {"DG", "C6", kC3H0}, {"DG", "C8", kC3H1}, {"DG", "N1", kN3H1},
    {"DG", "N2", kN3H2}, {"DG", "N3", kN2H0}, {"DG", "N7", kN2H0}, {"DG", "N9", kN3H0},
    {"DG", "O3'", kO2H1}, {"DG", "O4'", kO2H0}, {"DG", "O5'", kO2H0}, {"DG", "O6", kO1H0},
    {"DG", "OP1", kO1H0}, {"DG", "OP2", kO2H1}, {"DG", "OP3", kO2H1}, {"DG", "P", kP4H0},
    {"DI", "C1'", kC4H1}, {"DI", "C2", kC3H1}, {"DI", "C2'", kC4H2}, {"DI", "C3'", kC4H1},
    {"DI", "C4", kC3H0}, {"DI", "C4'", kC4H1}, {"DI", "C5", kC3H0}, {"DI", "C5'", kC4H2},
    {"DI", "C6", kC3H0}, {"DI", "C8", kC3H1}, {"DI", "N1", kN3H1}, {"DI", "N3", kN2H0},
    {"DI", "N7", kN2H0}, {"DI", "N9", kN3H0}, {"DI", "O3'", kO2H1}, {"DI", "O4'", kO2H0},
    {"DI", "O5'", kO2H0}, {"DI", "O6", kO1H0}, {"DI", "OP1", kO1H0}, {"DI", "OP2", kO2H1},
    {"DI", "OP3", kO2H1}, {"DI", "P", kP4H0}, {"DT", "C1'", kC4H1}, {"DT", "C2", kC3H0},
    {"DT", "C2'", kC4H2}, {"DT", "C3'", kC4H1}, {"DT", "C4", kC3H0}, {"DT", "C4'", kC4H1},
    {"DT", "C5", kC3H0}, {"DT", "C5'", kC4H2}, {"DT", "C6", kC3H1}, {"DT", "C7", kC4H3},
    {"DT", "N1", kN3H0}, {"DT", "N3", kN3H1}, {"DT", "O2", kO1H0}, {"DT", "O3'", kO2H1},
    {"DT", "O4", kO1H0}, {"DT", "O4'", kO2H0}, {"DT", "O5'", kO2H0}, {"DT", "OP1", kO1H0},
    {"DT", "OP2", kO2H1}, {"DT", "OP3", kO2H1}, {"DT", "P", kP4H0}, {"DU", "C1'", kC4H1},
    {"DU", "C2", kC3H0}, {"DU", "C2'", kC4H2}, {"DU", "C3'", kC4H1}, {"DU", "C4", kC3H0},
    {"DU", "C4'", kC4H1}, {"DU", "C5", kC3H1}, {"DU", "C5'", kC4H2}, {"DU", "C6", kC3H1},
    {"DU", "N1", kN3H0}, {"DU", "N3", kN3H1}, {"DU", "O2", kO1H0}, {"DU", "O3'", kO2H1},
    {"DU", "O4", kO1H0}, {"DU", "O4'", kO2H0}, {"DU", "O5'", kO2H0}, {"DU", "OP1", kO1H0},
    {"DU", "OP2", kO2H1}, {"DU", "OP3", kO2H1}, {"DU", "P", kP4H0}, {"G", "C1'", kC4H1},
    {"G", "C2", kC3H0}, {"G", "C2'", kC4H1}, {"G", "C3'", kC4H1}, {"G", "C4", kC3H0},
    {"G", "C4'", kC4H1}, {"G", "C5", kC3H0}, {"G", "C5'", kC4H2}, {"G", "C6", kC3H0},
    {"G", "C8", kC3H1}, {"G", "N1", kN3H1}, {"G", "N2", kN3H2}, {"G", "N3", kN2H0},
    {"G", "N7", kN2H0}, {"G", "N9", kN3H0}, {"G", "O2'", kO2H1}, {"G", "O3'", kO2H1},
    {"G", "O4'", kO2H0}, {"G", "O5'", kO2H0}, {"G", "O6", kO1H0}, {"G", "OP1", kO1H0},
    {"G", "OP2", kO2H1}, {"G", "OP3", kO2H1}, {"G", "P", kP4H0}, {"GLN", "C", kC3H0},
    {"GLN", "CA", kC4H1}, {"GLN", "CB", kC4H2}, {"GLN", "CD", kC3H0}, {"GLN", "CG", kC4H2},
    {"GLN", "N", kN3H2}, {"GLN", "NE2", kN3H2}, {"GLN", "O", kO1H0}, {"GLN", "OE1", kO1H0},
    {"GLN", "OXT", kO2H1}, {"GLU", "C", kC3H0}, {"GLU", "CA", kC4H1}, {"GLU", "CB", kC4H2},
    {"GLU", "CD", kC3H0}, {"GLU", "CG", kC4H2}, {"GLU", "N", kN3H2}, {"GLU", "O", kO1H0},
    {"GLU", "OE1", kO1H0}, {"GLU", "OE2", kO2H1}, {"GLU", "OXT", kO2H1}, {"GLX", "C", kC3H0},
    {"GLX", "CA", kC4H1}, {"GLX", "CB", kC4H2}, {"GLX", "CD", kC3H0}, {"GLX", "CG", kC4H2},
    {"GLX", "N", kN3H2}, {"GLX", "O", kO1H0}, {"GLX", "OXT", kO2H1}, {"GLX", "XE1", kX1H0},
    {"GLX", "XE2", kX1H0}, {"GLY", "C", kC3H0}, {"GLY", "CA", kC4H2}, {"GLY", "N", kN3H2},
    {"GLY", "O", kO1H0}, {"GLY", "OXT", kO2H1}, {"HIS", "C", kC3H0}, {"HIS", "CA", kC4H1},
    {"HIS", "CB", kC4H2}, {"HIS", "CD2", kC3H1}, {"HIS", "CE1", kC3H1}, {"HIS", "CG", kC3H0},
    {"HIS", "N", kN3H2}, {"HIS", "ND1", kN3H1}, {"HIS", "NE2", kN3H1}, {"HIS", "O", kO1H0},
    {"HIS", "OXT", kO2H1}, {"HOH", "O", kO2H2}, {"I", "C1'", kC4H1}, {"I", "C2", kC3H1},
    {"I", "C2'", kC4H1}, {"I", "C3'", kC4H1}, {"I", "C4", kC3H0}, {"I", "C4'", kC4H1},
    {"I", "C5", kC3H0}, {"I", "C5'", kC4H2}, {"I", "C6", kC3H0}, {"I", "C8", kC3H1},
    {"I", "N1", kN3H1}, {"I", "N3", kN2H0}, {"I", "N7", kN2H0}, {"I", "N9", kN3H0},
    {"I", "O2'", kO2H1}, {"I", "O3'", kO2H1}, {"I", "O4'", kO2H0}, {"I", "O5'", kO2H0},
    {"I", "O6", kO1H0}, {"I", "OP1", kO1H0}, {"I", "OP2", kO2H1}, {"I", "OP3", kO2H1},
    {"I", "P", kP4H0}, {"ILE", "C", kC3H0}, {"ILE", "CA", kC4H1}, {"ILE", "CB", kC4H1},
    {"ILE", "CD1", kC4H3}, {"ILE", "CG1", kC4H2}, {"ILE", "CG2", kC4H3}, {"ILE", "N", kN3H2},
    {"ILE", "O", kO1H0}, {"ILE", "OXT", kO2H1}, {"LEU", "C", kC3H0}, {"LEU", "CA", kC4H1},
    {"LEU", "CB", kC4H2}, {"LEU", "CD1", kC4H3}, {"LEU", "CD2", kC4H3}, {"LEU", "CG", kC4H1},
    {"LEU", "N", kN3H2}, {"LEU", "O", kO1H0}, {"LEU", "OXT", kO2H1}, {"LYS", "C", kC3H0},
    {"LYS", "CA", kC4H1}, {"LYS", "CB", kC4H2}, {"LYS", "CD", kC4H2}, {"LYS", "CE", kC4H2},
    {"LYS", "CG", kC4H2}, {"LYS", "N", kN3H2}, {"LYS", "NZ", kN4H3}, {"LYS", "O", kO1H0},
    {"LYS", "OXT", kO2H1}, {"MET", "C", kC3H0}, {"MET", "CA", kC4H1}, {"MET", "CB", kC4H2},
    {"MET", "CE", kC4H3}, {"MET", "CG", kC4H2}, {"MET", "N", kN3H2}, {"MET", "O", kO1H0},
    {"MET", "OXT", kO2H1}, {"MET", "SD", kS2H0}, {"MSE", "C", kC3H0}, {"MSE", "CA", kC4H1},
    {"MSE", "CB", kC4H2}, {"MSE", "CE", kC4H3}, {"MSE", "CG", kC4H2}, {"MSE", "N", kN3H2},
    {"MSE", "O", kO1H0}, {"MSE", "OXT", kO2H1}, {"MSE", "SE", kSE2H0}, {"NH2", "N", kN2H2},
    {"PHE", "C", kC3H0}, {"PHE", "CA", kC4H1}, {"PHE", "CB", kC4H2}, {"PHE", "CD1", kC3H1},
    {"PHE", "CD2", kC3H1}, {"PHE", "CE1", kC3H1}, {"PHE", "CE2", kC3H1}, {"PHE", "CG", kC3H0},
    {"PHE", "CZ", kC3H1}, {"PHE", "N", kN3H2}, {"PHE", "O", kO1H0}, {"PHE", "OXT", kO2H1},
    {"PRO", "C", kC3H0}, {"PRO", "CA", kC4H1}, {"PRO", "CB", kC4H2}, {"PRO", "CD", kC4H2},
    {"PRO", "CG", kC4H2}, {"PRO", "N", kN3H1}, {"PRO", "O", kO1H0}, {"PRO", "OXT", kO2H1},
    {"PYL", "C", kC3H0}, {"PYL", "C2", kC3H0}, {"PYL", "CA", kC4H1}, {"PYL", "CA2", kC4H1},
    {"PYL", "CB", kC4H2}, {"PYL", "CB2", kC4H3}, {"PYL", "CD", kC4H2}, {"PYL", "CD2", kC4H2},
    {"PYL", "CE", kC4H2}, {"PYL", "CE2", kC3H1}, {"PYL", "CG", kC4H2}, {"PYL", "CG2", kC4H1},
    {"PYL", "N", kN3H2}, {"PYL", "N2", kN2H0}, {"PYL", "NZ", kN3H1}, {"PYL", "O", kO1H0},
    {"PYL", "O2", kO1H0}, {"PYL", "OXT", kO2H1}, {"SEC", "C", kC3H0}, {"SEC", "CA", kC4H1},
    {"SEC", "CB", kC4H2}, {"SEC", "N", kN3H2}, {"SEC", "O", kO1H0}, {"SEC", "OXT", kO2H1},
    {"SEC", "SE", kSE2H1}, {"SER", "C", kC3H0}, {"SER", "CA", kC4H1}, {"SER", "CB", kC4H2},
    {"SER", "N", kN3H2}, {"SER", "O", kO1H0}, {"SER", "OG", kO2H1}, {"SER", "OXT", kO2H1},
    {"T", "C1'", kC4H1}, {"T", "C2", kC3H0}, {"T", "C2'", kC4H2}, {"T", "C3'", kC4H1},
    {"T", "C4", kC3H0}, {"T", "C4'", kC4H1}, {"T", "C5", kC3H0}, {"T", "C5'", kC4H2},
    {"T", "C6", kC3H1}, {"T", "C7", kC4H3}, {"T", "N1", kN3H0}, {"T", "N3", kN3H1},
    {"T", "O2", kO1H0}, {"T", "O3'", kO2H1}, {"T", "O4", kO1H0}, {"T", "O4'", kO2H0},
    {"T", "O5'", kO2H0}, {"T", "OP1", kO1H0}, {"T", "OP2", kO2H1}, {"T", "OP3", kO2H1},
    {"T", "P", kP4H0}, {"THR", "C", kC3H0}, {"THR", "CA", kC4H1}, {"THR", "CB", kC4H1},
    {"THR", "CG2", kC4H3}, {"THR", "N", kN3H2}, {"THR", "O", kO1H0}, {"THR", "OG1", kO2H1},
    {"THR", "OXT", kO2H1}, {"TRP", "C", kC3H0}, {"TRP", "CA", kC4H1}, {"TRP", "CB", kC4H2},
    {"TRP", "CD1", kC3H1}, {"TRP", "CD2", kC3H0}, {"TRP", "CE2", kC3H0}, {"TRP", "CE3", kC3H1},
    {"TRP", "CG", kC3H0}, {"TRP", "CH2", kC3H1}, {"TRP", "CZ2", kC3H1}, {"TRP", "CZ3", kC3H1},
    {"TRP", "N", kN3H2}, {"TRP", "NE1", kN3H1}, {"TRP", "O", kO1H0}, {"TRP", "OXT", kO2H1},
    {"TYR", "C", kC3H0}, {"TYR", "CA", kC4H1}, {"TYR", "CB", kC4H2}, {"TYR", "CD1", kC3H1},
    {"TYR", "CD2", kC3H1}, {"TYR", "CE1", kC3H1}, {"TYR", "CE2", kC3H1}, {"TYR", "CG", kC3H0},
    {"TYR", "CZ", kC3H0}, {"TYR", "N", kN3H2}, {"TYR", "O", kO1H0}, {"TYR", "OH", kO2H1},
    {"TYR", "OXT", kO2H1}, {"U", "C1'", kC4H1}, {"U", "C2", kC3H0}, {"U", "C2'", kC4H1},
    {"U", "C3'", kC4H1}, {"U", "C4", kC3H0}, {"U", "C4'", kC4H1}, {"U", "C5", kC3H1},
    {"U", "C5'", kC4H2}, {"U", "C6", kC3H1}, {"U", "N1", kN3H0}, {"U", "N3", kN3H1},
    {"U", "O2", kO1H0}, {"U", "O2'", kO2H1}, {"U", "O3'", kO2H1}, {"U", "O4", kO1H0},
    {"U", "O4'", kO2H0}, {"U", "O5'", kO2H0}, {"U", "OP1", kO1H0}, {"U", "OP2", kO2H1},
    {"U", "OP3", kO2H1}, {"U", "P", kP4H0}, {"VAL", "C", kC3H0}, {"VAL", "CA", kC4H1},
    {"VAL", "CB", kC4H1}, {"VAL", "CG1", kC4H3}, {"VAL", "CG2", kC4H3}, {"VAL", "N", kN3H2},
    {"VAL", "O", kO1H0}, {"VAL", "OXT", kO2H1},
};
}  // namespace protor
namespace naccess {
constexpr double kCALI = 1.87;
constexpr double kCCAR = 1.76;
constexpr double kCNUC = 1.80;
constexpr double kNAMD = 1.65;
constexpr double kNAMN = 1.50;
constexpr double kNNUC = 1.60;
constexpr double kO = 1.40;
constexpr double kP = 1.90;
constexpr double kS = 1.85;
constexpr double kSE = 1.80;
constexpr ClassifiedAtom kAtoms[] = {
    {"A", "C2", kCNUC}, {"A", "C4", kCNUC}, {"A", "C5", kCNUC}, {"A", "C6", kCNUC},
    {"A", "C8", kCNUC}, {"A", "N1", kNNUC}, {"A", "N3", kNNUC}, {"A", "N6", kNNUC},
    {"A", "N7", kNNUC}, {"A", "N9", kNNUC}, {"ALA", "CB", kCALI}, {"ANY", "C", kCCAR},
    {"ANY", "C1'", kCNUC}, {"ANY", "C2'", kCNUC}, {"ANY", "C3'", kCNUC}, {"ANY", "C4'", kCNUC},
    {"ANY", "C5'", kCNUC}, {"ANY", "CA", kCALI}, {"ANY", "CB", kCALI}, {"ANY", "N", kNAMD},
    {"ANY", "O", kO}, {"ANY", "O2'", kO}, {"ANY", "O3'", kO}, {"ANY", "O4'", kO},
    {"ANY", "O5'", kO}, {"ANY", "OP1", kO}, {"ANY", "OP2", kO}, {"ANY", "OP3", kO},
    {"ANY", "OXT", kO}, {"ANY", "P", kP}, {"ARG", "CD", kCALI}, {"ARG", "CG", kCALI},
    {"ARG", "CZ", kCCAR}, {"ARG", "NE", kNAMD}, {"ARG", "NH1", kNAMD}, {"ARG", "NH2", kNAMD},
    {"ASN", "CG", kCCAR}, {"ASN", "ND2", kNAMD}, {"ASN", "OD1", kO}, {"ASP", "CG", kCCAR},
    {"ASP", "OD1", kO}, {"ASP", "OD2", kO}, {"C", "C2", kCNUC}, {"C", "C4", kCNUC},
    {"C", "C5", kCNUC}, {"C", "C6", kCNUC}, {"C", "N1", kNNUC}, {"C", "N3", kNNUC},
    {"C", "N4", kNNUC}, {"C", "O2", kO}, {"CYS", "SG", kS}, {"DA", "C2", kCNUC},
    {"DA", "C4", kCNUC}, {"DA", "C5", kCNUC}, {"DA", "C6", kCNUC}, {"DA", "C8", kCNUC},
    {"DA", "N1", kNNUC}, {"DA", "N3", kNNUC}, {"DA", "N6", kNNUC}, {"DA", "N7", kNNUC},
    {"DA", "N9", kNNUC}, {"DC", "C2", kCNUC}, {"DC", "C4", kCNUC}, {"DC", "C5", kCNUC},
    {"DC", "C6", kCNUC}, {"DC", "N1", kNNUC}, {"DC", "N3", kNNUC}, {"DC", "N4", kNNUC},
    {"DC", "O2", kO}, {"DG", "C2", kCNUC}, {"DG", "C4", kCNUC}, {"DG", "C5", kCNUC},
    {"DG", "C6", kCNUC}, {"DG", "C8", kCNUC}, {"DG", "N1", kNNUC}, {"DG", "N2", kNNUC},
    {"DG", "N3", kNNUC}, {"DG", "N7", kNNUC}, {"DG", "N9", kNNUC}, {"DG", "O6", kO},
    {"DI", "C2", kCNUC}, {"DI", "C4", kCNUC}, {"DI", "C5", kCNUC}, {"DI", "C6", kCNUC},
    {"DI", "C8", kCNUC}, {"DI", "N1", kNNUC}, {"DI", "N3", kNNUC}, {"DI", "N7", kNNUC},
    {"DI", "N9", kNNUC}, {"DI", "O6", kO}, {"DT", "C2", kCNUC}, {"DT", "C4", kCNUC},
    {"DT", "C5", kCNUC}, {"DT", "C6", kCNUC}, {"DT", "C7", kCNUC}, {"DT", "N1", kNNUC},
    {"DT", "N3", kNNUC}, {"DT", "O2", kO}, {"DT", "O4", kO}, {"DU", "C2", kCNUC},
    {"DU", "C4", kCNUC}, {"DU", "C5", kCNUC}, {"DU", "C6", kCNUC}, {"DU", "N1", kNNUC},
    {"DU", "N3", kNNUC}, {"DU", "O2", kO}, {"DU", "O4", kO}, {"G", "C2", kCNUC}, {"G", "C4", kCNUC},
    {"G", "C5", kCNUC}, {"G", "C6", kCNUC}, {"G", "C8", kCNUC}, {"G", "N1", kNNUC},
    {"G", "N2", kNNUC}, {"G", "N3", kNNUC}, {"G", "N7", kNNUC}, {"G", "N9", kNNUC}, {"G", "O6", kO},
    {"GLN", "CD", kCCAR}, {"GLN", "CG", kCALI}, {"GLN", "NE2", kNAMD}, {"GLN", "OE1", kO},
    {"GLU", "CD", kCCAR}, {"GLU", "CG", kCALI}, {"GLU", "OE1", kO}, {"GLU", "OE2", kO},
    {"GLY", "CA", kCALI}, {"HIS", "CD2", kCCAR}, {"HIS", "CE1", kCCAR}, {"HIS", "CG", kCCAR},
    {"HIS", "ND1", kNAMD}, {"HIS", "NE2", kNAMD}, {"I", "C2", kCNUC}, {"I", "C4", kCNUC},
    {"I", "C5", kCNUC}, {"I", "C6", kCNUC}, {"I", "C8", kCNUC}, {"I", "N1", kNNUC},
    {"I", "N3", kNNUC}, {"I", "N7", kNNUC}, {"I", "N9", kNNUC}, {"I", "O6", kO},
    {"ILE", "CD1", kCALI}, {"ILE", "CG1", kCALI}, {"ILE", "CG2", kCALI}, {"LEU", "CD1", kCALI},
    {"LEU", "CD2", kCALI}, {"LEU", "CG", kCALI}, {"LYS", "CD", kCALI}, {"LYS", "CE", kCALI},
    {"LYS", "CG", kCALI}, {"LYS", "NZ", kNAMN}, {"MET", "CE", kCALI}, {"MET", "CG", kCALI},
    {"MET", "SD", kS}, {"MSE", "SE", kSE}, {"PHE", "CD1", kCCAR}, {"PHE", "CD2", kCCAR},
    {"PHE", "CE1", kCCAR}, {"PHE", "CE2", kCCAR}, {"PHE", "CG", kCCAR}, {"PHE", "CZ", kCCAR},
    {"PRO", "CD", kCALI}, {"PRO", "CG", kCALI}, {"SEC", "SE", kSE}, {"SER", "OG", kO},
    {"T", "C2", kCNUC}, {"T", "C4", kCNUC}, {"T", "C5", kCNUC}, {"T", "C6", kCNUC},
    {"T", "C7", kCNUC}, {"T", "N1", kNNUC}, {"T", "N3", kNNUC}, {"T", "O2", kO}, {"T", "O4", kO},
    {"THR", "CG2", kCALI}, {"THR", "OG1", kO}, {"TRP", "CD1", kCCAR}, {"TRP", "CD2", kCCAR},
    {"TRP", "CE2", kCCAR}, {"TRP", "CE3", kCCAR}, {"TRP", "CG", kCCAR}, {"TRP", "CH2", kCCAR},
    {"TRP", "CZ2", kCCAR}, {"TRP", "CZ3", kCCAR}, {"TRP", "NE1", kNAMD}, {"TYR", "CD1", kCCAR},
    {"TYR", "CD2", kCCAR}, {"TYR", "CE1", kCCAR}, {"TYR", "CE2", kCCAR}, {"TYR", "CG", kCCAR},
    {"TYR", "CZ", kCCAR}, {"TYR", "OH", kO}, {"U", "C2", kCNUC}, {"U", "C4", kCNUC},
    {"U", "C5", kCNUC}, {"U", "C6", kCNUC}, {"U", "N1", kNNUC}, {"U", "N3", kNNUC}, {"U", "O2", kO},
    {"U", "O4", kO}, {"VAL", "CG1", kCALI}, {"VAL", "CG2", kCALI},
};
}  // namespace naccess

struct ElementGuess {
  std::string_view element;
  double radius;
};
// FreeSASA's symbol_radius, in its order (src/classifier.c, unchanged from 2.1.2 to 2.1.3).
constexpr ElementGuess kFreesasaGuess[] = {
    {"H", 1.10}, {"C", 1.70}, {"N", 1.55}, {"O", 1.52}, {"P", 1.80}, {"S", 1.80}, {"Se", 1.90},
    {"F", 1.47}, {"Cl", 1.75}, {"Br", 1.83}, {"I", 1.98}, {"Li", 1.81}, {"Be", 1.53}, {"Na", 2.27},
    {"Mg", 1.73}, {"K", 2.75}, {"Ca", 2.31}, {"Rb", 3.03}, {"Sr", 2.49}, {"Cs", 3.43}, {"Ba", 2.68},
    {"Fr", 3.48}, {"Ra", 2.83}, {"Sc", 2.11}, {"Ti", 1.95}, {"V", 1.06}, {"Cr", 1.13}, {"Mn", 1.19},
    {"Fe", 1.26}, {"Co", 1.13}, {"Ni", 1.63}, {"Cu", 1.40}, {"Zn", 1.39}, {"Y", 1.61}, {"Zr", 1.42},
    {"Nb", 1.33}, {"Mo", 1.75}, {"Tc", 2.00}, {"Ru", 1.20}, {"Rh", 1.22}, {"Pd", 1.63},
    {"Ag", 1.72}, {"Cd", 1.58}, {"Hf", 1.40}, {"Ta", 1.22}, {"W", 1.26}, {"Re", 1.30}, {"Os", 1.58},
    {"Ir", 1.22}, {"Pt", 1.75}, {"Au", 1.66}, {"Hg", 1.55}, {"Al", 1.84}, {"Ga", 1.87},
    {"In", 1.93}, {"Sn", 2.17}, {"Tl", 1.96}, {"Pb", 2.02}, {"Bi", 2.07}, {"Po", 1.97}, {"B", 1.92},
    {"Si", 2.10}, {"Ge", 2.11}, {"As", 1.85}, {"Sb", 2.06}, {"Te", 2.06}, {"At", 2.02},
    {"He", 1.40}, {"Ne", 1.54}, {"Ar", 1.88}, {"Kr", 2.02}, {"Xe", 2.16}, {"Rn", 2.20},
    {"La", 1.83}, {"Ce", 1.86}, {"Pr", 1.62}, {"Nd", 1.79}, {"Pm", 1.76}, {"Sm", 1.74},
    {"Eu", 1.96}, {"Gd", 1.69}, {"Tb", 1.66}, {"Dy", 1.63}, {"Ho", 1.61}, {"Er", 1.59},
    {"Tm", 1.57}, {"Yb", 1.54}, {"Lu", 1.53}, {"Ac", 2.12}, {"Th", 1.84}, {"Pa", 1.60}, {"U", 1.86},
    {"Np", 1.71}, {"Pu", 1.67}, {"Am", 1.66}, {"Cm", 1.65}, {"Bk", 1.64}, {"Cf", 1.63},
    {"Es", 1.62}, {"Fm", 1.61}, {"Md", 1.60}, {"No", 1.59}, {"Lr", 1.58},
};
// clang-format on

static_assert(std::is_sorted(std::begin(protor::kAtoms), std::end(protor::kAtoms), before));
static_assert(std::is_sorted(std::begin(naccess::kAtoms), std::end(naccess::kAtoms), before));

template <std::size_t N>
std::optional<double> find(const ClassifiedAtom (&table)[N], std::string_view residue, std::string_view atom) {
  const ClassifiedAtom key{residue, atom, 0.0};
  const auto* it = std::lower_bound(std::begin(table), std::end(table), key, before);
  if (it != std::end(table) && it->residue == residue && it->atom == atom) return it->radius;
  return std::nullopt;
}

template <std::size_t N>
std::optional<double> classify(const ClassifiedAtom (&table)[N], std::string_view residue, std::string_view atom) {
  if (const std::optional<double> r = find(table, residue, atom)) return r;
  return find(table, "ANY", atom);
}

}  // namespace

std::optional<RadiusPreset> radiusPresetNamed(std::string_view name) {
  std::string lower(name);
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (lower == "protor") return RadiusPreset::ProtOr;
  if (lower == "naccess") return RadiusPreset::Naccess;
  return std::nullopt;
}

const char* radiusPresetName(RadiusPreset preset) {
  return preset == RadiusPreset::ProtOr ? "protor" : "naccess";
}

std::optional<double> presetRadius(RadiusPreset preset, std::string_view residue, std::string_view atom) {
  return preset == RadiusPreset::ProtOr ? classify(protor::kAtoms, residue, atom)
                                        : classify(naccess::kAtoms, residue, atom);
}

std::optional<double> freesasaGuessRadius(std::string_view element) {
  for (const ElementGuess& e : kFreesasaGuess)
    if (e.element == element) return e.radius;
  return std::nullopt;
}

}  // namespace surftrace::build
