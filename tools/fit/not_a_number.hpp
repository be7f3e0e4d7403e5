#pragma once

#include <limits>

namespace ambdrop {

/// "Not measured" / "not fitted" in the fit's result fields (one definition, so that the fit's
/// files can be compiled together in one unity translation unit).
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace ambdrop
