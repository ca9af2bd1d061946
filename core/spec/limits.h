#pragma once
// Every cap on what a spec may ask for. A spec arrives from a file or over the
// network, so anything that drives memory or time is bounded here, in one place for
// the docs, the validator and the tests. core/spec/validate.h enforces the caps on
// spec fields; loaders enforce the rest (kMaxMeshTriangles).

#include <cstddef>
#include <cstdint>

namespace loom {

// --- Names and lists --------------------------------------------------------

// Names end up in logs, file names and UI labels; longer is a mistake or abuse.
inline constexpr int kMaxNameLength = 256;
// Mesh paths (client side only); PATH_MAX on Linux.
inline constexpr int kMaxPathLength = 4096;

// --- PrecomputeSettings -------------------------------------------------------

// The BRDF array is resolution² texels per level; 2 is the smallest with a mip chain.
inline constexpr uint32_t kMinSpatialResolution = 2;
// 256² texels × lobes × RGB parameters is already hundreds of MiB per fabric.
inline constexpr uint32_t kMaxSpatialResolution = 256;
// Directions lie on a k×k grid interpolated bilinearly: 2×2 is the smallest grid.
inline constexpr uint32_t kMinDirections = 4;
// A 64×64 grid; finer grids cost acquisition time without visible gain.
inline constexpr uint32_t kMaxDirections = 4096;
// Daubert 2001 fits 1-3 Lafortune lobes; the shader evaluates at most 3.
inline constexpr uint32_t kMinLobes = 1;
inline constexpr uint32_t kMaxLobes = 3;
// spatial_resolution² × view_directions × light_directions: the radiance samples
// acquisition computes and fitting keeps in memory (1<<26 RGB floats = 768 MiB).
inline constexpr uint64_t kMaxRadianceSamples = uint64_t{1} << 26;
// The LUT alternation stops below this mean change; above 10 it would never run.
inline constexpr float kMaxLutChangeThreshold = 10.0f;
// Lobe/LUT alternation converges in a handful of rounds; 100 bounds a runaway fit.
inline constexpr uint32_t kMaxAlternations = 100;
// Levenberg-Marquardt iterations per lobe fit; bounds fitting time per texel.
inline constexpr uint32_t kMaxLmIterations = 1000;
// Indirect diffuse bounces between yarns; each bounce multiplies acquisition cost.
inline constexpr uint32_t kMaxIndirectBounces = 2;
// n×n rays per texel; 8×8 = 64 rays is far past visible convergence.
inline constexpr uint32_t kMaxSupersampling = 8;
// The tabulated method keeps every sample, per level, in memory, in its file and on
// the GPU (RGB): at this cap ~400 MB each as 32-bit floats; factored and neural hold them
// while they build. Their defaults, 81 views × 64 lights over 64² texels, are ~0.63 of it.
inline constexpr uint64_t kMaxTabulatedSamples = uint64_t{1} << 25;
// The factored method's terms per texel: each costs a texture fetch per light and
// fragment, and as much memory as the rank-1 asset.
inline constexpr uint32_t kMaxFactoredRank = 8;
// The neural method's latent numbers per texel (each four a texture fetch per
// fragment and level) and its decoder's hidden width (its weights live in one
// uniform block, which GL guarantees only 16 KiB: 64 wide with 16 channels is
// ~22 KiB, within what Mesa and NVIDIA give, 64 KiB; the upload checks).
inline constexpr uint32_t kMaxNeuralChannels = 16;
inline constexpr uint32_t kMaxNeuralHidden = 64;
// Frequencies of the decoder's direction encoding: each adds 8 inputs and 8 sines
// and cosines per light and fragment.
inline constexpr uint32_t kMaxNeuralFrequencies = 4;
// Training steps bound the precompute's time: a step is 1024 samples.
inline constexpr uint32_t kMaxNeuralSteps = 1000000;

// --- FabricSpec ----------------------------------------------------------------

// One colour/material per yarn; the asset stores per-texel parameters, not yarn ids,
// but acquisition shades every yarn and the tile must stay small.
inline constexpr int kMinYarns = 1;
inline constexpr int kMaxYarns = 16;
// Yarn radius as a fraction of the yarn pitch (woven): above 0.5 neighbouring
// yarns interpenetrate.
inline constexpr float kMaxYarnRadius = 0.5f;
// Yarn radius as a fraction of the loop width (knit): where loops interlock, four
// yarns cross at one height and depth within a wale, so round yarns jam near 1/8 of
// the loop width; Loom's loops hold 0.08 at every loop aspect without the yarns
// passing through each other (core/fabric/knit_tile.h).
inline constexpr float kMaxKnitYarnRadius = 0.08f;
// Plies twisted into one yarn; each ply is its own swept tube.
inline constexpr uint32_t kMaxPlies = 8;
// Ply twist angle in degrees, either handedness.
inline constexpr float kMaxTwistDegrees = 90.0f;
// Microflake yarn shading: the height-field scaling β of the neural woven paper's
// Table 2 (sampled there in [0, 2]).
inline constexpr float kMaxHeightScale = 2.0f;
// Energy conservation: diffuse + specular albedo per channel may exceed 1 by float
// rounding only (0.96 + 0.04 is not exactly 1 in float).
inline constexpr float kAlbedoSumTolerance = 1e-5f;

// Knit rib widths (columns of knit, then of purl).
inline constexpr uint32_t kMaxRibWidth = 16;
// Loops per tile side (wales across, courses down); the tile is one periodic unit.
inline constexpr uint32_t kMaxLoopsPerTileSide = 32;
// Loop width : height. Real knits run about 1.2-1.5; below 0.5 the key-point loop
// model degenerates, and above 1.5 the head of one course comes so close to the
// sinker two courses up that random loop offsets make the yarns touch.
inline constexpr float kMinLoopAspect = 0.5f;
inline constexpr float kMaxLoopAspect = 1.5f;
// Loop jitter (standard deviation of key-point offsets) in yarn radii: at the
// thickest knit yarn, 0.1 keeps 13% clearance between loops, 0.2 already touches.
inline constexpr float kMaxLoopJitter = 0.1f;

// Twill floats: n over, m under.
inline constexpr uint32_t kMinTwillFloat = 1;
inline constexpr uint32_t kMaxTwillFloat = 16;
// Satin repeat: 5 is the smallest n with a valid move (1 < m < n-1, gcd(m, n) = 1).
inline constexpr uint32_t kMinSatinRepeat = 5;
inline constexpr uint32_t kMaxSatinRepeat = 32;
// Basket weave: yarns grouped per interlacing.
inline constexpr uint32_t kMinBasketGroup = 1;
inline constexpr uint32_t kMaxBasketGroup = 8;
// Crimp angle; past 60 degrees the yarns would stand on end.
inline constexpr float kMaxInclinationDegrees = 60.0f;
// Gap ratio is in [0, 0.9): at 1 the yarns would vanish.
inline constexpr float kMaxGapRatio = 0.9f;
// Warp/weft colour lists and knit colour patterns repeat across one tile.
inline constexpr int kMaxColourListLength = 256;

// --- SceneSpec -----------------------------------------------------------------

// Objects per scene: one draw call and one fabric binding each.
inline constexpr int kMinObjects = 1;
inline constexpr int kMaxObjects = 64;
// Lights per scene: the svbrdf shader loops over them, each may own a shadow map.
inline constexpr int kMaxLights = 16;
// Built-in shape tessellation; 1024² quads is already 2M triangles.
inline constexpr uint32_t kMaxSegments = 1024;
// Triangles of a scene's meshes, every object's together (OBJ uploads and
// tessellated built-ins); bounds the memory of a parse and of the GPU's buffers
// (docs/operations.md "Limits").
inline constexpr int64_t kMaxMeshTriangles = 4'000'000;
// Vertices of a scene's meshes together, and each OBJ's positions, texture
// coordinates and normals.
inline constexpr int64_t kMaxMeshVertices = 4'000'000;
// One line of an OBJ file (a face of ~50k corners).
inline constexpr size_t kMaxObjLineBytes = size_t{1} << 20;
// Tile repeats across the UV square; beyond this a tile is far below a pixel.
inline constexpr float kMaxRepeat = 4096.0f;
// Perspective field of view in degrees: (0, 170); at 180 the projection is singular.
inline constexpr float kMaxFovDegrees = 170.0f;

// --- RenderSettings ------------------------------------------------------------

// Frame side in pixels: the largest GL renderbuffer every target supports.
inline constexpr uint32_t kMaxImageSide = 8192;
// Pixels per frame (8192×4096): bounds framebuffer and readback memory.
inline constexpr uint64_t kMaxImagePixels = uint64_t{8192} * 4096;
// MSAA sample counts GL implementations offer; any power of two up to this.
inline constexpr uint32_t kMaxMsaaSamples = 16;
// RENDER_METHOD_LUMISLICE takes msaa_samples as rays a pixel on the nearest square
// grid (1, 2 → 1×1; 4 → 2×2; 8 → 3×3; 16 → 4×4): the grid's side. It renders the frame
// that many times wider and higher, within kMaxImageSide and kMaxImagePixels.
constexpr uint32_t LumisliceRayGrid(uint32_t msaa_samples) {
  uint32_t side = 1;
  while ((side + 1) * (side + 1) <= msaa_samples) ++side;
  return msaa_samples - side * side > (side + 1) * (side + 1) - msaa_samples ? side + 1 : side;
}
// Shadow-map side in texels.
inline constexpr uint32_t kMinShadowMapSize = 256;
inline constexpr uint32_t kMaxShadowMapSize = 8192;
// Reference renderer samples per pixel; bounds ray-tracing time per frame.
inline constexpr uint32_t kMaxReferenceSamples = 4096;
// svbrdf level-of-detail bias in levels: beyond it a frame shows level 0 or the
// coarsest level wherever a texel is within 16× a pixel.
inline constexpr float kMaxLodBias = 4.0f;

// --- AnimationSpec ---------------------------------------------------------------

// Loops a side of an animated cloth, and loops in all: each is a mass point the
// simulation steps thousands of times a second of animation.
inline constexpr uint32_t kMinClothLoops = 2;
inline constexpr uint32_t kMaxClothLoops = 2048;
inline constexpr uint64_t kMaxClothPoints = 262144;
// Rest loop spacing in the simulation's units (a loop is 1).
inline constexpr float kMaxLoopSpacing = 100.0f;
// Positions, collider sizes and speeds (loops, loops/s): far beyond them float
// positions lose the field's fraction of a loop.
inline constexpr float kMaxAnimationCoordinate = 100000.0f;
inline constexpr float kMaxColliderSize = 10000.0f;
inline constexpr float kMaxBallMass = 1e6f;  // in loop masses
inline constexpr float kMaxAnimationSpeed = 1000.0f;
inline constexpr int kMaxPins = 4096;
inline constexpr int kMaxColliders = 64;
// Legs of a pin's or a collider's motion.
inline constexpr int kMaxMotionLegs = 64;
// The knit model's constants a spec may set (KnitMechanicsSpec; the lower bounds
// are 0).
inline constexpr float kMaxContactDamping = 1000.0f;  // 1/s
inline constexpr float kMaxFriction = 10.0f;
inline constexpr float kMaxAirViscosity = 100.0f;  // 1/s
inline constexpr float kMaxCourant = 1.0f;
// Simulated seconds and frames. The glTF sequence holds a morph target a frame
// and, a frame, a weight for every target (frames² floats: 36 MB at the cap).
inline constexpr float kMaxAnimationSeconds = 600.0f;
inline constexpr float kMaxFramesPerSecond = 120.0f;
inline constexpr uint64_t kMaxAnimationFrames = 3000;
// Frames × loops: the sequence's points, kept in memory and written out
// (12 bytes each: 805 MB at the cap).
inline constexpr uint64_t kMaxAnimationPoints = uint64_t{1} << 26;

}  // namespace loom
