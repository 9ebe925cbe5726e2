// The headless EGL context: it must open here (llvmpipe in CI), report GL 4.5, and nest.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "gl/gl_context.hpp"

namespace surftrace::gl {
namespace {

TEST(GlContext, OpensGl45CoreHeadless) {
  const GlContext context;
  EXPECT_FALSE(context.renderer().empty());
  EXPECT_NE(context.version().find("Core Profile"), std::string::npos) << context.version();
  EXPECT_TRUE(context.platform() == "surfaceless" || context.platform() == "device") << context.platform();
  const std::string description = context.description();
  EXPECT_NE(description.find(context.renderer()), std::string::npos);
  EXPECT_NE(description.find(context.version()), std::string::npos);
  std::printf("GL: %s\n", description.c_str());
}

TEST(GlContext, SeveralContextsOneAfterAnotherAndAtOnce) {
  { const GlContext first; }
  const GlContext a;
  const GlContext b;  // both alive: the shared EGL display must not be terminated under a
  a.makeCurrent();
  EXPECT_NO_THROW(checkGlError("after switching contexts"));
  b.makeCurrent();
  EXPECT_EQ(a.renderer(), b.renderer());
}

// No window system and no environment at all (CI runners, `env -i`): EGL's surfaceless
// platform needs neither DISPLAY nor XDG_RUNTIME_DIR.
TEST(GlContext, OpensWithAnEmptyEnvironment) {
  const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
  const std::string command =
      "env -i '" + self + "' --gtest_filter=GlContext.OpensGl45CoreHeadless > /dev/null 2>&1";
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
}

}  // namespace
}  // namespace surftrace::gl
