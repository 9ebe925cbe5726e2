// The Embree engine (view::Engine): every frame an Embree scene of its patch list on one
// device, traced exactly in double precision (trace/render.hpp).
#pragma once

#include <memory>

#include "view/engine.hpp"

namespace surftrace::trace {

class EmbreeDevice;

class EmbreeEngine final : public view::Engine {
 public:
  EmbreeEngine();
  ~EmbreeEngine() override;

  view::EngineDescription describe() const override;
  double sceneSeconds() const override { return sceneSeconds_; }
  const char* name() const override { return "embree"; }

 protected:
  // A transparent frame with every atom hands them to the scene, whose layers then clip the
  // SES spheres by the buried atoms too (trace/layers.hpp).
  view::FrameBuffers draw(const view::Frame& frame) override;

 private:
  std::unique_ptr<EmbreeDevice> device_;  // one for every frame
  double sceneSeconds_ = 0.0;
};

}  // namespace surftrace::trace
