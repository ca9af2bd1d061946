#pragma once
// Image error metrics on linear radiance (DESIGN.md "Metrics"). Every figure of
// Loom's speed-versus-accuracy chart compares a render against the `reference`
// render of the same scene with these.
//
// - RMSE over the RGB channels.
// - PSNR = 10·log10(peak² / MSE) with peak = the reference's largest RGB value
//   (radiance has no fixed white; a frame of peak 1 gives the usual PSNR).
// - SSIM (Wang, Bovik, Sheikh, Simoncelli 2004) on luminance, 8×8 windows with
//   stride 4, C1 = (0.01·peak)², C2 = (0.03·peak)²; reported as mean SSIM and as
//   the perceptual error 1 − SSIM (0 = identical).
// - Non-finite pixels: a NaN or ±Inf in either image makes every figure above
//   meaningless (a NaN difference used to read as a zero error, PSNR +inf), so
//   they are counted and the figures reported as NaN.
// - Temporal flicker: the mean absolute luminance change between consecutive
//   frames of a camera move, after undoing the move's image shift; aliasing shows
//   up as flicker.

#include <cstddef>
#include <vector>

#include "core/image/image.h"

namespace loom {

struct ImageComparison {
  double rmse = 0.0;     // NaN when non_finite_pixels > 0, like PSNR and SSIM
  double psnr_db = 0.0;  // +inf when identical
  double ssim = 1.0;
  double peak = 0.0;     // over the reference's finite values
  // Mean RGB radiance of the test image over the reference's (NaN like the others;
  // +inf for a black reference under a non-black test).
  double mean_ratio = 1.0;
  int width = 0, height = 0;
  // Pixels with a NaN or ±Inf in an RGB channel of either image.
  size_t non_finite_pixels = 0;
};

// Throws Error(kInvalidArgument) if the sizes differ or an image has < 3 channels.
ImageComparison CompareImages(const Image& test, const Image& reference);

// Per-pixel RGB error magnitude mapped through a perceptually ordered colour ramp
// (black → blue → magenta → yellow → white); `scale` is the error shown as white
// (0 = the largest error in the image).
Image ErrorHeatMap(const Image& test, const Image& reference, double scale = 0.0);

// Mean over pixels and frame pairs of |Y(frame k+1)(x) − Y(frame k)(x − shift)|,
// with shift = (dx, dy) pixels between consecutive frames; pixels whose shifted
// partner falls outside are skipped.
double TemporalFlicker(const std::vector<Image>& frames, int dx, int dy);

double Luminance(const Image& image, int x, int y);

}  // namespace loom
