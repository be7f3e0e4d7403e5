#pragma once
// Whether the drop's mode (rocking or whirling on the TDBs, Jarroux 2016, seed 001, Sec. 3) is
// a draw of the rotor's jitter when the power fails. A levitated rotor jitters by about its
// sensors' noise (its controller answers that noise); which way the first impacts throw it, and
// whether it then rocks at the bottom of the race or rolls into backward whirl, can turn on less
// than that. The fit's prediction is the expected reading, noise off: its drop is one of the
// outcomes, not all. On clean records of the independent rigid rig the drop went into backward
// whirl in about one in five seeds; the declared model's noise-free drop rocked, and runs of it
// with its controller answering noise of the record's level whirled in one run of six.
#include <cstdint>
#include <limits>
#include <string>

#include "tools/fit/record_cost.hpp"

namespace ambdrop {

struct DropModeDraw {
  /// The record's mode differs from the declared model's at some plane, and the model could be
  /// drawn (closed loop: a controller answers the noise).
  bool checked = false;
  int draws = 0;        ///< runs made
  int first_match = 0;  ///< the first run (1-based) in the record's mode at every plane; 0: none
  int matches = 0;      ///< runs in the record's mode
  /// The first such run's overall relative RMS residual on the part the verdict judges
  /// (NaN without one).
  double match_rms = std::numeric_limits<double>::quiet_NaN();
  double jitter_sigma_m = 0.0;
  std::string record_mode;  ///< e.g. "backward_whirl at nde and de"
  std::string model_mode;
};

/// Runs the declared model (`cost`'s) with its controller answering sensor noise of the
/// record's level before the trigger (the displacement channels' median noise), seeds 1 to
/// `max_draws` in batches of four, until one drop is in the record's mode at every plane where
/// both axes are measured. Nothing is run where the modes agree, open loop, with
/// measurement.trigger_state = "record" (the record's own jitter is then estimated), or
/// without a plane. Deterministic: the batches do not depend on `threads`.
/// `judged`: the part whose residual `match_rms` is (whole, start or speeds) over `cost`'s run.
DropModeDraw DrawDropMode(const RecordCost& cost, const RecordCost& judged, int max_draws,
                          int threads);

}  // namespace ambdrop
