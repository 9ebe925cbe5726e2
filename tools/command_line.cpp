// The top-level command line both programs share (command_line.hpp).
#include "command_line.hpp"

#include <cstdio>
#include <exception>

#include "build/io/output_file.hpp"
#include "commands.hpp"

namespace surftrace::tools {

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
      "Run `surftrace COMMAND --help` for the options of one command.");
  app.name("surftrace");
  app.require_subcommand(1);
  app.set_version_flag("--version", kSoftware);
  app.fallthrough();
}

int runApp(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
    // What was printed must have reached standard output (a full disk, a closed pipe).
    build::finishStandardOutput();
  } catch (const CLI::ParseError& e) {
    // CLI11 prints the message; its own exit codes (104, 105, ...) mean nothing to a user:
    // 0 for --help and --version, 1 for every error, as --help says.
    return app.exit(e) == 0 ? 0 : 1;
  } catch (const std::exception& e) {
    std::fflush(stdout);
    std::fprintf(stderr, "surftrace: error: %s\n", e.what());
    return 1;
  }
  return 0;
}

}  // namespace surftrace::tools
