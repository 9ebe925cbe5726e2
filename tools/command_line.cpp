// The top-level command line both programs share (command_line.hpp).
#include "command_line.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <vector>

#include "commands.hpp"
#include "surftrace/files.hpp"

namespace surftrace::tools {
namespace {

// This machine's memory, e.g. "23.4 GiB"; empty when the system does not say.
std::string physicalMemory() {
  const long pages = sysconf(_SC_PHYS_PAGES), pageSize = sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || pageSize <= 0) return {};
  char text[32];
  std::snprintf(text, sizeof text, "%.1f GiB", static_cast<double>(pages) * static_cast<double>(pageSize) / 0x1p30);
  return text;
}

}  // namespace

std::string outOfMemoryMessage(const std::string& file, const char* what) {
  const std::string memory = physicalMemory();
  return file + ": not enough memory to hold " + what + " it describes (the allocation failed" +
         (memory.empty() ? std::string() : "; this machine has " + memory) +
         "): a damaged or forged header, or a file too large for this machine or for the memory limit (ulimit -v)";
}

void describeApp(CLI::App& app) {
  app.description(
      "SurfTrace computes molecular surfaces exactly - the solvent excluded surface (SES) and the\n"
      "molecular skin surface (MSS) - as analytic patches, ray-traces them on the CPU (Embree) or with\n"
      "OpenGL, renders whole MD trajectories, and compares renderings pixel by pixel.\n"
      "\n"
      "Typical use:\n"
      "  surftrace info 1vis.pdb.gz                 what is in a structure file, what gets skipped\n"
      "  surftrace area 1vis.pdb.gz --probe 1.4      exact SAS/SES areas and SES volume\n"
      "  surftrace area 1vis.pdb.gz --surface mss --shrink 0.5   the skin's area and volume\n"
      "  surftrace build 1vis.pdb.gz -o 1vis.stp     write the SES (or --surface mss) patch list for renderers\n"
      "  surftrace render 1vis.pdb.gz -o 1vis.png    ray-trace the surface exactly (add --exr for buffers)\n"
      "  surftrace compare gl.exr embree.exr        validate another renderer pixel by pixel\n"
      "  surftrace trajectory adk.psf adk.dcd -o f/%05d.png   the surface of every frame of an MD run\n"
      "\n"
      "Input: PDB, mmCIF (both optionally gzipped), PQR (radii from the file), XYZR, XYZ, GRO; trajectories\n"
      "from DCD, XTC, GRO, XYZ and multi-model PDB/mmCIF with a PSF, GRO, PDB or mmCIF topology.\n"
      "Run `surftrace COMMAND --help` for the options of one command. Options spelt with colour (--colour,\n"
      "--uniform-colour, ...) are the same as those spelt with color.");
  app.name("surftrace");
  app.require_subcommand(1);
  // -V as in python3, ssh and cmake's own tools: -v is a verbosity flag elsewhere.
  app.set_version_flag("-V,--version", kSoftware);
  app.fallthrough();
}

namespace {

// An option name in British spelling, in its American one (--colour -> --color): the options are
// spelt as in CLI conventions and in OpenGL (color), the prose as in the README (colour), and
// users type both. Values are left alone, and so is everything after a bare "--".
std::vector<std::string> americanOptionNames(int argc, char** argv) {
  std::vector<std::string> args(argv, argv + argc);
  for (std::size_t i = 1; i < args.size() && args[i] != "--"; ++i) {
    std::string& arg = args[i];
    if (arg.rfind("--", 0) != 0) continue;
    std::size_t end = std::min(arg.find('='), arg.size());
    for (std::size_t at = arg.find("colour"); at < end; at = arg.find("colour", at)) {
      arg.erase(at + 4, 1);  // colour -> color
      --end;
    }
  }
  return args;
}

// The optimal string alignment distance (Levenshtein with adjacent transpositions, so that
// --szie is one edit from --size).
std::size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i)
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}

// The names `word` was probably meant to be: the nearest within two edits (one for words of up
// to four letters, where two edits reach nearly anything; none for one letter), else the names it begins (an
// abbreviation: --depth-dark). Empty when nothing is near.
std::vector<std::string> nearestNames(const std::string& word, const std::vector<std::string>& names) {
  const std::size_t letters = word.size() - std::min(word.find_first_not_of('-'), word.size());
  // One letter (-v) is one edit from every short option: no guess.
  const std::size_t limit = letters <= 1 ? 0 : letters <= 4 ? 1 : 2;
  std::size_t best = limit + 1;
  std::vector<std::string> nearest;
  for (const std::string& name : names) {
    const std::size_t d = editDistance(word, name);
    if (d > limit || std::find(nearest.begin(), nearest.end(), name) != nearest.end()) continue;
    if (d < best) {
      nearest.clear();
      best = d;
    }
    if (d == best) nearest.push_back(name);
  }
  if (nearest.empty() && letters >= 3)
    for (const std::string& name : names)
      if (name.rfind(word, 0) == 0) nearest.push_back(name);
  return nearest;
}

// "--a", "--a or --b", "--a, --b or --c".
std::string alternatives(const std::vector<std::string>& names) {
  std::string text;
  for (std::size_t i = 0; i < names.size(); ++i) text += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
  return text;
}

// For CLI11's "The following argument was not expected: --szie": what was not understood and
// what was probably meant, from the names of the command that was running. Empty when the
// extras are no mistyped option or command (CLI11's message then stands).
std::string explainExtras(const CLI::App& app) {
  const std::vector<std::string> extras = app.remaining(true);
  const std::vector<CLI::App*> commands = app.get_subcommands();
  const CLI::App& command = commands.empty() ? app : *commands.front();
  const std::string where = commands.empty() ? "surftrace --help" : "surftrace " + command.get_name() + " --help";
  std::vector<std::string> optionNames, commandNames;
  for (const CLI::App* owner : {&command, &app})
    for (const CLI::Option* option : owner->get_options()) {
      for (const std::string& name : option->get_lnames()) optionNames.push_back("--" + name);
      for (const std::string& name : option->get_snames()) optionNames.push_back("-" + name);
    }
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    commandNames.push_back(sub->get_name());
  // No command: the first word is the mistyped command (rendr), whatever options follow.
  if (commands.empty())
    for (const std::string& extra : extras)
      if (extra.empty() || extra[0] != '-') {
        const std::vector<std::string> near = nearestNames(extra, commandNames);
        return "unknown command " + extra + (near.empty() ? "" : "; did you mean " + alternatives(near) + "?") +
               " (`surftrace --help` lists the commands)";
      }
  for (const std::string& extra : extras) {
    if (extra.size() > 1 && extra[0] == '-') {
      const std::string word = extra.substr(0, extra.find('='));
      const std::vector<std::string> near = nearestNames(word, optionNames);
      return "unknown option " + word + (near.empty() ? "" : "; did you mean " + alternatives(near) + "?") + " (`" +
             where + "` lists the options)";
    }
  }
  return {};
}

}  // namespace

int runApp(CLI::App& app, int argc, char** argv) {
  try {
    const std::vector<std::string> args = americanOptionNames(argc, argv);
    std::vector<const char*> pointers;
    for (const std::string& arg : args) pointers.push_back(arg.c_str());
    app.parse(argc, pointers.data());
    // What was printed must have reached standard output (a full disk, a closed pipe).
    build::finishStandardOutput();
  } catch (const CLI::ParseError& e) {
    // An unknown option or command is said first, with what was probably meant: it is the
    // cause of what else went wrong (its value taken for a file: "TRAJECTORY: File does not
    // exist: 1" for `area X --prboe 1`; "A subcommand is required" for `rendr`).
    const std::string explained = e.get_exit_code() == 0 ? std::string() : explainExtras(app);
    if (!explained.empty()) {
      std::fprintf(stderr, "surftrace: error: %s\n", explained.c_str());
      return 1;
    }
    // CLI11 prints the message; its own exit codes (104, 105, ...) mean nothing to a user:
    // 0 for --help and --version, 1 for every error, as --help says.
    return app.exit(e) == 0 ? 0 : 1;
  } catch (const std::bad_alloc&) {
    // Where no command said which file asked for it (readingFile): at least the command.
    std::fflush(stdout);
    const std::string command = app.get_subcommands().empty() ? "surftrace" : app.get_subcommands().front()->get_name();
    std::fprintf(stderr, "surftrace: error: out of memory (std::bad_alloc) in `surftrace %s`: the input or the "
                 "options ask for more memory than this machine has\n", command.c_str());
    return 1;
  } catch (const std::exception& e) {
    std::fflush(stdout);
    std::fprintf(stderr, "surftrace: error: %s\n", e.what());
    return 1;
  }
  return 0;
}

}  // namespace surftrace::tools
