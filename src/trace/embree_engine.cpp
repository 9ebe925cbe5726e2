// The Embree engine (embree_engine.hpp).
#include "trace/embree_engine.hpp"

#include <string>

#include <embree3/rtcore_config.h>

#include "trace/patch_scene.hpp"
#include "trace/render.hpp"

namespace surftrace::trace {

EmbreeEngine::EmbreeEngine() : device_(std::make_unique<EmbreeDevice>()) {}

EmbreeEngine::~EmbreeEngine() = default;

view::EngineDescription EmbreeEngine::describe() const {
  return {name(), "", std::string("embree ") + RTC_VERSION_STRING + " (double-precision patches)", {}};
}

view::FrameBuffers EmbreeEngine::draw(const view::Frame& frame) {
  const build::PatchList& list = *frame.surface;
  const bool transparent = frame.options.opacity < 1.0 && frame.centers.size() == list.params.atomCount;
  const PatchScene scene(transparent ? ScenePatches::fromPatchList(list, frame.centers, frame.radii, frame.model)
                                     : ScenePatches::fromPatchList(list, {}, {}, frame.model),
                         *device_);
  sceneSeconds_ = scene.buildSeconds();
  return trace::render(scene, frame.options, frame.atomColors);
}

}  // namespace surftrace::trace
