// Choosing an engine (surftrace/engine.hpp).
#include "surftrace/engine.hpp"

#include <stdexcept>
#include <string>

#include "gl/gl_engine.hpp"
#include "trace/embree_engine.hpp"

namespace surftrace {

std::unique_ptr<Engine> makeEngine(const EngineOptions& options) {
  switch (options.kind) {
    case EngineKind::Embree:
      return std::make_unique<trace::EmbreeEngine>();
    case EngineKind::Gl:
      return std::make_unique<gl::GlEngine>(options);
  }
  throw std::invalid_argument("makeEngine: unknown engine kind " + std::to_string(static_cast<int>(options.kind)));
}

}  // namespace surftrace
