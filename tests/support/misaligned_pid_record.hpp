#pragma once
// The record the fit's benchmark and its verdict tests share: the PID rig with its DE TDB
// offset by (20, -40) um, made at 2.5 us (the fit runs at the rig's 5 us) with the rig's sensor
// noise and 5 mA on the currents.
#include <string>
#include <vector>

#include "tools/fit/measured_record_maker.hpp"

namespace ambdrop::testing {

inline constexpr const char* kPidRig = "jarroux2019_industrial_pid.toml";

/// The record, over `timing` (config overrides: duration and trigger time).
SyntheticMeasurement MisalignedPidRecord(const std::vector<std::string>& timing);

}  // namespace ambdrop::testing
