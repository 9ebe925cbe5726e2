// Writing and reading rendered frames through OpenImageIO: PNG colour, multi-channel EXR.
#pragma once

#include <map>
#include <string>

#include "view/frame_buffers.hpp"

namespace surftrace::view {

// String attributes stored with an image ("surftrace:camera" holds cameraToJson, etc.).
using ImageMetadata = std::map<std::string, std::string>;

// 8-bit RGB PNG of the colour buffer (already composited over the background).
void writePng(const std::string& path, const FrameBuffers& frame, const ImageMetadata& metadata);

// OpenEXR with every buffer, one pixel per ray through the pixel centre:
//   R G B A (half-free float colour and coverage), depth.t (ray distance, Å),
//   depth.z (view-space z, Å), N.X N.Y N.Z (world-space unit normal), as 32-bit floats;
//   patch.kind, patch.id, atom.id, flags as 32-bit unsigned integers (misses: id 2³²−1).
void writeExr(const std::string& path, const FrameBuffers& frame, const ImageMetadata& metadata);

// Reads an EXR written by writeExr (or by the GL path) back. Throws std::runtime_error
// naming the file and the missing channel when it is not such a file.
FrameBuffers readExr(const std::string& path, ImageMetadata* metadata = nullptr);

}  // namespace surftrace::view
