// The GL engine (gl_engine.hpp).
#include "gl/gl_engine.hpp"

#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "build/sphere_blockers.hpp"
#include "gl/gl_context.hpp"
#include "gl/gl_renderer.hpp"

namespace surftrace::gl {
namespace {

// One thread that runs the jobs given to it, one at a time, in the order given.
//
// An EGL context may be current in one thread at a time, and GlContext is made, used and
// destroyed on one thread. Callers draw from wherever they are: `render` from the main
// thread, `trajectory` from a TBB pipeline's serial_in_order stage, which runs one frame at a
// time but on whichever worker thread TBB picks for it. Making the context current in the
// calling thread at every draw (and releasing it after) would work there only as long as
// every caller is serial, and would leave the context's objects to be destroyed from some
// other thread; a thread of the engine's own holds the context from its first frame to its
// destruction whatever the callers do, and two callers at once simply queue. The cost is a
// hand-over per frame, microseconds beside a frame's milliseconds. GL's output depends on
// the frame alone, not on the thread that asked for it.
class DrawThread {
 public:
  DrawThread() : thread_([this] { loop(); }) {}
  ~DrawThread() {
    {
      const std::lock_guard lock(mutex_);
      stop_ = true;
    }
    wake_.notify_one();
    thread_.join();
  }
  DrawThread(const DrawThread&) = delete;
  DrawThread& operator=(const DrawThread&) = delete;

  // f() on the thread, waited for; its result, or its exception rethrown here.
  template <class F> auto run(F f) -> decltype(f()) {
    std::packaged_task<decltype(f())()> task(std::move(f));
    auto result = task.get_future();
    {
      const std::lock_guard lock(mutex_);
      jobs_.push_back([&task] { task(); });  // `task` outlives the job: we wait for it below
    }
    wake_.notify_one();
    return result.get();
  }

 private:
  void loop() {
    for (;;) {
      std::function<void()> job;
      {
        std::unique_lock lock(mutex_);
        wake_.wait(lock, [&] { return stop_ || !jobs_.empty(); });
        if (jobs_.empty()) return;
        job = std::move(jobs_.front());
        jobs_.pop_front();
      }
      job();
    }
  }

  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::function<void()>> jobs_;
  bool stop_ = false;
  std::thread thread_;  // last: started once the members it uses exist
};

}  // namespace

struct GlEngine::Impl {
  GlOptions gl;
  std::optional<GlContext> context;  // the draw thread's, opened by the first frame
  // Made with the context and kept for every frame: its programs are compiled once (a frame
  // uploads its own patches, blockers and model: GlRenderer::upload replaces them all).
  std::optional<GlRenderer> renderer;
  std::string contextDescription;    // written on the draw thread, read after run() returns
  DrawThread thread;                 // last: destroyed first, after the context is closed
};

GlEngine::GlEngine(const view::EngineOptions& options) : impl_(std::make_unique<Impl>()) {
  impl_->gl.torus = parseTorusMethod(options.glTorus);
  impl_->gl.primitive = parsePrimitive(options.glPrimitive);
  if (options.glSteps < 1)
    throw std::invalid_argument("GL sphere-tracing steps " + std::to_string(options.glSteps) + ": give 1 or more");
  impl_->gl.maxSteps = options.glSteps;
}

GlEngine::~GlEngine() {
  // The context is closed on the thread that opened it.
  try {
    impl_->thread.run([this] {
      impl_->renderer.reset();
      impl_->context.reset();
    });
  } catch (...) {
    // A context that fails to close leaves nothing to do here; the driver reclaims it at exit.
  }
}

view::EngineDescription GlEngine::describe() const {
  return {name(),
          impl_->contextDescription,
          "gl: " + impl_->contextDescription,
          {{"surftrace:gl_torus_method", torusMethodName(impl_->gl.torus)},
           {"surftrace:gl_primitive", primitiveName(impl_->gl.primitive)}}};
}

view::FrameBuffers GlEngine::draw(const view::Frame& frame) {
  const build::PatchList& list = *frame.surface;
  // Transparency: every atom hides parts of the whole spheres (build/sphere_blockers.hpp).
  std::optional<build::SphereBlockers> blockers;
  if (frame.options.opacity < 1.0 && frame.centers.size() == list.params.atomCount) {
    std::vector<glm::dvec4> atoms;
    atoms.reserve(frame.centers.size());
    for (std::size_t i = 0; i < frame.centers.size(); ++i) atoms.push_back(glm::dvec4(frame.centers[i], frame.radii[i]));
    blockers = build::sphereBlockers(list, atoms);
  }
  return impl_->thread.run([&] {
    Impl& m = *impl_;
    if (!m.context) {
      m.context.emplace();
      m.contextDescription = m.context->description();
    }
    if (!m.renderer) m.renderer.emplace(*m.context);
    return renderGl(*m.renderer, list, frame.options, frame.atomColors, m.gl, blockers ? &*blockers : nullptr,
                    frame.model);
  });
}

}  // namespace surftrace::gl
