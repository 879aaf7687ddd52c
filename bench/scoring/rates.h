// Counts to rates for the scores: NaN (undefined, shown as such) where nothing was
// there to count, never 0 or infinity.
#pragma once

#include <limits>

namespace grapebench {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// a / b, or NaN when b is not positive.
inline double ratio(double a, double b) { return b > 0 ? a / b : kNaN; }

}  // namespace grapebench
