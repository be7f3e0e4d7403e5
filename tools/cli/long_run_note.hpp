#pragma once
#include "rt_core/model.hpp"

namespace ambdrop {

/// Before a run that will take long (a minute or more), says on stderr how many steps it has
/// and roughly how long it will take, so that a duration typed with a wrong exponent is seen
/// before it costs hours. Offline (`real_time` false) the time is estimated by timing a short
/// burst of the model's steps; a real-time run lasts its simulated time.
void NoteLongRun(const Model& model, bool real_time);

}  // namespace ambdrop
