#pragma once
// measurement.trigger_state = "record": the state at the trigger is an estimate, and a rotor
// that the power loss leaves unstable goes where its error sends it. Before a departure of the
// drop's start is taken as evidence of an effect, the declared model is given the state (and
// held currents) that the estimate allows best: a shift along the estimate's own uncertainty,
// weighted by its prior. If a shift of plausible size takes the start to the record's noise, the
// departure is the estimate's, not the rig's (on the magnet-biased flexible rig's clean seed 8
// a DE sensor 16 mm off had been named for it).
#include <vector>

#include <Eigen/Core>

#include "tools/fit/record_cost.hpp"
#include "tools/fit/simulate_on_record.hpp"

namespace ambdrop {

struct StartStateShift {
  bool fitted = false;
  /// The shift's size in standard deviations of the estimate (Mahalanobis norm of the
  /// prior), and the bound a clean record's shift stays within (chi-square at 99.5 % for the
  /// number of directions the residual determines).
  double sigmas = 0.0;
  double plausible_sigmas = 0.0;
  double directions = 0.0;  ///< effective number of directions the residual determines
  double rms_before = 0.0;  ///< the cost's relative RMS residual of the declared model
  double rms_after = 0.0;   ///< ... with the shift
  int runs = 0;
};

/// The maximum a posteriori shift of the state at the trigger for `cost` (a part of the record
/// after the trigger) with the declared model's residual `residual_before` there: the probes'
/// central differences as the Jacobian, the record's noise as the samples' variance, a unit
/// normal prior per probe axis; Gauss-Newton steps on that Jacobian, each checked by a run.
/// With `target_rms` > 0 and the shift within it, the question becomes whether any plausible
/// state agrees (the maximum a posteriori shift also fits the noise's wiggles, which the
/// samples outnumber the prior on): the least shift that the same Jacobian predicts within a
/// share of `target_rms` (the discrepancy principle), linearised where the last run was (at most
/// four runs), the least one a run confirms kept; where none is, the boundary between the
/// maximum a posteriori shift and the nearest unconfirmed one (a bisection, four runs); then
/// drawn back along its own ray to the smallest share of it that still leaves the start within
/// `target_rms` (a bisection, six runs).
StartStateShift FitStartStateShift(const RecordCost& cost, const Eigen::VectorXd& residual_before,
                                   int threads, double target_rms = 0.0);

}  // namespace ambdrop
