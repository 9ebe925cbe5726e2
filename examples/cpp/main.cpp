// SurfTrace as a library: read a structure, build its solvent-excluded surface (SES), print
// the surface's area and render it with Embree to a PNG. Every stage is one call of the public
// API (<surftrace/surftrace.hpp>); the `surftrace` program is these same calls behind argv.
//
//   surface_example STRUCTURE IMAGE.png      e.g. tests/data/structures/1crn.pdb 1crn.png
#include <charconv>
#include <cstdio>
#include <exception>
#include <memory>
#include <vector>

#include <surftrace/surftrace.hpp>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s STRUCTURE IMAGE.png\n", argv[0]);
    return 2;
  }
  try {
    // Read: the atoms' centres and radii (PDB, mmCIF, PQR, XYZR, XYZ, GRO, gzipped or not),
    // with the choices `surftrace` makes by default (waters left out, hydrogens kept).
    const surftrace::Molecule molecule = surftrace::readStructure(argv[1]);

    // Build: the SES of a probe of 1.4 Å (water) as a list of exact patches (convex spheres,
    // tori, concave spheres), the plain data every later stage reads.
    surftrace::SurfaceRequest request;
    request.surface = surftrace::SurfaceKind::Ses;
    request.probeRadius = 1.4;
    const surftrace::PatchList surface = surftrace::buildSurface(molecule, request);

    // Its area, exact from the patches. Printed in the shortest digits that read back as the
    // same double (std::to_chars), as `surftrace area FILE --format json` writes it.
    const surftrace::SurfaceAreas areas = surftrace::surfaceAreas(surface, molecule.centers);
    char digits[32];
    const auto printed = std::to_chars(digits, digits + sizeof digits, areas.total);
    std::printf("SES area %.*s A^2 (%zu atoms)\n", static_cast<int>(printed.ptr - digits), digits, molecule.size());

    // A camera: the base camera holds the image size (and the projection and field of view);
    // frameSurface puts the eye where the whole surface fits, looking down -z.
    surftrace::Camera camera;
    camera.width = 256;
    camera.height = 256;
    camera = surftrace::frameSurface(camera, surftrace::Framing{}, surface, molecule);

    // Render with Embree: a Frame is what to draw (the patches, the atoms and their colours)
    // and how (the render options: here the camera, colours by element).
    const std::unique_ptr<surftrace::Engine> engine = surftrace::makeEngine({});
    surftrace::Frame frame;
    frame.options.camera = camera;
    frame.options.color = surftrace::ColorMode::Element;
    const std::vector<glm::vec3> colors = surftrace::atomColors(molecule, frame.options.color, glm::vec3(0.8f));
    frame.surface = &surface;
    frame.centers = molecule.centers;
    frame.radii = molecule.radii;
    frame.atomColors = colors;
    const surftrace::FrameBuffers image = engine->render(frame);

    // Write the PNG (no EXR: ""), with a record of how it was made in its metadata.
    surftrace::ImageRecord record;
    record.engine = engine->name();
    record.surface = "ses";
    record.probeRadius = request.probeRadius;
    record.input = argv[1];
    record.color = "element";
    surftrace::writeImage(argv[2], "", image, record, camera);
    std::printf("wrote %s (%d x %d)\n", argv[2], camera.width, camera.height);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "surface_example: %s\n", e.what());
    return 1;
  }
  return 0;
}
