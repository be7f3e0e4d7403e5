#pragma once
// Where a record's power failed, when its [measurement] table does not say (trigger = "detect").
#include "io/config/config_measurement.hpp"
#include "io/files/measured_csv.hpp"

namespace ambdrop {

/// The trigger time: given, or found in the record. Found: the record's first tenth is taken as
/// levitated (each current, controller command and displacement channel's mean and noise); the
/// first row from which, for at least half a millisecond (four rows at least), some channel
/// stays far from its levitated level (8 sigma; a current or command also a fifth of its mean)
/// is surely after the power failed: from there back to the last row on which every channel is
/// within 3 sigma of its level, and the trigger is the middle of the interval after that row.
/// A failure that shows at once (currents cut) is found within half a sample; one that shows
/// slowly (a slow decay or ramp) when its effect leaves the noise, later by that time. Where
/// the coil currents stopped jittering before that (their second differences fall to their
/// measurement noise once no amplifier follows the controller: held, fading, ramping), the
/// trigger is dated where they did, if beyond what chance makes of the levitated time.
/// Throws std::runtime_error when no such channel leaves its level for good.
double RecordTriggerTime(const MeasurementParams& measurement, const MeasuredRecord& record);

}  // namespace ambdrop
