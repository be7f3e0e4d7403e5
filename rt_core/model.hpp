#pragma once
#include <array>
#include <memory>
#include <vector>

#include "rt_core/control_input.hpp"
#include "rt_core/eigen_types.hpp"
#include "rt_core/levitated_start.hpp"
#include "rt_core/model_params.hpp"
#include "rt_core/plane_model.hpp"
#include "rt_core/reduced_rotor.hpp"
#include "rt_core/touchdown_bearing.hpp"

namespace ambdrop {

/// Immutable simulation model built once from ModelParams (may allocate and throw
/// std::invalid_argument; nothing after it does).
struct Model {
  ModelParams params;
  ReducedRotor rotor;

  std::vector<StationShape> amb_shapes;
  std::vector<StationShape> tdb_shapes;
  std::vector<StationShape> sensor_shapes;
  std::vector<StationShape> unbalance_shapes;
  std::vector<std::unique_ptr<TouchdownBearing>> tdbs;
  std::vector<int> tdb_state_offset;  ///< into State::y

  ModalVector gravity_force;  ///< S^T f of gravity, constant
  /// K and C while the AMBs are powered: rotor plus the equivalent-law AMBs projected on q.
  ModalMatrix stiffness_powered;
  ModalMatrix damping_powered;
  ModalVector amb_bias_force;  ///< gravity compensation of equivalent-law AMBs
  /// Per AMB (x, y): the static force that holds the rotor with zero deflection at the AMB
  /// planes (an integrating controller's settled output). Equivalent-law AMBs with gravity
  /// compensation apply it as a bias; current-driven AMBs' controllers use it as feedforward.
  std::vector<std::array<double, 2>> amb_bias_force_N;

  PlaneModel planes;  ///< the same equations by bending plane, for the step

  /// Where a run under the in-process controller starts and what holds it there
  /// (ComputeLevitatedStart): the reference start unless a sensor offset, or a static load the
  /// feedforward leaves to the controller, moves it.
  LevitatedStart levitated;

  int state_size = 0;
  std::int64_t trigger_step = -1;  ///< first step without AMB forces (-1: never)
  std::int64_t restore_step = -1;  ///< first step with power back (-1: never)
  std::int64_t total_steps = 0;

  int modes() const { return rotor.size; }
  int spin_index() const { return 2 * rotor.size; }
  int spin_angle_index() const { return 2 * rotor.size + 1; }
};

/// Builds the model: FE assembly and pseudo-modal reduction (or the rigid form), station shapes,
/// TDB objects, AMB projections and the gravity compensation.
Model BuildModel(const ModelParams& params);

/// The same with the reduced rotor already built: `rotor` must be BuildReducedRotor of params
/// (of params with equal ReductionInputsOf).
Model BuildModel(const ModelParams& params, const ReducedRotor& rotor);

/// Control currents that hold the rotor at its levitated start: those of Model::levitated when it
/// moved, else the currents that carry the static load (amb_bias_force_N) at the centre. What a
/// run driven by a controller applies until the controller's first command, and records as its
/// start.
ControlInput StaticLoadInput(const Model& model);

/// Static equilibrium q of the powered rotor for the given AMB control currents, the
/// current-driven laws linearised at the centre (zero if singular).
ModalVector PoweredEquilibrium(const Model& model, const ControlInput& input);

/// True when `input` carries exactly the currents of a moved Model::levitated start: a run
/// handed them starts at Model::levitated.q (Simulator::InitialState).
bool HoldsLevitatedStart(const Model& model, const ControlInput& input);

}  // namespace ambdrop
