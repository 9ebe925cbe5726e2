// The GPU records, the per-frame block and the resource bindings, declared once for C++ and GLSL.
//
// Written in the subset of C both languages read (as OSPRay's *Shared.h between C++ and
// ISPC): gl/gpu_layout.hpp includes it with vec4, uvec4 and uint standing for the glm types,
// every GLSL stage has it pasted in first (src/gl/CMakeLists.txt). std430 records, std140
// block; gpu_layout.hpp static_asserts the sizes, tests/gl/gl_layout_test.cpp checks the
// offsets GL reports. No preprocessor lines: GLSL would need an include extension for them.

// Buffers every program reads, and the two slots a kind's own buffers are bound to before
// its draw: each program sees its kind's records and atoms and no other kind's.
const int kFrameBinding = 0;          // uniform block Frame (std140)
const int kAtomColorBinding = 0;      // vec4 atomColors[]
const int kFragmentCountBinding = 1;  // uint fragmentCounts[2 n]: fragments shaded, hits (statistics only)
const int kRecordBinding = 2;         // the kind's records: vec4 spheres[], GpuTorus tori[], GpuConcave concaves[], GpuSkin skins[],
                                      // vec4 balls[], vec4 sticks[2 n] (a, radius; b, unused)
const int kAtomBinding = 3;           // the kind's atoms: uint, uvec2 (i, j), uvec4 (i, j, k, unused); balls uint, sticks uvec2
const int kClipPlaneUnit = 0;         // samplerBuffer clipPlanes (RGBA32F: n, w): SES clipping, then MSS cell planes
// Depth peeling (transparency, gl_renderer.cpp): the pass's block, the previous layer's and the
// opaque geometry's ray distance t per pixel, and the spheres' blockers (build/sphere_blockers.hpp).
const int kPeelBinding = 1;           // uniform block Peel (std140)
const int kPreviousLayerUnit = 1;     // sampler2D previousLayer (R: t of layer k − 1, +inf where none)
const int kOpaqueDepthUnit = 2;       // sampler2D opaqueDepth (R: t of the opaque geometry, +inf where none)
const int kBlockerBinding = 4;        // vec4 blockers[]: centre (origin-shifted), grown radius; then the saddle arcs, 3 each
const int kBlockerListBinding = 5;    // uint blockerList[]: CSR begin[n + 1] (offsets into this array), the arcs' CSR
                                      // arcBegin[n + 1] (indices into blockers[]), then the lists
const int kSkinAtomBinding = 6;       // the skin's atoms: uvec4 (count, grid cells along x, y, z), vec4 (grid corner, cell
                                      // edge), vec4 (largest radius, unused), then vec4 balls[] (centre, r²)
const int kSkinGridBinding = 7;       // uint skinGridCells[]: CSR cellStart[cells + 1], then the atoms of each cell
const int kLayerColorUnit = 3;        // sampler2D layerColor: the colour a peel wrote (peel.glsl)
const int kLayerDepthUnit = 4;        // sampler2D layerDepth (R: t, +inf where the peel wrote nothing)
const int kAccumulatedUnit = 5;       // sampler2D accumulated: Σ α(1 − α)^k c_k, coverage 1 − (1 − α)^n
const int kOpaqueColorUnit = 6;       // sampler2D opaqueColor: the opaque geometry's colour, alpha its coverage
// The light maps of --lighting soft and full (gl_renderer.cpp, renderLightMaps): one
// orthographic depth map of the whole scene per light direction, layers of one texture array.
const int kLightMapBinding = 8;       // GpuLightMap lightMaps[]: the key light's maps, then the ambient ones
const int kLightMapUnit = 7;          // sampler2DArray lightDepth (depth 32F, texelFetch)

// The `patch.kind` codes: view::PatchKind's, the one table (gl/gpu_kinds.hpp static_asserts they
// agree); the frame's kinds[code − 1] is the kind's row.
const uint kConvexKind = 1u;
const uint kToroidalKind = 2u;
const uint kConcaveKind = 3u;
const uint kSkinConvexKind = 4u;   // the molecular skin: kSkinConvexKind + MssKind
const uint kBallKind = 8u;         // the ball-and-stick model, drawn before the surface
const uint kStickKind = 9u;
const int kKindCount = 9;

// A saddle in four vectors: the torus, its frame and the patch limits (ORACLES A.3).
struct GpuTorus {
  vec4 centerR;  // centre c, big radius R
  vec4 axisRp;   // unit axis n (atom i → j), tube (probe) radius rp
  vec4 e1Phi;    // unit e1 ⊥ n (φ = 0), φ extent in (0, 2π]
  vec4 theta;    // θi, θj, unused, unused
};

// A concave triangle in four vectors: the probe and its three contact directions (ORACLES
// A.4). Its clipping planes are texels [clipBegin, clipBegin + clipCount) of the clip-plane
// texture buffer; the indices are stored as floats, exact below 2²⁴ (checked at upload).
struct GpuConcave {
  vec4 probeRp;    // probe centre p, probe radius rp
  vec4 dirIBegin;  // unit contact direction u_i, clipBegin
  vec4 dirJCount;  // u_j, clipCount
  vec4 dirK;       // u_k, unused
};

// A molecular-skin patch in four vectors (ORACLES C.3): the quadric
// f = radial |x − c|² + axial ((x − c)·a)² + constant inside the bounding ball and the mixed
// cell, whose planes are texels [cellBegin, cellBegin + cellCount) of the clip-plane buffer
// (after the SES clipping planes).
// The rasterised primitive: spheres (convex, concave) the screen rectangle of their sphere,
// hyperboloids the box [hLo, hHi] along a times the square of half-side rhoMax across it,
// which holds the patch (caps and bounding ball; build's quadric, gpu_kinds.cpp).
struct GpuSkin {
  vec4 centerBound;    // centre c (origin-shifted), bounding-ball radius
  vec4 axisConstant;   // unit axis a, constant
  vec4 coefficients;   // radial, axial, hLo, hHi
  uvec4 cell;          // kind code (kSkinConvexKind + MssKind), cellBegin, cellCount, rhoMax (float bits)
};

// What the shaders need of a kind: its colour and where its global patch ids start.
struct GpuKind {
  vec4 color;   // rgb: view::kPatchKinds colour, a = 1
  uvec4 first;  // x: global id of the kind's first patch (view::PatchIdOrder), yzw unused
};

// Everything that changes per frame but not per patch: camera, shading, depth mapping.
struct GpuFrame {
  vec4 eyeProjection;  // eye (origin-shifted), projection (0 perspective, 1 orthographic)
  vec4 forwardTan;     // unit forward, tan(fovY/2)
  vec4 rightAspect;    // unit right, W/H
  vec4 upHalfHeight;   // unit true up, orthoHeight/2
  vec4 viewport;       // W, H, near plane of the rasterised boxes (Å), 1/(depth range in Å)
  vec4 lighting;       // ambient, diffuse, specular, shininess
  vec4 background;     // rgb, unused
  GpuKind kinds[kKindCount];
  uvec4 shading;       // colour by kind (0) or by atom (1), atom colours, model (0 headlight, 1 key-fill), unused
  uvec4 torusTrace;    // torus method (0 quartic, 1 sphere tracing), max steps, plain march (1), unused
  vec4 traceParams;    // sphere-tracing stop distance (Å), primitive (0 box, 1 cylinder), count fragments (1), unused
  // The key-fill model (view::Lighting, shading.z = 1): unit directions towards the lights.
  vec4 keyLight;       // key direction, unused
  vec4 fillLight;      // fill direction, fill weight
  // Soft shadows and ambient occlusion from the light maps (lightMaps[], lightDepth): none
  // when both counts are 0 (S = A = 1).
  uvec4 lightMaps;     // key-light maps, ambient maps, unused, unused
  vec4 lightMapScale;  // unused, depth units per Å, unused, unused
};

// One light map: x (origin-shifted) lands on texel coordinates (u, v) in [0, 1]² and is at
// depth r = dot(toMapZ.xyz, x) + toMapZ.w from the light's side, in the map's depth units; the
// map stores the depth of the surface nearest the light there.
struct GpuLightMap {
  vec4 toMapX;     // u = dot(xyz, x) + w, in the map's texels (texel k's centre at k + 0.5)
  vec4 toMapY;     // v = dot(xyz, x) + w, likewise
  vec4 toMapZ;     // r = dot(xyz, x) + w, depth units
  vec4 direction;  // unit direction towards the light, the map's texel side (Å)
};

// One depth-peeling pass. All zero: the opaque draw, every hit in t > 0 counts.
struct GpuPeel {
  uvec4 flags;   // x: a previous layer bounds the hits (pass k >= 1), y: an opaque depth (and
                 // colour) bounds them, z: clip the spheres to their convex patches,
                 // w: peel.glsl's step (0 composite a layer, 1 resolve over the opaque colour)
  vec4 merge;    // x: merge distance (Å) at t = 0, y: its growth per Å of t, z: the spheres' grow
                 // distance g (build::SphereBlockers), w: the opacity α
};

