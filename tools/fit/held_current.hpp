#pragma once
// The current an AMB axis held when its power failed, read from the record. Two things make the
// obvious readings wrong:
//  - interpolating at a trigger that falls between two samples takes part of the decay for the
//    held current (0.5 % low at 20 kHz and tau = 5 ms with the trigger mid-interval);
//  - the last sample before the trigger may belong to the controller's previous period: a
//    digital controller holds its output between updates, its output jitters from period to
//    period as it answers its sensors' noise (57 mA on the PID rig, 60 mA on the independent
//    rig of tools/truth, about 20 % of that rig's levitated current), and an update may land at
//    the cut itself. There the last levitated sample was 0.223 A and the current that then
//    decayed 0.320 A.
// The samples at and just after the trigger say what was held: the decay starts from it.
#include "io/files/measured_csv.hpp"
#include "rt_core/amb_params.hpp"

namespace ambdrop {

/// The value of column `column` held at `trigger_s`: where its first two samples at or after
/// the trigger extrapolate back to (a straight line; over one sample interval of a decay of
/// tau, off by about (interval / tau)^2 / 2 of the held value). Without two samples after the
/// trigger, or unless `decay_seen` (the column is a coil current whose samples after the
/// trigger may be read: not a command, which goes on answering the falling rotor, nor a channel
/// windowed to the levitated part), its last sample before (the first sample for a trigger at
/// or before it).
double HeldCurrentAtTrigger(const MeasuredRecord& record, int column, double trigger_s,
                            bool decay_seen = true);

/// The held current c0 that makes `amb`'s declared power-loss law (rt_core/power_loss_drive.hpp:
/// the control current it reports, c(t; c0)) fit the coil-current column's samples over
/// HeldCurrentWindowSeconds after the trigger, by least squares (Gauss-Newton from
/// HeldCurrentAtTrigger's reading). Two samples leave it the current's noise (5 mA on
/// tools/truth's records) off, and on a rotor that the power loss leaves unstable (a magnet's
/// bias) that error drives the drop: the law's whole window averages it down. A law whose
/// reported current does not depend on c0 (the currents vanish at once) keeps the reading.
/// `sd_A`, if given, receives c0's standard error (the window's noise, NoiseSigma, over the
/// root of its sum of squared sensitivities; 0 where the reading is kept).
double HeldCurrentByLaw(const MeasuredRecord& record, int column, double trigger_s,
                        const AmbParams& amb, double* sd_A = nullptr);

/// The window of HeldCurrentByLaw: 2 ms and at most 40 samples.
double HeldCurrentWindowSeconds(const MeasuredRecord& record);

}  // namespace ambdrop
