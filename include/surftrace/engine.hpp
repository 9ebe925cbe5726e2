// Engines: draw a Frame (the patch list, the atoms, the ball-and-stick model and the render
// options) into its buffers, with Embree (exact, CPU, the reference) or GL (headless OpenGL,
// one sample per pixel, no shadows or ambient occlusion). One interface for both
// (view/engine.hpp); makeEngine chooses.
//
//   auto engine = surftrace::makeEngine({});              // Embree
//   surftrace::Frame frame{&patches, centers, radii, colors};
//   frame.options.camera = camera;
//   const surftrace::FrameBuffers image = engine->render(frame);
#pragma once

#include <memory>

#include "view/engine.hpp"

namespace surftrace {

using view::checkEngineCanDraw;
using view::Engine;
using view::EngineDescription;
using view::EngineKind;
using view::engineKindName;
using view::EngineOptions;
using view::Frame;
using view::FrameBuffers;
using view::parseEngineKind;
using view::RenderOptions;

// The engine `options.kind` names. GL's context opens with its first frame (std::runtime_error
// there when no OpenGL 4.5 driver can be opened); std::invalid_argument for a GL setting it
// does not know. The one place that names every engine: a new engine adds its case here.
std::unique_ptr<Engine> makeEngine(const EngineOptions& options = {});

}  // namespace surftrace
