#pragma once
#include <vector>

#include "rt_core/model_params.hpp"

namespace ambdrop {

/// Natural frequencies of a rotor described by a config.
struct ModalAnalysis {
  /// Full FE (or rigid) model, free-free, at rest; rigid-body modes appear as 0.
  std::vector<double> free_free_rad_s;
  /// Full FE model on the config's linear bearings and powered AMBs (equivalent stiffness and
  /// damping, or the linearised law's negative stiffness) at the given spin speed (imaginary parts
  /// of the eigenvalues, ascending; gyroscopics split each pair into backward and forward whirl).
  std::vector<double> supported_rad_s;
  /// The same for the reduced (pseudo-modal) model the simulator integrates.
  std::vector<double> reduced_supported_rad_s;
};

/// Natural frequencies, `count` of each list at most.
ModalAnalysis AnalyseModes(const ModelParams& params, double spin_speed_rad_s, int count);

}  // namespace ambdrop
