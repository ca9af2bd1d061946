// The fit on real samples: the standard knit's radiance samples (reduced in size so
// the test stays fast) rather than synthetic ones.

#include <gtest/gtest.h>

#include "core/acquire/acquisition.h"
#include "core/fabric/fabric_tile.h"
#include "core/fit/texel_fit.h"
#include "core/spec/spec_json.h"

namespace loom {
namespace {

// Daubert §5: the lobe fit and the LUT update alternate "until the average
// difference of the previous lookup table's entries to the new one's is below a
// certain threshold". On the standard knit every channel of every texel gets there
// or uses up its rounds, and the change never grows from one round to the next
// (a longer step than the last is shortened: UpdateLut); the printed count of
// shortened rounds says how often that acts.
TEST(StandardKnitFit, AlternationConvergesOnEveryTexel) {
  v1::PrecomputeSettings settings;
  settings.set_spatial_resolution(8);
  settings.set_view_directions(36);
  settings.set_light_directions(36);
  settings.set_supersampling(1);
  settings.set_lut_change_threshold(1e-3f);  // tight, so the sequences are long
  settings.set_max_alternations(8);
  const RadianceSamples samples =
      Acquire(BuildFabricTile(ParseSpecJson<v1::FabricSpec>(R"({"knit": {}})", "fabric")), settings);
  const TexelFitOptions options = MakeTexelFitOptions(settings);

  size_t sequences = 0, multi_round = 0, capped_rounds = 0;
  for (size_t texel = 0; texel < samples.texel_count(); ++texel) {
    const glm::vec3 n = samples.normals[texel];
    const glm::vec3 t = samples.tangents[texel];
    const TexelFrame frame(n, t);
    TexelSamples texel_samples(static_cast<uint32_t>(samples.view_count()));
    for (size_t view = 0; view < samples.view_count(); ++view) {
      if (samples.alpha[samples.AlphaIndex(texel, view)] <= 0.0f) continue;
      for (size_t light = 0; light < samples.light_count(); ++light) {
        texel_samples.Add(frame.ToLocal(samples.light_directions[light]), frame.ToLocal(samples.view_directions[view]),
                          static_cast<uint32_t>(view), samples.radiance[samples.RadianceIndex(texel, view, light)]);
      }
    }
    const TexelFit fit = FitTexel(texel_samples, options);
    for (const std::vector<double>& changes : fit.lut_changes) {
      if (changes.empty()) continue;
      ++sequences;
      if (changes.size() > 2) ++multi_round;
      for (size_t i = 1; i < changes.size(); ++i) {
        EXPECT_LE(changes[i], changes[i - 1] * (1.0 + 1e-9)) << "texel " << texel << " round " << i;
        if (changes[i] >= changes[i - 1] * (1.0 - 1e-9)) ++capped_rounds;
      }
      // It stopped because it converged, or because it ran out of rounds.
      EXPECT_TRUE(changes.back() < settings.lut_change_threshold() || changes.size() == settings.max_alternations());
    }
  }
  std::printf("%zu sequences, %zu with more than two rounds, %zu rounds shortened\n", sequences, multi_round,
              capped_rounds);
  // Of the 192 channels, those that keep a lobe fit (147 since lobes peaking far
  // above the energy-conserving peak count as failed: texel_fit.cpp LobePeaksBounded).
  EXPECT_GT(sequences, 140u);
  EXPECT_GT(multi_round, sequences / 4);
}

}  // namespace
}  // namespace loom
