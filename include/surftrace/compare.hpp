// Comparing a rendering with a reference of the same view: `surftrace compare` as one call. The
// test is SurfTrace's buffers, or another renderer's depth (and normal) buffers, from files or
// held in memory (memoryChannels: e.g. glReadPixels' result), read in their declared conventions;
// the result holds the figures, the verdict with its hints, the JSON report, and makes the
// difference image and the HTML page. Declared in view/comparison.hpp.
#pragma once

#include "view/comparison.hpp"

namespace surftrace {

// What is compared.
using view::CompareReference;
using view::CompareTest;
using view::ForeignBuffers;
using view::FrameBuffers;
using view::ImageChannels;
using view::ImageMetadata;
// How another renderer's buffers are read.
using view::DepthConvention;
using view::ForeignBufferOptions;
using view::NormalEncoding;
using view::NormalSpace;
using view::RowOrigin;
using view::depthConventionNamed;
using view::normalEncodingNamed;
using view::normalSpaceNamed;
using view::rowOriginNamed;
// Reading them from files or memory.
using view::compareReference;
using view::hasFrameBufferChannels;  // whether a file is SurfTrace's EXR or another renderer's buffers
using view::memoryChannels;
using view::readImageChannels;       // another renderer's buffer from any file OpenImageIO reads
using view::readCompareReference;
using view::readCompareTest;
using view::readForeignTest;
using view::readSurfTraceTest;
// The comparison and what it returns.
using view::compare;
using view::CompareResult;
using view::CompareSettings;
using view::CompareThresholds;
using view::FrameComparison;
using view::kComparePresets;
using view::KindErrors;
using view::TestChannels;
using view::WorstPixel;
// What it draws.
using view::comparisonPage;
using view::differenceImage;
using view::differenceLegend;
using view::EncodedImage;
using view::encodeDifference;
using view::writeDifference;

}  // namespace surftrace
