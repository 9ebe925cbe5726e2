// The GPU records: C++ struct offsets against what the linked GLSL programs report, and the packing.
#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include "build/patch_list.hpp"
#include "gl/gl_context.hpp"
#include "gl/gl_renderer.hpp"
#include "gl/gpu_kinds.hpp"
#include "gl/gpu_layout.hpp"

namespace surftrace::gl {
namespace {

struct Member {
  const char* name;
  GLint offset;
};

GLint resourceProperty(GLuint program, GLenum interface, const std::string& name, GLenum property) {
  const GLuint index = glGetProgramResourceIndex(program, interface, name.c_str());
  if (index == GL_INVALID_INDEX) return -1;
  GLint value = -1;
  glGetProgramResourceiv(program, interface, index, 1, &property, 1, nullptr, &value);
  return value;
}

TEST(GlLayout, StorageRecordsMatchStd430) {
  const GlContext context;
  const GlRenderer renderer(context);
  const GLuint torus = renderer.program(view::PatchKind::Toroidal);
  const Member torusMembers[] = {{"tori[0].centerR", offsetof(GpuTorus, centerR)},
                                 {"tori[0].axisRp", offsetof(GpuTorus, axisRp)},
                                 {"tori[0].e1Phi", offsetof(GpuTorus, e1Phi)},
                                 {"tori[0].theta", offsetof(GpuTorus, theta)}};
  for (const Member& m : torusMembers)
    EXPECT_EQ(resourceProperty(torus, GL_BUFFER_VARIABLE, m.name, GL_OFFSET), m.offset) << m.name;
  EXPECT_EQ(resourceProperty(torus, GL_BUFFER_VARIABLE, "tori[0].centerR", GL_TOP_LEVEL_ARRAY_STRIDE),
            static_cast<GLint>(sizeof(GpuTorus)));
  EXPECT_EQ(resourceProperty(torus, GL_BUFFER_VARIABLE, "torusAtoms[0]", GL_ARRAY_STRIDE),
            static_cast<GLint>(sizeof(glm::uvec2)));

  const GLuint concave = renderer.program(view::PatchKind::Concave);
  const Member concaveMembers[] = {{"concaves[0].probeRp", offsetof(GpuConcave, probeRp)},
                                   {"concaves[0].dirIBegin", offsetof(GpuConcave, dirIBegin)},
                                   {"concaves[0].dirJCount", offsetof(GpuConcave, dirJCount)},
                                   {"concaves[0].dirK", offsetof(GpuConcave, dirK)}};
  for (const Member& m : concaveMembers)
    EXPECT_EQ(resourceProperty(concave, GL_BUFFER_VARIABLE, m.name, GL_OFFSET), m.offset) << m.name;
  EXPECT_EQ(resourceProperty(concave, GL_BUFFER_VARIABLE, "concaves[0].probeRp", GL_TOP_LEVEL_ARRAY_STRIDE),
            static_cast<GLint>(sizeof(GpuConcave)));
  EXPECT_EQ(resourceProperty(concave, GL_BUFFER_VARIABLE, "concaveAtoms[0]", GL_ARRAY_STRIDE),
            static_cast<GLint>(sizeof(glm::uvec4)));

  const GLuint skin = renderer.program(view::PatchKind::SkinFace);
  const Member skinMembers[] = {{"skins[0].centerBound", offsetof(GpuSkin, centerBound)},
                                {"skins[0].axisConstant", offsetof(GpuSkin, axisConstant)},
                                {"skins[0].coefficients", offsetof(GpuSkin, coefficients)},
                                {"skins[0].cell", offsetof(GpuSkin, cell)}};
  for (const Member& m : skinMembers)
    EXPECT_EQ(resourceProperty(skin, GL_BUFFER_VARIABLE, m.name, GL_OFFSET), m.offset) << m.name;
  EXPECT_EQ(resourceProperty(skin, GL_BUFFER_VARIABLE, "skins[0].centerBound", GL_TOP_LEVEL_ARRAY_STRIDE),
            static_cast<GLint>(sizeof(GpuSkin)));
  EXPECT_EQ(resourceProperty(skin, GL_BUFFER_VARIABLE, "skinAtoms[0]", GL_ARRAY_STRIDE),
            static_cast<GLint>(sizeof(glm::uvec4)));
  // The skin's atoms (GpuPatches::skinAtoms): a header of three vec4, then one vec4 per atom.
  EXPECT_EQ(resourceProperty(skin, GL_BUFFER_VARIABLE, "skinGridReach", GL_OFFSET), 32);
  EXPECT_EQ(resourceProperty(skin, GL_BUFFER_VARIABLE, "skinBalls[0]", GL_OFFSET), 48);
  EXPECT_EQ(resourceProperty(skin, GL_BUFFER_VARIABLE, "skinBalls[0]", GL_ARRAY_STRIDE),
            static_cast<GLint>(sizeof(glm::vec4)));

  const GLuint sphere = renderer.program(view::PatchKind::Convex);
  EXPECT_EQ(resourceProperty(sphere, GL_BUFFER_VARIABLE, "spheres[0]", GL_ARRAY_STRIDE),
            static_cast<GLint>(sizeof(GpuSphere)));
  EXPECT_EQ(resourceProperty(sphere, GL_BUFFER_VARIABLE, "sphereAtoms[0]", GL_ARRAY_STRIDE),
            static_cast<GLint>(sizeof(std::uint32_t)));
  EXPECT_EQ(resourceProperty(sphere, GL_BUFFER_VARIABLE, "atomColors[0]", GL_ARRAY_STRIDE),
            static_cast<GLint>(sizeof(glm::vec4)));

  // The bindings the renderer binds its buffers to: each kind's records and atoms to the
  // same two slots (bound per draw), the atom colours and fragment counts to their own.
  const struct {
    GLuint program;
    const char* block;
    GLint binding;
  } blocks[] = {{sphere, "Spheres", kRecordBinding},       {sphere, "SphereAtoms", kAtomBinding},
                {torus, "Tori", kRecordBinding},           {torus, "TorusAtoms", kAtomBinding},
                {concave, "Concaves", kRecordBinding},     {concave, "ConcaveAtoms", kAtomBinding},
                {skin, "Skins", kRecordBinding},           {skin, "SkinAtoms", kAtomBinding},
                {skin, "SkinBalls", kSkinAtomBinding},     {skin, "SkinGridCells", kSkinGridBinding},
                {sphere, "AtomColors", kAtomColorBinding}, {torus, "FragmentCounts", kFragmentCountBinding}};
  for (const auto& b : blocks)
    EXPECT_EQ(resourceProperty(b.program, GL_SHADER_STORAGE_BLOCK, b.block, GL_BUFFER_BINDING), b.binding) << b.block;
}

TEST(GlLayout, FrameBlockMatchesStd140) {
  const GlContext context;
  const GlRenderer renderer(context);
  const GLuint program = renderer.program(view::PatchKind::Toroidal);
  const GLint kinds = offsetof(GpuFrame, kinds);
  const Member members[] = {{"frame.eyeProjection", offsetof(GpuFrame, eyeProjection)},
                            {"frame.forwardTan", offsetof(GpuFrame, forwardTan)},
                            {"frame.rightAspect", offsetof(GpuFrame, rightAspect)},
                            {"frame.upHalfHeight", offsetof(GpuFrame, upHalfHeight)},
                            {"frame.viewport", offsetof(GpuFrame, viewport)},
                            {"frame.lighting", offsetof(GpuFrame, lighting)},
                            {"frame.background", offsetof(GpuFrame, background)},
                            {"frame.kinds[0].color", kinds + static_cast<GLint>(offsetof(GpuKind, color))},
                            {"frame.kinds[0].first", kinds + static_cast<GLint>(offsetof(GpuKind, first))},
                            {"frame.kinds[1].color", kinds + static_cast<GLint>(sizeof(GpuKind))},
                            {"frame.shading", offsetof(GpuFrame, shading)},
                            {"frame.torusTrace", offsetof(GpuFrame, torusTrace)},
                            {"frame.traceParams", offsetof(GpuFrame, traceParams)},
                            {"frame.keyLight", offsetof(GpuFrame, keyLight)},
                            {"frame.fillLight", offsetof(GpuFrame, fillLight)},
                            {"frame.lightMaps", offsetof(GpuFrame, lightMaps)},
                            {"frame.lightMapScale", offsetof(GpuFrame, lightMapScale)}};
  for (const Member& m : members) EXPECT_EQ(resourceProperty(program, GL_UNIFORM, m.name, GL_OFFSET), m.offset) << m.name;
  EXPECT_EQ(resourceProperty(program, GL_UNIFORM_BLOCK, "Frame", GL_BUFFER_DATA_SIZE), static_cast<GLint>(sizeof(GpuFrame)));
  EXPECT_EQ(resourceProperty(program, GL_UNIFORM_BLOCK, "Frame", GL_BUFFER_BINDING), static_cast<GLint>(kFrameBinding));
}

// The origin shift happens in double, before rounding: a molecule 1e4 Å from the origin
// keeps its sub-milliångström detail, and the clipping planes move with it.
TEST(GlLayout, PackingShiftsInDoubleBeforeRounding) {
  build::PatchList list;
  list.params.probeRadius = 1.5;
  const glm::dvec3 origin(1e4, -2e4, 3e4);
  list.convex.center = {origin + glm::dvec3(1.0001234, 0.0, 0.0)};
  list.convex.radius = {1.7};
  list.convex.atom = {7};
  list.concave.probe = {origin + glm::dvec3(0.0, 2.0000321, 0.0)};
  list.concave.dirI = {{1, 0, 0}};
  list.concave.dirJ = {{0, 1, 0}};
  list.concave.dirK = {{0, 0, 1}};
  list.concave.atomI = {1};
  list.concave.atomJ = {2};
  list.concave.atomK = {3};
  list.concave.clipBegin = {0};
  list.concave.clipCount = {1};
  // Keep x·(0,0,1) − (origin.z + 0.5) <= 0, i.e. z' <= 0.5 after the shift.
  list.clipPlanes = {{0.0, 0.0, 1.0, -(origin.z + 0.5)}};
  const GpuPatches g = packPatches(list, origin);
  const auto& spheres = g.of<GpuSphereKind>();
  const auto& concave = g.of<GpuConcaveKind>();
  ASSERT_EQ(spheres.records.size(), 1u);
  EXPECT_FLOAT_EQ(spheres.records[0].x, 1.0001234f);
  EXPECT_FLOAT_EQ(spheres.records[0].w, 1.7f);
  EXPECT_EQ(spheres.atoms[0], 7u);
  ASSERT_EQ(concave.records.size(), 1u);
  EXPECT_FLOAT_EQ(concave.records[0].probeRp.y, 2.0000321f);
  EXPECT_FLOAT_EQ(concave.records[0].probeRp.w, 1.5f);
  EXPECT_EQ(concave.records[0].dirIBegin.w, 0.0f);
  EXPECT_EQ(concave.records[0].dirJCount.w, 1.0f);
  EXPECT_EQ(concave.atoms[0], glm::uvec4(1, 2, 3, 0));
  ASSERT_EQ(g.clipPlanes.size(), 1u);
  EXPECT_FLOAT_EQ(g.clipPlanes[0].w, -0.5f);
  // A skin patch: shifted in double, its cell planes after the SES clipping planes, its kind code.
  list.mss.kind = {static_cast<std::uint32_t>(build::MssKind::Edge)};
  list.mss.center = {origin + glm::dvec3(0.0, 0.0, 3.0000123)};
  list.mss.axis = {{0, 0, 1}};
  list.mss.radialCoeff = {0.5};
  list.mss.axialCoeff = {-1.0};
  list.mss.constant = {-0.25};
  list.mss.boundRadius = {2.0};
  list.mss.atoms = {glm::uvec4(4, 9, ~0u, ~0u)};
  list.mss.cellBegin = {0};
  list.mss.cellCount = {1};
  list.cellPlanes = {{0.0, 0.0, 1.0, -(origin.z + 4.0)}};
  const GpuPatches withSkin = packPatches(list, origin);
  const auto& edges = withSkin.of<GpuSkinKind<build::MssKind::Edge>>();
  ASSERT_EQ(edges.records.size(), 1u);
  EXPECT_FLOAT_EQ(edges.records[0].centerBound.z, 3.0000123f);
  EXPECT_EQ(edges.records[0].cell.x, static_cast<std::uint32_t>(view::PatchKind::SkinEdge));
  EXPECT_EQ(edges.records[0].cell.y, 1u);  // after the one clipping plane
  EXPECT_EQ(edges.records[0].cell.z, 1u);
  EXPECT_EQ(edges.atoms[0], glm::uvec4(4, 9, ~0u, ~0u));
  ASSERT_EQ(withSkin.clipPlanes.size(), 2u);
  EXPECT_FLOAT_EQ(withSkin.clipPlanes[1].w, -4.0f);
  // No skin atoms: the header with count 0. With them: the count, then each vdW ball, shifted
  // in double, r² = s·w, and every atom once in the grid, in the cell that holds its centre.
  ASSERT_EQ(withSkin.skinAtoms.size(), 3u);
  EXPECT_EQ(std::bit_cast<std::uint32_t>(withSkin.skinAtoms[0].x), 0u);
  list.params.shrinkFactor = 0.25;
  for (int i = 0; i < 10; ++i) {
    list.skinAtoms.center.push_back(origin + glm::dvec3(0.0, 0.0, 1.0000123 * i));
    list.skinAtoms.weight.push_back(4.0 * i);
  }
  const GpuPatches withAtoms = packPatches(list, origin);
  ASSERT_EQ(withAtoms.skinAtoms.size(), 13u);
  EXPECT_EQ(std::bit_cast<std::uint32_t>(withAtoms.skinAtoms[0].x), 10u);
  EXPECT_FLOAT_EQ(withAtoms.skinAtoms[3 + 9].z, 9.0001107f);
  EXPECT_FLOAT_EQ(withAtoms.skinAtoms[3 + 9].w, 9.0f);
  const glm::uvec3 dims(std::bit_cast<std::uint32_t>(withAtoms.skinAtoms[0].y), std::bit_cast<std::uint32_t>(withAtoms.skinAtoms[0].z),
                        std::bit_cast<std::uint32_t>(withAtoms.skinAtoms[0].w));
  const std::size_t cells = std::size_t{dims.x} * dims.y * dims.z;
  const glm::vec4 corner = withAtoms.skinAtoms[1];
  ASSERT_EQ(withAtoms.skinGrid.size(), cells + 1 + 10);
  std::vector<int> seen(10, 0);
  for (std::size_t c = 0; c < cells; ++c)
    for (std::uint32_t e = withAtoms.skinGrid[c]; e < withAtoms.skinGrid[c + 1]; ++e) {
      const std::uint32_t i = withAtoms.skinGrid[cells + 1 + e];
      ASSERT_LT(i, 10u);
      ++seen[i];
      const float z = withAtoms.skinAtoms[3 + i].z;
      EXPECT_EQ(c / (std::size_t{dims.x} * dims.y), std::min<std::size_t>(dims.z - 1, static_cast<std::size_t>((z - corner.z) / corner.w)));
    }
  EXPECT_EQ(seen, std::vector<int>(10, 1));
}

}  // namespace
}  // namespace surftrace::gl
