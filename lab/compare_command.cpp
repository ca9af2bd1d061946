// loom-lab compare: image error figures between a render and a reference.

#include <cmath>
#include <cstdio>

#include "core/image/image.h"
#include "core/metrics/image_metrics.h"
#include "lab/lab_command.h"

namespace loom::lab {

LabCommand AddCompareCommand(CLI::App& app, const LabFlags& flags) {
  struct Options {
    std::string test, reference, heat_map;
    double heat_scale = 0.0;
  };
  auto options = std::make_shared<Options>();
  auto* command = app.add_subcommand(
      "compare", "Compare an image with a reference on linear radiance: RMSE, PSNR, SSIM (perceptual error = 1 - SSIM)");
  command->add_option("image", options->test, "Image to judge (EXR or PNG)")->required();
  command->add_option("reference", options->reference, "Reference image")->required();
  command->add_option("--heatmap", options->heat_map, "Write a per-pixel error heat-map PNG");
  command->add_option("--heatmap-scale", options->heat_scale, "Error shown as white (default: the largest)")
      ->check(CLI::NonNegativeNumber);
  return {command, [&flags, options] {
            const Image test = ReadImage(options->test);
            const Image reference = ReadImage(options->reference);
            const ImageComparison result = CompareImages(test, reference);
            if (!options->heat_map.empty()) {
              WriteImage(ErrorHeatMap(test, reference, options->heat_scale), options->heat_map);
            }
            if (flags.json) {
              // JSON has no infinity or NaN: identical images report psnr_db null, and
              // images with non-finite pixels null figures (non_finite_pixels > 0).
              const auto number = [](double value) {
                return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json();
              };
              nlohmann::json figures = {{"rmse", number(result.rmse)},
                                        {"psnr_db", number(result.psnr_db)},
                                        {"ssim", number(result.ssim)},
                                        {"perceptual_error", number(1.0 - result.ssim)},
                                        {"mean_ratio", number(result.mean_ratio)},
                                        {"peak", result.peak},
                                        {"width", result.width},
                                        {"height", result.height},
                                        {"non_finite_pixels", result.non_finite_pixels}};
              if (!options->heat_map.empty()) figures["heatmap"] = options->heat_map;
              PrintJson(figures);
            } else {
              std::printf("RMSE %.6g  PSNR %.2f dB  SSIM %.4f (perceptual error %.4f)  mean ratio %.4f  %dx%d, peak %.4g\n",
                          result.rmse, result.psnr_db, result.ssim, 1.0 - result.ssim, result.mean_ratio, result.width,
                          result.height, result.peak);
              if (result.non_finite_pixels > 0) {
                std::printf("%zu pixel(s) NaN or Inf: the figures are undefined\n", result.non_finite_pixels);
              }
            }
            return 0;
          }};
}

}  // namespace loom::lab
