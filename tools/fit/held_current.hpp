#pragma once
// The current an AMB axis held when its power failed, read from the record. A record's sample
// after the trigger is already inside the decay, so interpolating at a trigger that falls between
// two samples takes part of the decay for the held current (0.5 % low at 20 kHz and tau = 5 ms
// with the trigger mid-interval). The held current is taken from the levitated samples alone.
#include "io/measured_csv.hpp"

namespace ambdrop {

/// The value of column `column` held at `trigger_s`: its last sample before the trigger (the
/// first sample for a trigger at or before it). A sample at the trigger's own time is left out:
/// a logger that reads after the cut already sees the decay there. Not a mean or a line over
/// several samples: a digital controller holds its output between its samples, so on a record
/// logged at the controller's rate the last sample before the cut is the held current, and the
/// sample-to- sample jitter around it is the controller answering its sensors' noise, a current
/// that really flows (about 57 mA on the PID rig, ten times its record's 5 mA current noise), which
/// a mean would smear away.
double HeldCurrentAtTrigger(const MeasuredRecord& record, int column, double trigger_s);

}  // namespace ambdrop
