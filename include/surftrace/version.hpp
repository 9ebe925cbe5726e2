// The library's version: CMake's project(VERSION), as every image's metadata and `--version` state it.
#pragma once

namespace surftrace {

// "0.1.0".
const char* version();

}  // namespace surftrace
