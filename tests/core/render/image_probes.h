#pragma once
// What the render tests look for in a frame.

#include "core/image/image.h"

namespace loom::testing {

// Fraction of pixels where red clearly outweighs green: a red floor seen through
// a fabric's holes.
double RedFraction(const Image& image);

// Mean over the pixels of red minus green: the red floor's share of a frame whose
// cloth is grey.
double MeanRedExcess(const Image& image);

// Mean red over the pixel columns [x0, x1), every row.
double MeanRedInColumns(const Image& image, int x0, int x1);

}  // namespace loom::testing
