// The GL engine (view::Engine): the headless OpenGL ray caster (gl_renderer.hpp), its EGL
// context opened by the first frame and used by one thread of its own for as long as the
// engine lives.
#pragma once

#include <memory>

#include "view/engine.hpp"

namespace surftrace::gl {

class GlEngine final : public view::Engine {
 public:
  // Throws std::invalid_argument for a GL setting it does not know (options.glTorus,
  // glPrimitive, glSteps < 1).
  explicit GlEngine(const view::EngineOptions& options);
  ~GlEngine() override;

  view::EngineDescription describe() const override;
  const char* name() const override { return "gl"; }

 protected:
  // Computes the frame's sphere blockers (transparency with every atom) on the calling
  // thread, then draws on the engine's own thread.
  view::FrameBuffers draw(const view::Frame& frame) override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace surftrace::gl
