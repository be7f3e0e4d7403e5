#pragma once
// Whether what the record shows after the drop's start is a draw of the rotor's jitter when
// the power fails. A levitated rotor jitters by about its sensors' noise (its controller
// answers that noise); which way the first impacts throw it, whether it then rocks at the
// bottom of the race or rolls into backward whirl (Jarroux 2016, seed 001, Sec. 3), and how
// soon the races spin up, can turn on less than that. The fit's prediction is the expected
// reading, noise off: its drop is one of the outcomes, not all. On clean records of the
// independent rigid rig the drop went into backward whirl in about one in five seeds; the
// declared model's noise-free drop rocked, and runs of it with its controller answering noise
// of the record's level whirled in one run of six. On the 4-DOF rig a clean record's races
// spun up in 0.066 s against the noise-free model's 0.10-0.12 s; two runs of sixteen with the
// jitter drawn spun up in 0.065 s and agreed with its speeds within their limit.
#include <cstdint>
#include <limits>
#include <string>

#include "tools/fit/record_cost.hpp"

namespace ambdrop {

struct JitterDraws {
  bool ran = false;  ///< runs were made (closed loop, a jitter to draw)
  /// measurement.trigger_state = "record": what was drawn is the state at the trigger (and
  /// the held currents) from the uncertainty of its estimate, not the controller's noise.
  bool from_estimate = false;
  bool mode_differs = false;  ///< the record's mode differs from the noise-free model's
  int draws = 0;              ///< runs made
  /// The first run (1-based) within the judged part's agreement limit there; 0: none.
  int first_within = 0;
  double within_rms = std::numeric_limits<double>::quiet_NaN();
  /// Where the modes differ: the first run in the record's mode at every plane; 0: none.
  int first_match = 0;
  double match_rms = std::numeric_limits<double>::quiet_NaN();  ///< its judged-part residual
  /// The least judged-part residual of any run made.
  double closest_rms = std::numeric_limits<double>::quiet_NaN();
  /// The draws went on past `max_draws` (DrawJitter's `extend_within`).
  bool extended = false;
  double jitter_sigma_m = 0.0;
  std::string record_mode;  ///< e.g. "backward_whirl at nde and de"
  std::string model_mode;   ///< the noise-free model's
};

/// Runs the declared model (`cost`'s) with its controller answering sensor noise of the
/// record's level before the trigger (the displacement channels' median noise), seeds 1 to
/// `max_draws` in batches of four, until a run agrees with the record on `judged` within
/// `judged_limit`, or, where the noise-free model's drop mode differs from the record's, a run
/// is in the record's mode at every plane where both axes are measured. With
/// measurement.trigger_state = "record" the rotor's jitter is the record's own, estimated from
/// its lead window: what is drawn then is that estimate's error, normal along every axis of its
/// covariance and each held current's standard error (trigger_state_probes.hpp; a seeded
/// portable generator). Nothing is run open loop. Deterministic: the batches do not depend on
/// `threads`.
/// With `match_modes` false only agreement on `judged` stops the draws (a part that ends
/// before the drop settles has no mode to match). With `extend_within` > 0, where none of
/// `max_draws` runs agreed but the closest came within `extend_within` times the limit, the
/// draws go on to four times `max_draws`: a record at the edge of the jitter's spread is
/// decided by more of them, while one far beyond it costs no more runs. On the 4-DOF truth
/// rig's clean record of seed 912 the closest of 16 runs left its speeds at 0.0359 against a
/// limit of 0.0348, the 35th agreed (0.0335), and a friction coefficient had been named; its
/// race drag, race inertia and flux-decay records' closest runs stayed 1.7 to 5 times their
/// limits.
JitterDraws DrawJitter(const RecordCost& cost, const RecordCost& judged, double judged_limit,
                       int max_draws, int threads, bool match_modes = true,
                       double extend_within = 0.0);

/// DrawJitter that stops at a run in the record's drop mode only, not at a run that agrees on
/// `judged` (its residuals are still kept: `closest_rms`): whether any of `max_draws` runs
/// reaches the record's mode. Setting an effect aside because its model never reaches that mode
/// needs every run looked at: on the rigid truth rig's race drag of seed 14 a run of the fitted
/// drag agreed on the speeds without whirling, the draws stopped there at 20 of 64, and the
/// record's race drag was called `unexplained`.
JitterDraws DrawJitterForMode(const RecordCost& cost, const RecordCost& judged, int max_draws,
                              int threads);

/// Run `run` (1-based) of draws `d` made with the controller's noise (not from an estimate),
/// again, over `cost`'s span: a draw judged on the drop's start, run to the record's end.
SimulatedRecord RunDraw(const RecordCost& cost, const JitterDraws& d, int run);

/// What a run of the draws had drawn, for a reason's text: "with its controller answering
/// sensor noise of the record's level (3e-07 m)" or "with its state at the trigger drawn from
/// its estimate's uncertainty".
std::string DrawnText(const JitterDraws& d);

/// What a departure after the start that a run reached is: "a draw of the rotor's jitter when
/// the power failed", or, drawn from the estimate, within what the record leaves open of it.
std::string DepartureReachedText(const JitterDraws& d);

}  // namespace ambdrop
