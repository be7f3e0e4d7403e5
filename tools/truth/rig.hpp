#pragma once
// The rig the truth generator simulates: a rigid rotor on two differential current-biased AMB
// axes pairs, read by two displacement-sensor planes (not colocated with the AMBs), held by a
// PID per axis, dropped onto two contact-law TDBs. Every number in SI; the hidden effects of
// effects.hpp are fields here too (absent from a rig file: their defaults are "no effect").
// Frame: z along the rotor from the non-drive end, y vertical up, x horizontal.
#include <array>
#include <string>
#include <vector>

namespace ambdrop_truth {

/// A flexible shaft: Rayleigh beam elements (translational and rotary inertia, the shaft's
/// gyroscopic moment; no shear) plus rigid discs, reduced to its first free-free modes.
struct ShaftSegmentRig {
  double length_m = 0.0;
  double outer_diameter_m = 0.0;
  double inner_diameter_m = 0.0;
  int elements = 1;
};
struct DiscRig {
  double position_m = 0.0;
  double mass_kg = 0.0;
  double transverse_inertia_kg_m2 = 0.0;  ///< about its own centre
  double polar_inertia_kg_m2 = 0.0;
};
struct FlexibleShaftRig {
  bool enabled = false;  ///< false: the rotor is rigid (RotorRig's numbers)
  double start_m = 0.0;  ///< station of the shaft's first end
  double youngs_modulus_Pa = 0.0;
  double density_kg_m3 = 0.0;
  std::vector<ShaftSegmentRig> segments;
  std::vector<DiscRig> discs;
  int bending_modes = 0;             ///< kept per plane beside the two rigid-body modes
  double modal_damping_ratio = 0.0;  ///< on the bending modes
};

/// For a flexible rotor these are derived from the shaft and discs (rig_reader.cpp).
struct RotorRig {
  double mass_kg = 0.0;
  double transverse_inertia_kg_m2 = 0.0;  ///< about the centre of mass
  double polar_inertia_kg_m2 = 0.0;
  double centre_of_mass_m = 0.0;  ///< station of the centre of mass (m)
};

/// One AMB plane, two axes (x, y), each a pair of opposed electromagnets with a bias current.
struct AmbRig {
  std::string name;
  double position_m = 0.0;
  double electromagnet_constant_N_m2_per_A2 = 0.0;  ///< k of f = k (I/g)^2 per coil
  double nominal_gap_m = 0.0;
  double bias_current_A = 0.0;
  double coil_current_limit_A = 0.0;  ///< each coil's current stays in [0, limit]
  int sensor = 0;                     ///< index of the sensor plane its PID reads
  /// A permanent magnet makes the bias flux: bias_current_A is its equivalent current, which
  /// stays after power loss; the amplifier carries the control current alone, |i| <=
  /// min(I0, coil_current_limit_A). False: the amplifiers make the bias (coils in [0, limit]).
  bool permanent_magnet_bias = false;
};

/// A displacement-sensor plane. gain and offset are the sensor's errors (1 and 0 when true).
struct SensorRig {
  std::string name;
  double position_m = 0.0;
  std::array<double, 2> gain{1.0, 1.0};
  std::array<double, 2> offset_m{0.0, 0.0};
};

/// One section of a firmware controller, in s: a PD with a filtered derivative
/// kp + kd s/(1 + tau s), a lead (1 + s/wz)/(1 + s/wp), or a notch
/// (s^2 + 2 zz w s + w^2)/(s^2 + 2 zp w s + w^2). Discretised by Tustin, prewarped at
/// prewarp_Hz when given (firmware_controller.hpp).
struct FirmwareSectionRig {
  enum class Kind { kPd, kLead, kNotch } kind = Kind::kPd;
  double kp = 0.0, kd_s = 0.0, derivative_filter_s = 0.0;
  double zero_Hz = 0.0, pole_Hz = 0.0;
  double frequency_Hz = 0.0, pole_damping = 0.0, zero_damping = 0.0;
  double prewarp_Hz = 0.0;
};

/// The coil current loop between the command and the coil (continuous, as the analogue loop
/// is): i' = w (c - i), |i'| <= slew rate. Disabled: the coil carries the command.
struct AmplifierRig {
  bool enabled = false;
  double bandwidth_Hz = 0.0;
  double slew_rate_A_per_s = 0.0;  ///< 0: none
};

/// A PID per AMB axis (seed 003's structure, kp + ki/s + kd s/(1 + tau_d s)), run at rate_Hz,
/// its command applied computation_delay_s after the sample it was computed from. Or, with
/// `firmware`, a cascade of sections and a gravity feedforward (no integral).
struct ControllerRig {
  bool firmware = false;
  std::vector<FirmwareSectionRig> sections;
  AmplifierRig amplifier;
  double rate_Hz = 0.0;
  double computation_delay_s = 0.0;
  double sensor_gain_V_per_m = 0.0;
  double amplifier_gain_A_per_V = 0.0;
  double kp = 0.0;
  double ki_per_s = 0.0;
  double kd_s = 0.0;
  double derivative_filter_s = 0.0;
};

enum class ContactLaw { kLinear, kHuntCrossley };

/// A massless ribbon under the TDB's housing with the generalized Dahl law (Jarroux 2019
/// Eq. (1)-(3)); the housing then has a mass and moves on it.
struct DahlRibbonRig {
  bool enabled = false;
  double housing_mass_kg = 0.3;
  double slipping_threshold_N = 0.0;  ///< muFN
  double slipping_stiffness_N_per_m = 0.0;
  double beta_per_m = 0.0;
  double hardening_N = 0.0;           ///< a = c
  double hardening_rate_per_m = 0.0;  ///< b = d
};

/// A 4-DOF TDB's mount (Jarroux 2019 models #2/#3, Sec. 4.1, Fig. 9(b)): the inner race has a
/// lateral mass and rides on the ball bearing (linear, kb and cb) on the outer race, which rides
/// on the ribbon (Kelvin-Voigt, Eq. (4), or the Dahl ribbon when that is on) in a housing that it
/// never reaches. Off: the races are fixed to the housing (the contact-law TDB).
struct FourDofMountRig {
  bool enabled = false;
  double inner_race_mass_kg = 0.0;
  double outer_race_mass_kg = 0.0;
  double bearing_stiffness_N_per_m = 0.0;
  double bearing_damping_N_s_per_m = 0.0;
  double ribbon_stiffness_N_per_m = 0.0;
  double ribbon_damping_N_s_per_m = 0.0;
};

struct TdbRig {
  std::string name;
  double position_m = 0.0;
  double journal_radius_m = 0.0;
  double clearance_m = 0.0;
  double inner_race_radius_m = 0.0;  ///< 0 in a rig file: taken as the journal radius
  ContactLaw contact_law = ContactLaw::kLinear;
  double contact_stiffness = 0.0;  ///< N/m (linear) or N/m^n (Hunt-Crossley)
  double contact_damping = 0.0;    ///< N s/m (linear) or alpha, s/m (Hunt-Crossley)
  double contact_exponent = 1.0;   ///< n (Hunt-Crossley)
  double friction_coefficient = 0.0;
  double slip_regularisation_m_s = 0.0;  ///< v0 of tanh(v / v0)
  double race_inertia_kg_m2 = 0.0;
  double race_viscous_drag_N_m_s = 0.0;
  double race_drag_torque_N_m = 0.0;
  std::array<double, 2> misalignment_m{0.0, 0.0};  ///< TDB centre off the magnetic centre
  /// With the 4-DOF mount the Dahl ribbon carries its outer race (housing_mass_kg unused).
  DahlRibbonRig dahl;
  FourDofMountRig four_dof;
};

/// What the acquisition records and how: its rate and length, the trigger, and its noise.
struct AcquisitionRig {
  double sample_rate_Hz = 0.0;
  double record_length_s = 0.0;
  double trigger_time_s = 0.0;
  double sensor_noise_m = 0.0;         ///< sigma
  double sensor_quantisation_m = 0.0;  ///< 0: none
  /// The displacement sensors' noise through their electronics' first-order bandwidth, Hz (a
  /// coloured noise of the same sigma, as a real sensor's is); 0: white at every read.
  double sensor_noise_bandwidth_Hz = 0.0;
  double current_noise_A = 0.0;
  double speed_noise_rpm = 0.0;
  double force_noise_N = 0.0;
  /// A lag of the whole acquisition chain, the same on every sensor axis: a first-order
  /// low-pass then a pure delay (both 0: none). The controller reads through it too.
  double lag_time_constant_s = 0.0;
  double lag_delay_s = 0.0;
  /// The closed loop runs this long before the record starts (a machine levitated for a
  /// while); 0: the record starts at the computed equilibrium.
  double settle_s = 0.0;
};

/// How the AMB forces go when the power fails. kInstant: at once. kFormA: bias and control
/// flux fade together, currents as exp(-t/tau), force as exp(-2t/tau). kFormB: the currents
/// (and so the force law) are held for hold_time_s, then the force falls as exp(-t/tau).
/// kRamp: the DC link collapses and each coil's control current falls to zero at
/// slew_rate_A_per_s (a permanent magnet's bias stays; an electromagnet bias ramps too).
enum class FluxDecayForm { kInstant, kFormA, kFormB, kRamp };
struct PowerLossRig {
  FluxDecayForm form = FluxDecayForm::kInstant;
  double time_constant_s = 0.0;
  double hold_time_s = 0.0;
  double slew_rate_A_per_s = 0.0;
};

/// Torques that slow the rotor once its motor stops: -(c1 W + c2 W |W|).
struct CoastDownRig {
  double viscous_N_m_s = 0.0;
  double windage_N_m_s2 = 0.0;
};

/// Unbalance: a static one at the centre of mass and a couple (equal and opposite masses in
/// two planes), each as mass x eccentricity (kg m) and phase (rad).
struct UnbalanceRig {
  double static_kg_m = 0.0;
  double static_phase_rad = 0.0;
  double couple_kg_m = 0.0;
  double couple_phase_rad = 0.0;
  std::array<double, 2> couple_planes_m{0.0, 0.0};
};

/// A constant force on the rotor at a station that stays after power loss (e.g. the unbalanced
/// magnetic pull of a permanent-magnet motor whose rotor sits off its stator's centre).
struct SidePullRig {
  std::array<double, 2> force_N{0.0, 0.0};
  double position_m = 0.0;
};

struct Rig {
  std::string name;
  double spin_speed_rad_s = 0.0;
  double gravity_m_s2 = 9.81;
  double step_s = 1e-6;  ///< the generator's own integration step
  RotorRig rotor;
  FlexibleShaftRig shaft;
  CoastDownRig coast_down;
  std::array<AmbRig, 2> ambs;
  std::array<SensorRig, 2> sensors;
  ControllerRig controller;
  std::array<TdbRig, 2> tdbs;
  AcquisitionRig acquisition;
  PowerLossRig power_loss;
  UnbalanceRig unbalance;
  SidePullRig side_pull;
};

/// Reads a rig file (JSON; tools/truth/rigs/*.json shows the schema); throws
/// std::runtime_error naming the key on a missing or malformed value.
Rig ReadRig(const std::string& path);

/// Every hardware station of the rig (AMBs, sensors, TDBs), in that order.
std::vector<double> HardwareStations(const Rig& rig);

/// Checks the numbers are physical (positive masses, gaps, rates ...); throws naming the key.
void CheckRig(const Rig& rig);

}  // namespace ambdrop_truth
