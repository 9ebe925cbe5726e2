// Areas per atom, residue or chain (area_groups.hpp).
#include "area_groups.hpp"

#include <algorithm>
#include <cstdio>
#include <map>
#include <utility>

#include "surftrace/files.hpp"

namespace surftrace::tools {
namespace {

struct MaxAsa {
  std::string_view residue;
  double area;  // Å²
};

// M. Z. Tien, A. G. Meyer, D. K. Sydykova, S. J. Spielman, C. O. Wilke, "Maximum allowed solvent
// accessibilities of residues in proteins", PLoS ONE 8(11): e80635 (2013), Table 1, column
// "Theoretical": the largest ASA of residue X in a Gly-X-Gly tripeptide over the sterically
// allowed backbone and side-chain conformations (probe 1.4 Å). Chosen over the empirical column
// and the older scales (Miller 1987, Rose 1985, Sander & Rost 1994) because it bounds the ASA a
// residue can have, so a relative value above 1 means an input or radius problem, not an
// exposed residue.
constexpr MaxAsa kTien2013[] = {
    {"ALA", 129.0}, {"ARG", 274.0}, {"ASN", 195.0}, {"ASP", 193.0}, {"CYS", 167.0},
    {"GLN", 225.0}, {"GLU", 223.0}, {"GLY", 104.0}, {"HIS", 224.0}, {"ILE", 197.0},
    {"LEU", 201.0}, {"LYS", 236.0}, {"MET", 224.0}, {"PHE", 240.0}, {"PRO", 159.0},
    {"SER", 155.0}, {"THR", 172.0}, {"TRP", 285.0}, {"TYR", 263.0}, {"VAL", 174.0}};

std::string charText(char c) { return c == ' ' || c == '\0' ? std::string() : std::string(1, c); }

// A table's cell for a text that may be empty: "-", so that whitespace still splits the columns.
std::string cell(const std::string& s) { return s.empty() ? "-" : s; }

double sum(const std::vector<double>& perAtom, const std::vector<std::size_t>& atoms) {
  double s = 0.0;
  for (std::size_t i : atoms) s += perAtom[i];
  return s;
}

void appendAltLoc(std::string& altLocs, char altLoc) {
  if (altLoc != ' ' && altLoc != '\0' && altLocs.find(altLoc) == std::string::npos) altLocs += altLoc;
}

}  // namespace

AreaLevel areaLevelNamed(const std::string& name) {
  if (name == "atom") return AreaLevel::Atom;
  if (name == "chain") return AreaLevel::Chain;
  return AreaLevel::Residue;
}

std::vector<AreaGroup> residueGroups(const build::Molecule& m) {
  std::vector<AreaGroup> groups;
  for (std::size_t i = 0; i < m.size(); ++i) {
    const build::AtomRecord& a = m.atoms[i];
    const bool same = !groups.empty() && groups.back().chain == a.chain && groups.back().residue == a.residue &&
                      groups.back().residueNumber == a.residueNumber &&
                      groups.back().insertionCode == a.insertionCode;
    if (!same) {
      AreaGroup g;
      g.chain = a.chain;
      g.residue = a.residue;
      g.residueNumber = a.residueNumber;
      g.insertionCode = a.insertionCode;
      g.residueCount = 1;
      groups.push_back(std::move(g));
    }
    groups.back().atoms.push_back(i);
    appendAltLoc(groups.back().altLocs, a.altLoc);
  }
  return groups;
}

std::vector<AreaGroup> chainGroups(const build::Molecule& m) {
  std::vector<AreaGroup> groups;
  std::map<std::string, std::size_t> index;
  for (const AreaGroup& r : residueGroups(m)) {
    const auto [it, added] = index.emplace(r.chain, groups.size());
    if (added) {
      AreaGroup g;
      g.chain = r.chain;
      groups.push_back(std::move(g));
    }
    AreaGroup& c = groups[it->second];
    c.atoms.insert(c.atoms.end(), r.atoms.begin(), r.atoms.end());
    for (char l : r.altLocs) appendAltLoc(c.altLocs, l);
    ++c.residueCount;
  }
  return groups;
}

std::vector<AreaGroup> areaGroups(const build::Molecule& m, AreaLevel level) {
  if (level == AreaLevel::Residue) return residueGroups(m);
  if (level == AreaLevel::Chain) return chainGroups(m);
  return {};
}

std::optional<double> maxAsaTien2013(std::string_view residue) {
  for (const MaxAsa& e : kTien2013)
    if (e.residue == residue) return e.area;
  return std::nullopt;
}

std::vector<std::string> residuesWithoutMaxAsa(const std::vector<AreaGroup>& groups) {
  std::vector<std::string> names;
  for (const AreaGroup& g : groups)
    if (!maxAsaTien2013(g.residue) && std::find(names.begin(), names.end(), g.residue) == names.end())
      names.push_back(g.residue);
  return names;
}

bool AreaRows::relative() const {
  return level == AreaLevel::Residue &&
         std::any_of(columns.begin(), columns.end(), [](const AreaColumn& c) { return c.name == "sas"; });
}

namespace {

const std::vector<double>* sasColumn(const std::vector<AreaColumn>& columns) {
  for (const AreaColumn& c : columns)
    if (c.name == "sas") return c.perAtom;
  return nullptr;
}

}  // namespace

void AreaRows::printHeader() const {
  const bool csv = format == "csv";
  std::vector<std::string> names;
  if (withFrame) names = {"frame", "time_ps"};
  if (level == AreaLevel::Atom)
    for (const char* n : {"atom", "serial", "chain", "residue", "residue_number", "insertion_code", "altloc", "name",
                          "element", "radius"})
      names.emplace_back(n);
  else if (level == AreaLevel::Residue)
    for (const char* n : {"chain", "residue", "residue_number", "insertion_code", "altloc", "atoms"})
      names.emplace_back(n);
  else
    for (const char* n : {"chain", "residues", "atoms"}) names.emplace_back(n);
  for (const AreaColumn& c : columns) names.push_back(c.name);
  if (relative()) names.emplace_back(csv ? kRelativeSasColumn : "relative_sas");
  if (csv) {
    for (std::size_t k = 0; k < names.size(); ++k) std::printf("%s%s", k ? "," : "", names[k].c_str());
    std::printf("\n");
    return;
  }
  if (relative()) std::printf("# relative_sas: SAS / maximum ASA of %s; '-' where the residue is not one of its 20\n", kMaxAsaTable);
  // The table's columns, each as wide as printRows writes it.
  std::string line;
  char buf[64];
  std::size_t k = 0;
  if (withFrame) {
    std::snprintf(buf, sizeof buf, "%6s %12s", "frame", "time_ps");
    line += buf;
    k = 2;
  }
  for (; k < names.size(); ++k) {
    const std::string& n = names[k];
    const bool text = n == "chain" || n == "residue" || n == "name" || n == "element" || n == "insertion_code" ||
                      n == "altloc";
    const int width = n == "insertion_code" ? 5 : n == "altloc" ? 6 : text ? 5 : n == "residue_number" ? 8
                      : (n == "atom" || n == "serial" || n == "atoms" || n == "residues") ? 7 : n == "radius" ? 7 : 12;
    const std::string shown = n == "insertion_code" ? "icode" : n == "residue_number" ? "number" : n;
    std::snprintf(buf, sizeof buf, text ? "%s%-*s" : "%s%*s", line.empty() ? "" : " ", width, shown.c_str());
    line += buf;
  }
  std::printf("%s\n", line.c_str());
}

void AreaRows::printRows(const build::Molecule& m, const std::vector<AreaGroup>& groups, std::size_t frame,
                         double time) const {
  const bool csv = format == "csv";
  const std::vector<double>* sas = sasColumn(columns);
  const auto prefix = [&] {
    if (withFrame) std::printf(csv ? "%zu,%.6g," : "%6zu %12.6g ", frame, time);
  };
  const auto area = [&](double v) { std::printf(csv ? ",%.6f" : " %12.4f", v); };
  if (level == AreaLevel::Atom) {
    for (std::size_t i = 0; i < m.size(); ++i) {
      const build::AtomRecord& r = m.atoms[i];
      prefix();
      if (csv)
        std::printf("%zu,%d,%s,%s,%d,%s,%s,%s,%s,%.4f", r.fileIndex, r.serial, r.chain.c_str(), r.residue.c_str(),
                    r.residueNumber, charText(r.insertionCode).c_str(), charText(r.altLoc).c_str(), r.name.c_str(),
                    r.element.c_str(), m.radii[i]);
      else
        std::printf("%7zu %7d %-5s %-5s %8d %-5s %-6s %-5s %-5s %7.4f", r.fileIndex, r.serial, cell(r.chain).c_str(),
                    cell(r.residue).c_str(), r.residueNumber, cell(charText(r.insertionCode)).c_str(),
                    cell(charText(r.altLoc)).c_str(), cell(r.name).c_str(), cell(r.element).c_str(), m.radii[i]);
      for (const AreaColumn& c : columns) area((*c.perAtom)[i]);
      std::printf("\n");
      // A reader that stopped early (| head) ends the command here, with the reason.
      build::checkStandardOutput();
    }
    return;
  }
  for (const AreaGroup& g : groups) {
    prefix();
    if (level == AreaLevel::Residue) {
      if (csv)
        std::printf("%s,%s,%d,%s,%s,%zu", g.chain.c_str(), g.residue.c_str(), g.residueNumber,
                    charText(g.insertionCode).c_str(), g.altLocs.c_str(), g.atoms.size());
      else
        std::printf("%-5s %-5s %8d %-5s %-6s %7zu", cell(g.chain).c_str(), cell(g.residue).c_str(), g.residueNumber,
                    cell(charText(g.insertionCode)).c_str(), cell(g.altLocs).c_str(), g.atoms.size());
    } else {
      std::printf(csv ? "%s,%zu,%zu" : "%-5s %7zu %7zu", (csv ? g.chain : cell(g.chain)).c_str(), g.residueCount,
                  g.atoms.size());
    }
    for (const AreaColumn& c : columns) area(sum(*c.perAtom, g.atoms));
    if (relative()) {
      const std::optional<double> max = maxAsaTien2013(g.residue);
      if (max) std::printf(csv ? ",%.6f" : " %12.4f", sum(*sas, g.atoms) / *max);
      else std::printf(csv ? "," : " %12s", "-");
    }
    std::printf("\n");
    build::checkStandardOutput();
  }
}

nlohmann::json AreaRows::json(const build::Molecule& m, const std::vector<AreaGroup>& groups) const {
  nlohmann::json rows = nlohmann::json::array();
  const std::vector<double>* sas = sasColumn(columns);
  if (level == AreaLevel::Atom) {
    for (std::size_t i = 0; i < m.size(); ++i) {
      const build::AtomRecord& r = m.atoms[i];
      nlohmann::json row = {{"atom", r.fileIndex},
                            {"serial", r.serial},
                            {"chain", r.chain},
                            {"residue", r.residue},
                            {"residue_number", r.residueNumber},
                            {"insertion_code", charText(r.insertionCode)},
                            {"altloc", charText(r.altLoc)},
                            {"name", r.name},
                            {"element", r.element},
                            {"radius", m.radii[i]}};
      for (const AreaColumn& c : columns) row[c.name] = (*c.perAtom)[i];
      rows.push_back(std::move(row));
    }
    return rows;
  }
  for (const AreaGroup& g : groups) {
    nlohmann::json row = {{"chain", g.chain}};
    if (level == AreaLevel::Residue) {
      row["residue"] = g.residue;
      row["residue_number"] = g.residueNumber;
      row["insertion_code"] = charText(g.insertionCode);
      row["altloc"] = g.altLocs;
    } else {
      row["residues"] = g.residueCount;
    }
    row["atoms"] = g.atoms.size();
    for (const AreaColumn& c : columns) row[c.name] = sum(*c.perAtom, g.atoms);
    if (relative()) {
      const std::optional<double> max = maxAsaTien2013(g.residue);
      row["relative_sas"] = max ? nlohmann::json(sum(*sas, g.atoms) / *max) : nlohmann::json(nullptr);
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace surftrace::tools
