// Writing the files the stages make: whole or not at all (a temporary beside the target,
// renamed over it), "-" the standard output, a device, FIFO or socket written in place, a
// symbolic link followed; and the checks a program makes before slow work starts.
#pragma once

#include "build/io/output_file.hpp"
#include "build/io/text_fields.hpp"

namespace surftrace {

using build::OutputContent;
using build::checkStandardOutput;   // a reader that went away (| head): an error naming the pipe
using build::finishStandardOutput;  // flush, and report a closed pipe as an error
using build::isStandardOutput;      // "-"
using build::isWrittenInPlace;      // "-", a device, a FIFO, a socket: no temporary, no rename
using build::prepareOutputPath;     // an output name checked before the work (folder, permissions, kind)
using build::writeFileAtomically;   // bytes to a path, whole or not at all
using build::text::readTextFile;    // a text file whole, any line ends, named in errors

}  // namespace surftrace
