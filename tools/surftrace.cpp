// surftrace: the command-line front end. Each subcommand lives in its own *_command.cpp.
#include <cstdio>
#include <exception>
#include <string>

#include <CLI/CLI.hpp>

#include "build/io/error.hpp"
#include "commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "SurfTrace computes molecular surfaces exactly (solvent excluded surface, SES) and ray-traces them.\n"
      "\n"
      "Typical use:\n"
      "  surftrace info 1vis.pdb.gz                 what is in a structure file, what gets skipped\n"
      "  surftrace area 1vis.pdb.gz --probe 1.4      exact SAS/SES areas and SES volume\n"
      "  surftrace build 1vis.pdb.gz -o 1vis.stp     write the SES patch list for renderers\n"
      "  surftrace render 1vis.pdb.gz -o 1vis.png    ray-trace the SES exactly (add --exr for buffers)\n"
      "  surftrace compare gl.exr embree.exr        validate another renderer pixel by pixel\n"
      "  surftrace trajectory adk.psf adk.dcd -o f/%05d.png   the surface of every frame of an MD run\n"
      "\n"
      "Input: PDB, mmCIF (both optionally gzipped), PQR (radii from the file), XYZR, XYZ, GRO; trajectories\n"
      "from DCD, XTC, GRO, XYZ and multi-model PDB/mmCIF with a PSF, GRO, PDB or mmCIF topology.\n"
      "Run `surftrace COMMAND --help` for the options of one command.",
      "surftrace"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "surftrace 0.1.0");
  app.fallthrough();

  surftrace::tools::addInfoCommand(app);
  surftrace::tools::addBuildCommands(app);
  std::string commandLine;
  for (int i = 0; i < argc; ++i) commandLine += (i ? " " : "") + std::string(argv[i]);
  surftrace::tools::addRenderCommand(app, commandLine);
  surftrace::tools::addTrajectoryCommand(app, commandLine);
  surftrace::tools::addCompareCommand(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "surftrace: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
