// Runs the FreeSASA command-line program on a temporary PDB file and parses its JSON areas.
#include "oracles/freesasa_oracle.hpp"

#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include <unistd.h>

namespace surftrace::oracle {
namespace {

namespace fs = std::filesystem;

std::string findOnPath(const std::string& program) {
  const char* path = std::getenv("PATH");
  if (!path) return {};
  std::stringstream dirs(path);
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    // An empty PATH entry means the current directory.
    const fs::path p = (dir.empty() ? fs::path(".") : fs::path(dir)) / program;
    if (::access(p.c_str(), X_OK) == 0 && fs::is_regular_file(p)) return p.string();
  }
  return {};
}

// Single-quoted for /bin/sh.
std::string shellQuote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// Removes the temporary files however runFreesasa leaves.
struct TempFiles {
  std::vector<fs::path> paths;
  ~TempFiles() {
    std::error_code ec;
    for (const auto& p : paths) fs::remove(p, ec);
  }
};

fs::path uniqueTempPath(const std::string& suffix) {
  static std::atomic<unsigned> counter{0};
  return fs::temp_directory_path() /
         ("surftrace_freesasa_" + std::to_string(::getpid()) + "_" +
          std::to_string(counter.fetch_add(1)) + suffix);
}

std::string readFile(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The number right after position `pos` (skipping blanks); throws if there is none.
double numberAt(const std::string& text, std::size_t pos) {
  while (pos < text.size() && (text[pos] == ' ' || text[pos] == '\n' || text[pos] == '\r' ||
                               text[pos] == '\t'))
    ++pos;
  const char* begin = text.c_str() + pos;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(begin, &end);
  if (end == begin || errno == ERANGE)
    throw std::runtime_error("runFreesasa: expected a number in freesasa's JSON at offset " +
                             std::to_string(pos));
  return v;
}

}  // namespace

void roundForPdb(std::vector<Sphere>& atoms) {
  for (auto& a : atoms)
    for (int k = 0; k < 3; ++k) a.c[k] = std::round(a.c[k] * 1000.0) / 1000.0;
}

FreesasaResult runFreesasa(const std::vector<Sphere>& atoms, double probeRadius, int slices) {
  const std::string exe = findOnPath("freesasa");
  if (exe.empty())
    throw std::runtime_error(
        "runFreesasa: `freesasa` is not on PATH; run scripts/install-deps.sh --tests (Debian package "
        "freesasa)");
  if (!(std::isfinite(probeRadius) && probeRadius >= 0))
    throw std::invalid_argument("runFreesasa: probe radius must be finite and >= 0");
  if (slices < 1) throw std::invalid_argument("runFreesasa: slices must be >= 1");
  if (atoms.empty()) return {0.0, {}};

  TempFiles tmp;
  const fs::path pdb = uniqueTempPath(".pdb"), json = uniqueTempPath(".json"),
                 err = uniqueTempPath(".err");
  tmp.paths = {pdb, json, err};
  {
    std::FILE* f = std::fopen(pdb.c_str(), "w");
    if (!f) throw std::runtime_error("runFreesasa: cannot write " + pdb.string());
    for (std::size_t i = 0; i < atoms.size(); ++i) {
      const Sphere& a = atoms[i];
      const double r100 = a.r * 100.0;
      if (!(std::isfinite(r100) && a.r >= 0 && a.r <= 999.99 &&
            std::abs(r100 - std::round(r100)) <= 1e-9)) {
        std::fclose(f);
        throw std::invalid_argument("runFreesasa: radius of atom " + std::to_string(i) +
                                    " is not a multiple of 0.01 in [0, 999.99] (the PDB "
                                    "occupancy column is %6.2f)");
      }
      for (int k = 0; k < 3; ++k) {
        if (!(std::isfinite(a.c[k]) && a.c[k] > -999.9995 && a.c[k] < 9999.9995)) {
          std::fclose(f);
          throw std::invalid_argument("runFreesasa: coordinate of atom " + std::to_string(i) +
                                      " does not fit the PDB %8.3f column");
        }
      }
      // Serial (5 columns) and resSeq (4 columns) wrap; FreeSASA keys residues on changes of
      // resSeq, so consecutive atoms stay in distinct residues.
      const int serial = static_cast<int>(i % 99999) + 1;
      const int resSeq = static_cast<int>(i % 9999) + 1;
      std::fprintf(f, "ATOM  %5d  C   ALA A%4d    %8.3f%8.3f%8.3f%6.2f%6.2f           C\n",
                   serial, resSeq, a.c.x, a.c.y, a.c.z, std::round(r100) / 100.0, 0.0);
    }
    std::fprintf(f, "END\n");
    if (std::fclose(f) != 0) throw std::runtime_error("runFreesasa: cannot write " + pdb.string());
  }

  char probe[64];
  std::snprintf(probe, sizeof probe, "%.17g", probeRadius);
  const std::string cmd = shellQuote(exe) + " -O -L --resolution=" + std::to_string(slices) +
                          " --hetatm --hydrogen --unknown=guess --probe-radius=" + probe +
                          " --format=json --depth=atom --output=" + shellQuote(json.string()) +
                          " --error-file=" + shellQuote(err.string()) + " " +
                          shellQuote(pdb.string()) + " </dev/null >/dev/null 2>&1";
  const int rc = std::system(cmd.c_str());
  if (rc != 0)
    throw std::runtime_error("runFreesasa: `" + cmd + "` failed (status " + std::to_string(rc) +
                             "): " + readFile(err));

  // Atom objects carry "area":<number>; chains, residues and the structure carry
  // "area":{...}. ("relative-area" does not match the leading quote.) The structure's
  // "total" is the last one in the document.
  const std::string text = readFile(json);
  FreesasaResult out{0.0, {}};
  out.perAtom.reserve(atoms.size());
  const std::string areaKey = "\"area\":", totalKey = "\"total\":";
  for (std::size_t pos = text.find(areaKey); pos != std::string::npos;
       pos = text.find(areaKey, pos + 1)) {
    std::size_t p = pos + areaKey.size();
    while (p < text.size() && (text[p] == ' ' || text[p] == '\n')) ++p;
    if (p < text.size() && text[p] != '{') out.perAtom.push_back(numberAt(text, p));
  }
  const std::size_t lastTotal = text.rfind(totalKey);
  if (lastTotal == std::string::npos)
    throw std::runtime_error("runFreesasa: no total area in freesasa's output");
  out.total = numberAt(text, lastTotal + totalKey.size());
  if (out.perAtom.size() != atoms.size())
    throw std::runtime_error("runFreesasa: freesasa reported " +
                             std::to_string(out.perAtom.size()) + " atom areas for " +
                             std::to_string(atoms.size()) + " input atoms");
  return out;
}

}  // namespace surftrace::oracle
