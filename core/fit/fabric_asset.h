#pragma once
// The cached fabric asset (DESIGN.md "Fabric asset"): a FittedFabric on disk as
// three files in one directory.
//
//   parameters.exr  the BRDF array: one pixel per texel, the fitted levels as the
//                   file's MIP levels (not a filtered copy). Channels, in order:
//                   rho.{R,G,B}; per lobe i: lobe<i>.{Cx,Cy,Cz,N}.{R,G,B}; normal.{X,Y,Z};
//                   tangent.{X,Y,Z}; rmse; status (TexelFitStatus as a number).
//   lut.exr         T and alpha per texel and view, RGBA: texel (x, y) is the k×k
//                   block at (x·k, y·k), view (col, row) of the k×k hemisphere grid
//                   (core/acquire/hemisphere_directions.h) at (x·k + col, y·k + row),
//                   so a GPU interpolates views bilinearly inside a block. MIP level j
//                   is fitted level j; OpenEXR wants MIP levels down to 1×1, so below
//                   the 1×1-texel level (k×k pixels) come point-sampled padding levels
//                   that no renderer reads (manifest "fitted_levels").
//   manifest.json   asset version, fabric key, settings, sizes, per-level fit
//                   statistics, timings, and each image's byte size and SHA-256.
//
// Half floats (settings.half_float) for both images; full floats otherwise.
// Every file is written to a temporary name and renamed, the manifest last, so a
// manifest only ever names complete images. Reading verifies both checksums
// before decoding; a mismatch is Error(kInvalidArgument) naming the file.

#include <cstdint>
#include <filesystem>
#include <string>

#include "core/fit/fabric_fit.h"
#include "core/methods/asset_files.h"
#include "core/spec/fabric_key.h"
#include "loom/v1/precompute.pb.h"

namespace loom {

// The layout above is version kAssetFormatVersion (core/spec/fabric_key.h), part
// of every fabric's cache key: changing the layout bumps it.

// Creates `directory` if needed. `settings` are recorded as given, with defaults
// applied.
void WriteFabricAsset(const FittedFabric& fabric, const v1::PrecomputeSettings& settings,
                      const std::string& fabric_key, const AssetSheet& directory);

// The fabric as written (to half-float precision where the asset is half float),
// statistics and timings included. Error(kNotFound) if a file is missing,
// Error(kInvalidArgument) if one is corrupted or inconsistent.
FittedFabric ReadFabricAsset(const AssetSheet& directory);

}  // namespace loom
