// The radiance samples file (core/acquire/radiance_samples.h). Its SHA-256 trailer
// would stop every mutated input at the first check, so most inputs get a correct
// trailer appended (first byte even) and reach the header, size and value checks;
// the rest go in as they are.

#include <cstddef>
#include <cstdint>
#include <string>

#include "core/acquire/radiance_samples.h"
#include "core/util/error.h"
#include "core/util/sha256.h"
#include "fuzz/quiet_logs.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  loom::fuzz::QuietLogs();
  if (size == 0) return 0;
  std::string bytes(reinterpret_cast<const char*>(data) + 1, size - 1);
  if (data[0] % 2 == 0) bytes += loom::Sha256Hex(bytes);
  try {
    const loom::RadianceSamples samples = loom::DecodeRadianceSamples(bytes, "fuzz.rsmp");
    // What loom-lab does next with a file it read.
    loom::EncodeRadianceSamples(samples);
    samples.MeanAlpha();
  } catch (const loom::Error&) {
  }
  return 0;
}
