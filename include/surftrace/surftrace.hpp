// SurfTrace's public C++ API, in the order data flows:
//
//   read (molecule.hpp)  ->  build or update the surface, its areas (surface.hpp)
//   ->  a camera (camera.hpp)  ->  an Engine draws a Frame (engine.hpp)  ->  image-space effects
//   ->  encode and write the image (image.hpp, files.hpp);  compare two images (compare.hpp).
//
// One CMake target: find_package(SurfTrace) then target_link_libraries(app SurfTrace::surftrace).
// The types are those the library's modules share (build::, view::), named here in namespace
// surftrace; examples/cpp/ is a whole program.
#pragma once

#include "surftrace/camera.hpp"
#include "surftrace/compare.hpp"
#include "surftrace/engine.hpp"
#include "surftrace/files.hpp"
#include "surftrace/image.hpp"
#include "surftrace/molecule.hpp"
#include "surftrace/surface.hpp"
#include "surftrace/version.hpp"
