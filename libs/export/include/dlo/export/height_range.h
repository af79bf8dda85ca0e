/// \file height_range.h
/// \brief The height interval a colour scale spans.
#pragma once

#include <utility>
#include <vector>

namespace dlo {

/// The [low_percentile, high_percentile] interval (percent, nearest rank) of `heights`, so that a
/// few outliers (birds, noise below the ground) do not wash out the colours. When that interval
/// is under 5 cm (a map that is mostly flat ground: both percentiles fall on it), the full
/// [min, max] is used instead, otherwise every object would saturate to the top colour.
/// Returns {0, 1} for no heights; the interval is never empty.
std::pair<double, double> colourHeightRange(std::vector<float> heights, double low_percentile,
                                            double high_percentile);

}  // namespace dlo
