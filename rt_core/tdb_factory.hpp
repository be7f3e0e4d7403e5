#pragma once
#include <memory>

#include "rt_core/touchdown_bearing.hpp"

namespace ambdrop {

/// The TDB model a config names (TdbParams::model).
std::unique_ptr<TouchdownBearing> MakeTouchdownBearing(const TdbParams& params);

}  // namespace ambdrop
