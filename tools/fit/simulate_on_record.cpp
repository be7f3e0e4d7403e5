#include "tools/fit/simulate_on_record.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <stdexcept>

#include "controller_if/boundary/power_state.hpp"
#include "controller_if/boundary/sensor_emulator.hpp"
#include "controller_if/controller/pid_controller.hpp"
#include "controller_if/loop/hil_session.hpp"
#include "controller_if/loop/settled_start.hpp"
#include "controller_if/loop/state_dump.hpp"
#include "controller_if/loop/step_driver.hpp"
#include "rt_core/amb_force.hpp"
#include "rt_core/model.hpp"
#include "rt_core/power_loss_drive.hpp"
#include "rt_core/tdb_clearance_watch.hpp"
#include "tools/fit/held_current.hpp"
#include "tools/fit/lead_state_estimate.hpp"
#include "tools/fit/not_a_number.hpp"

namespace ambdrop {
namespace {

// Linear interpolation of column `c` at time t (held beyond the ends).
double ValueAt(const MeasuredRecord& r, int c, double t) {
  const std::vector<double>& ts = r.time_s;
  const std::vector<double>& v = r.values[c];
  if (t <= ts.front()) return v.front();
  if (t >= ts.back()) return v.back();
  const auto hi = std::upper_bound(ts.begin(), ts.end(), t);
  const std::size_t j = static_cast<std::size_t>(hi - ts.begin());
  const double w = (t - ts[j - 1]) / (ts[j] - ts[j - 1]);
  return v[j - 1] + w * (v[j] - v[j - 1]);
}

}  // namespace

double LeadCurrentCorrection::At(const MeasuredRecord& r, std::size_t amb, int axis,
                                 double t) const {
  const std::vector<double>& v = A[amb][static_cast<std::size_t>(axis)];
  if (v.empty()) return 0.0;
  const std::vector<double>& ts = r.time_s;
  const std::size_t last = first_row + v.size() - 1;
  if (t < ts[first_row] || t > ts[last]) return 0.0;
  const auto hi = std::upper_bound(ts.begin() + static_cast<std::ptrdiff_t>(first_row),
                                   ts.begin() + static_cast<std::ptrdiff_t>(last) + 1, t);
  const std::size_t j = static_cast<std::size_t>(hi - ts.begin());
  if (j > last) return v.back();
  const double w = (t - ts[j - 1]) / (ts[j] - ts[j - 1]);
  return v[j - 1 - first_row] + w * (v[j - first_row] - v[j - 1 - first_row]);
}

namespace {

// Least-squares slope and value at t0 of column c over the samples within +-half of t0.
// The rows within `half` of t0, and their normal matrix for value, slope and curvature.
struct LocalRows {
  std::vector<std::size_t> rows;
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
};
LocalRows RowsNear(const MeasuredRecord& r, double t0, double half) {
  LocalRows out;
  const auto first = std::lower_bound(r.time_s.begin(), r.time_s.end(), t0 - half);
  for (auto it = first; it != r.time_s.end() && *it <= t0 + half; ++it) {
    const double dt = *it - t0;
    const Eigen::Vector3d b(1.0, dt, dt * dt);
    out.rows.push_back(static_cast<std::size_t>(it - r.time_s.begin()));
    out.normal += b * b.transpose();
  }
  return out;
}

// Value and slope at t0 of a least-squares quadratic through the samples within `half` of it:
// the quadratic lets the window span a millisecond or two of the levitated jitter, and the
// longer window pins the slope far better than a short line can.
std::pair<double, double> LocalFit(const MeasuredRecord& r, int c, double t0, double half) {
  const LocalRows near = RowsNear(r, t0, half);
  if (near.rows.size() < 3) return {ValueAt(r, c, t0), 0.0};
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  for (const std::size_t j : near.rows) {
    const double dt = r.time_s[j] - t0;
    rhs += r.values[c][j] * Eigen::Vector3d(1.0, dt, dt * dt);
  }
  const Eigen::Vector3d p = near.normal.ldlt().solve(rhs);
  return {p(0), p(1)};
}

}  // namespace

double OpenLoopStartHalfWindow(const MeasuredRecord& record) {
  return std::max(4.0 * record.SampleInterval(), 1e-3);
}

std::pair<double, double> OpenLoopStartUncertainty(const MeasuredRecord& record, double t_start) {
  const LocalRows near = RowsNear(record, t_start, OpenLoopStartHalfWindow(record));
  if (near.rows.size() < 3) return {1.0, 1.0 / record.SampleInterval()};
  const Eigen::Matrix3d cov = near.normal.inverse();
  return {std::sqrt(cov(0, 0)), std::sqrt(cov(1, 1))};
}

bool ClosedLoop(const ModelParams& params, const MeasurementParams& measurement,
                const RecordRunOptions& options) {
  if (options.pre_trigger != PreTrigger::kAuto) return false;
  if (measurement.power_loss == PowerLossSource::kFromRecord) return false;
  if (params.controller.kind == ControllerKind::kInternalPid) return true;
  // AMBs with the equivalent law hold the rotor by their stiffness and damping, as a controller
  // would: the rig levitates by itself and needs no measured currents.
  return !params.ambs.empty() &&
         std::all_of(params.ambs.begin(), params.ambs.end(),
                     [](const AmbParams& a) { return a.law == AmbForceLaw::kEquivalent; });
}

namespace {

// Sets the rotor's modal positions and velocities to those that best explain the displacement
// channels at record time t: a quadratic through each channel's samples within
// OpenLoopStartHalfWindow of t gives its value and slope, which the least-squares correction of
// minimum norm takes the state to (the modes the sensors do not see keep their values).
void SetToRecordedState(const Model& model, const MeasurementParams& m, const MeasuredRecord& r,
                        double t, const RecordRunOptions& options, State* state) {
  const int n = model.modes();
  std::vector<Eigen::RowVectorXd> rows_q;
  std::vector<double> pos, vel;
  const double half_window = OpenLoopStartHalfWindow(r);
  const Eigen::VectorXd q = state->y.head(n), v = state->y.segment(n, n);
  for (const MeasurementChannel& ch : m.channels) {
    if (ch.quantity != MeasuredQuantity::kDisplacement) continue;
    const SensorParams& s = model.params.sensors[ch.index];
    const auto [value, slope] = LocalFit(r, r.Column(ch.column), t, half_window);
    const Eigen::RowVectorXd row = model.sensor_shapes[ch.index].row(ch.axis) * s.AxisGain(ch.axis);
    rows_q.push_back(row);
    pos.push_back(value + options.start_position_shift_m - s.AxisOffset_m(ch.axis) - row.dot(q));
    vel.push_back(slope + options.start_velocity_shift_m_s - row.dot(v));
  }
  if (rows_q.empty()) return;
  Eigen::MatrixXd a(static_cast<Eigen::Index>(rows_q.size()), n);
  for (std::size_t i = 0; i < rows_q.size(); ++i) a.row(static_cast<Eigen::Index>(i)) = rows_q[i];
  const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> fit(a);
  const Eigen::Map<const Eigen::VectorXd> dp(pos.data(), static_cast<Eigen::Index>(pos.size()));
  const Eigen::Map<const Eigen::VectorXd> dv(vel.data(), static_cast<Eigen::Index>(vel.size()));
  state->y.head(n) += fit.solve(dp);
  state->y.segment(n, n) += fit.solve(dv);
}

}  // namespace

namespace {

SimulatedRecord RunOnRecord(const ModelParams& declared, const MeasurementParams& m,
                            const MeasuredRecord& r, const RecordRunOptions& options) {
  SimulatedRecord out;
  out.trigger_time_s = RecordTriggerTime(m, r);
  out.closed_loop = ClosedLoop(declared, m, options);
  const bool closed = out.closed_loop;
  // Closed loop, the rig runs from time 0 as `ambdrop sim` runs it; open loop, from just before
  // the trigger.
  // Open loop with measurement.trigger_state = "record", the run starts a lead window before
  // the trigger whose samples pin its start through the model (lead_state_estimate.hpp).
  const bool lead_fit_open = !closed && m.trigger_state_from_record && !options.initial_state;
  const double lead =
      lead_fit_open ? std::max(options.lead_s, TriggerStateLeadSeconds(r)) : options.lead_s;
  const double t_start = closed ? 0.0 : std::max(r.time_s.front(), out.trigger_time_s - lead);
  const double t_end = r.time_s.back();
  if (out.trigger_time_s >= t_end) {
    throw std::runtime_error(
        fmt::format("the trigger ({} s) is not inside the record ({} s to {} s)",
                    out.trigger_time_s, r.time_s.front(), t_end));
  }

  ModelParams params = declared;
  if (options.step_s > 0) params.simulation.step_s = options.step_s;
  const double dt = params.simulation.step_s;
  const double run_end = std::min(t_end, std::max(options.end_s, out.trigger_time_s));
  params.simulation.duration_s = run_end - t_start + dt;
  params.trigger.enabled = true;
  params.trigger.time_s = out.trigger_time_s - t_start;
  params.trigger.restore_time_s = -1.0;
  if (!closed) {
    params.simulation.initial_position = InitialPosition::kCentred;
    params.controller.kind = ControllerKind::kNone;
  }
  for (AmbParams& a : params.ambs) a.current_profile.clear();
  // The prediction is the expected reading: noise and quantisation are not the model's to fit.
  for (std::size_t i = 0; i < params.sensors.size(); ++i) {
    SensorParams& s = params.sensors[i];
    s.noise.enabled = closed && options.jitter_sigma_m > 0.0;
    s.noise.std_dev_m = options.jitter_sigma_m;
    s.noise.seed = options.jitter_seed * 7919u + i;
    s.noise.bandwidth_Hz = options.jitter_bandwidth_Hz;
    s.quantisation_m = 0.0;
  }
  int rotor_speed_column = -1;
  for (const MeasurementChannel& ch : m.channels) {
    if (ch.quantity == MeasuredQuantity::kRotorSpeed) rotor_speed_column = r.Column(ch.column);
  }
  const double configured_spin = params.simulation.spin_speed_rad_s;
  if (rotor_speed_column >= 0 && !closed) {
    params.simulation.spin_speed_rad_s = ValueAt(r, rotor_speed_column, t_start);
  }
  const Model model =
      options.rotor_cache ? options.rotor_cache->BuildModel(params) : BuildModel(params);
  const int n = model.modes();

  // Measured currents by AMB axis; the rest carry the static load. While the axis has power
  // its coil follows the controller's command, so a command channel stands in for an axis
  // without a coil-current channel.
  std::array<std::array<int, 2>, kMaxAmbs> current_column;
  std::array<std::array<const MeasurementChannel*, 2>, kMaxAmbs> current_channel{};
  for (auto& a : current_column) a = {-1, -1};
  for (const MeasuredQuantity q :
       {MeasuredQuantity::kControllerCommand, MeasuredQuantity::kCurrent}) {
    for (const MeasurementChannel& ch : m.channels) {
      if (ch.quantity != q) continue;
      current_column[ch.index][ch.axis] = r.Column(ch.column);
      current_channel[ch.index][ch.axis] = &ch;
    }
  }
  // from_record: the axes whose coil current the record gives go on following it after the
  // trigger (never a command's: it answers the falling rotor, the coil does not).
  std::array<std::array<int, 2>, kMaxAmbs> driven_column;
  for (auto& a : driven_column) a = {-1, -1};
  for (const MeasurementChannel& ch : m.channels) {
    if (m.Drives(ch)) driven_column[ch.index][ch.axis] = r.Column(ch.column);
  }
  // What each measured axis held when the power failed. The coil current's samples just after
  // the trigger say it (the decay starts from it), if its window keeps them; a command goes on
  // answering the falling rotor after the cut, so from a command the last levitated sample.
  std::array<std::array<double, 2>, kMaxAmbs> held_A{};
  for (std::size_t a = 0; a < model.params.ambs.size(); ++a) {
    for (int axis = 0; axis < 2; ++axis) {
      const int c = current_column[a][axis];
      if (c < 0) continue;
      const MeasurementChannel& ch = *current_channel[a][axis];
      const bool decay_seen =
          ch.quantity == MeasuredQuantity::kCurrent &&
          ch.InWindow(out.trigger_time_s, out.trigger_time_s) &&
          ch.InWindow(out.trigger_time_s + 2.0 * r.SampleInterval(), out.trigger_time_s);
      held_A[a][axis] = decay_seen
                            ? HeldCurrentByLaw(r, c, out.trigger_time_s, model.params.ambs[a],
                                               &out.held_current_sd_A[a][axis])
                            : HeldCurrentAtTrigger(r, c, out.trigger_time_s, false);
      held_A[a][axis] += options.held_current_shift_A[a][axis];
    }
  }
  const ControlInput static_load = StaticLoadInput(model);
  ControlInput input = static_load;
  // The lead window's corrections of the measured currents: the options' (a sensitivity run of
  // the lead estimate), or the estimate's own once it is made.
  std::shared_ptr<const LeadCurrentCorrection> correction = options.lead_current_correction;
  const auto measured_currents = [&](double t_record, bool keep_unmeasured) {
    for (std::size_t a = 0; a < model.params.ambs.size(); ++a) {
      for (int axis = 0; axis < 2; ++axis) {
        const int c = current_column[a][axis];
        if (c >= 0) {
          input.amb[a].current_A[axis] =
              ValueAt(r, c, t_record) + (correction ? correction->At(r, a, axis, t_record) : 0.0);
        } else if (!keep_unmeasured) {
          input.amb[a].current_A[axis] = static_load.amb[a].current_A[axis];
        }
      }
    }
  };
  // The controller's output before the power state overrides an unpowered axis's current: the
  // controller, on its own supply, keeps commanding.
  std::array<std::array<double, 2>, kMaxAmbs> command_A{};
  // (The controller's output includes its amplifier loop when one is declared: ambdrop models
  // it as the controller's last stage, and records made from runs carry the same.)
  const auto keep_command = [&] {
    for (std::size_t a = 0; a < model.params.ambs.size(); ++a) {
      command_A[a] = input.amb[a].current_A;
    }
  };
  // A load cell reads its housing's share of the rig's weight before any contact: the tare.
  // The record's is its mean before the trigger (no contact while levitated), the model's its
  // first predicted value; the prediction is the model's change on the record's tare.
  std::vector<double> record_tare(m.channels.size(), 0.0);
  std::vector<double> model_tare(m.channels.size(), kNaN);
  for (std::size_t c = 0; c < m.channels.size(); ++c) {
    if (m.channels[c].quantity != MeasuredQuantity::kTdbSupportForce) continue;
    const std::vector<double>& v = r.values[r.Column(m.channels[c].column)];
    double sum = 0.0;
    std::size_t n = 0;
    for (std::size_t j = 0; j < v.size() && r.time_s[j] < out.trigger_time_s; ++j, ++n) sum += v[j];
    record_tare[c] = n > 0 ? sum / static_cast<double>(n) : v.front();
  }

  const bool controlled = closed && model.params.controller.kind == ControllerKind::kInternalPid;
  const std::int64_t substeps = controlled ? ControllerSubsteps(model) : 1;
  // The steps in `ambdrop sim`'s order (controller_if/loop/step_driver.hpp); the controller's
  // sensors are the driver's, sampled at its period.
  StepDriver driver(model, controlled ? substeps : 0);
  std::optional<ReferenceController> controller;
  State state;
  // measurement.trigger_state = "record": the state `lead` seconds before the trigger moved to
  // the lead window's fit (plus a start-sensitivity probe's shift), and that fit's uncertainty.
  const auto fit_lead_window = [&](State& at, double lead) {
    const LeadStateFit fit =
        FitLeadState(declared, m, r, options, model, at, out.trigger_time_s, lead);
    at.y.head(2 * n) += fit.correction;
    if (fit.current_correction) correction = fit.current_correction;
    out.lead_uncertainty = fit.uncertainty;
    out.lead_uncertainty_all = fit.uncertainty_all;
    out.lead_fit = fit.note;
    out.lead_misfit = fit.misfit;
  };
  // A levitated time an earlier run of this fit ran bit for bit: resumed from its end (the
  // trigger, or the start of the lead window of measurement.trigger_state).
  const bool reusable = controlled && options.prefix_cache;
  const std::uint64_t fingerprint = reusable ? RecordFingerprint(r) : 0;
  const std::optional<PrefixMatch> resumed =
      reusable
          ? options.prefix_cache->Find(model.params, model, m, fingerprint, options.keep_states)
          : std::nullopt;
  // How close the journal comes to each TDB before the trigger, while that time is kept.
  TdbClearanceWatch clearance;
  std::int64_t settle_steps = 0;
  if (controlled && resumed) {
    controller = resumed->prefix->controller;
  } else if (controlled) {
    controller.emplace(model, static_cast<double>(substeps) * dt, dt);
    controller->Initial(&input);
    state = driver.sim().InitialState(static_load);
    // As `ambdrop sim` starts it: settled first when the config asks (simulation.settle_s).
    const SettleResult settled =
        SettleClosedLoop(model, driver.sim(), &state, &*controller, driver.sensors(), &input);
    if (settled.status != StepStatus::kOk) {
      // Nothing of the record was reached: every row NaN, as after a run that stopped.
      out.values.assign(m.channels.size(), std::vector<double>(r.time_s.size(), kNaN));
      out.status = settled.status;
      out.failure = settled.failure;
      return out;
    }
    clearance = settled.clearance;
    settle_steps = settled.steps;
    keep_command();
  } else if (closed) {
    state = driver.sim().InitialState(static_load);
  } else {
    measured_currents(t_start, false);
    if (options.initial_state) {
      state = *options.initial_state;
      state.step_index = 0;
    } else {
      state = driver.sim().InitialState(input);
      // The modal coordinates that best explain the displacement channels around the start.
      SetToRecordedState(model, m, r, t_start, options, &state);
      state.y(model.spin_angle_index()) = configured_spin * t_start;
    }
    if (options.state_correction.size() == 2 * n) state.y.head(2 * n) += options.state_correction;
    if (lead_fit_open) fit_lead_window(state, out.trigger_time_s - t_start);
  }
  // measurement.trigger_state = "record": over a lead window before the trigger the record's
  // currents drive the rotor, whose seen state is fitted to the window (lead_state_estimate.hpp).
  // The window lies in the record: before its first row there are no currents to drive with.
  const double in_record_s = std::max(0.0, out.trigger_time_s - r.time_s.front());
  const std::int64_t lead_steps =
      std::min(static_cast<std::int64_t>(std::llround(TriggerStateLeadSeconds(r) / dt)),
               static_cast<std::int64_t>(std::floor(in_record_s / dt + 1e-6)));
  const std::int64_t lead_step = closed && m.trigger_state_from_record && lead_steps > 0
                                     ? std::max<std::int64_t>(0, model.trigger_step - lead_steps)
                                     : -1;
  bool lead_driven = false;
  // Where a run's levitated time ends for the runs that resume from it: the trigger's step, or
  // the lead window's start, whose fit reads the run's own model.
  const std::int64_t resume_step = lead_step >= 0 ? lead_step : model.trigger_step;

  // Rows of the record to predict, and the step each falls on.
  const std::size_t record_rows = r.time_s.size();
  // Rows past run_end are not simulated; they stay NaN, as after a run that stopped.
  const std::size_t total_rows = static_cast<std::size_t>(
      std::upper_bound(r.time_s.begin(), r.time_s.end(), run_end + 0.5 * dt) - r.time_s.begin());
  out.first_row = static_cast<std::size_t>(
      std::lower_bound(r.time_s.begin(), r.time_s.end(), t_start - 0.5 * dt) - r.time_s.begin());
  out.values.assign(m.channels.size(), std::vector<double>(record_rows, kNaN));
  // The record's sampler: what the rows predict (noise and quantisation off, above; a drawn
  // jitter's noise drives the controller, not the expected reading).
  std::vector<SensorParams> expected = model.params.sensors;
  for (SensorParams& s : expected) s.noise.enabled = false;
  SensorEmulator sensors(expected, r.SampleInterval());
  const PowerEvent failure = ScheduledFailure(model);
  SensorReadings readings;
  std::size_t row = out.first_row;
  if (options.keep_states) out.states.assign(record_rows, Eigen::VectorXd());
  // The step each row was predicted at, while this run's levitated time is kept for others.
  const bool keeping = reusable && !resumed;
  std::vector<std::int64_t> row_step(keeping ? record_rows : 0, -1);
  // A TDB channel's value from what its TDB reports.
  const auto tdb_value = [&](std::size_t c, const TdbForce& f) {
    const MeasurementChannel& ch = m.channels[c];
    switch (ch.quantity) {
      case MeasuredQuantity::kTdbSupportForce: {
        const double support = ch.axis == 0 ? f.support_x_N : f.support_y_N;
        if (std::isnan(model_tare[c])) model_tare[c] = support;
        return support - model_tare[c] + record_tare[c];
      }
      case MeasuredQuantity::kTdbNormalForce:
        return f.normal_force_N;
      case MeasuredQuantity::kTdbSpeed:
        return f.tdb_spin_rad_s;
      default:
        return kNaN;
    }
  };
  const auto record_row = [&](const StepDriver& d, std::size_t j) {
    const State& state = d.state();
    if (keeping) row_step[j] = state.step_index;
    const ControlInput& input = d.input();
    if (options.keep_states) out.states[j] = state.y.head(2 * n);
    Observation obs;
    d.sim().Observe(state, &obs);
    sensors.Sample(obs, &readings);
    for (std::size_t c = 0; c < m.channels.size(); ++c) {
      const MeasurementChannel& ch = m.channels[c];
      double v = kNaN;
      switch (ch.quantity) {
        case MeasuredQuantity::kDisplacement:
          v = readings.reading_m[ch.index][ch.axis];
          break;
        case MeasuredQuantity::kCurrent:
          // The coil's control current: what flows, fading with the flux after power loss.
          v = input.amb[ch.index].current_A[ch.axis] *
              std::sqrt(std::max(0.0, input.amb[ch.index].force_scale[ch.axis]));
          break;
        case MeasuredQuantity::kControllerCommand:
          // Open loop no controller runs: the command after the trigger is unknown (the record's
          // command channel is then not compared, tools/fit/record_cost.hpp).
          v = closed ? command_A[ch.index][ch.axis] : kNaN;
          break;
        case MeasuredQuantity::kTdbSupportForce:
        case MeasuredQuantity::kTdbNormalForce:
        case MeasuredQuantity::kTdbSpeed:
          v = tdb_value(c, obs.tdb[ch.index]);
          break;
        case MeasuredQuantity::kRotorSpeed:
          v = obs.spin_speed_rad_s;
          break;
      }
      out.values[c][j] = v;
    }
  };

  // The record's sources around the step driver.
  struct RecordHooks : StepHooks {
    std::function<void(StepDriver&, std::int64_t)> begin, power, command;
    std::function<bool(StepDriver&)> before;
    void BeginStep(StepDriver& d, std::int64_t k) noexcept { begin(d, k); }
    void PowerEvents(StepDriver& d, std::int64_t k) noexcept { power(d, k); }
    bool Command(StepDriver& d, std::int64_t k) noexcept {
      command(d, k);
      return true;
    }
    bool BeforeStep(StepDriver& d) noexcept { return before(d); }
  } hooks;
  hooks.begin = [&](StepDriver& d, std::int64_t k) {
    if (k == model.trigger_step && options.trigger_state_shift.size() == 2 * n) {
      d.mutable_state().y.head(2 * n) += options.trigger_state_shift;
    }
  };
  hooks.power = [&](StepDriver& d, std::int64_t k) {
    if (k != model.trigger_step) return;
    // What flowed when power failed is what was measured then: a controller answers its
    // sensors' noise, so the model's own command at that instant is off by that jitter. The
    // power state freezes the input's currents.
    for (std::size_t a = 0; a < model.params.ambs.size(); ++a) {
      for (int axis = 0; axis < 2; ++axis) {
        if (current_column[a][axis] >= 0)
          d.mutable_input().amb[a].current_A[axis] = held_A[a][axis];
      }
    }
    d.ApplyPower(failure);
  };
  hooks.command = [&](StepDriver& d, std::int64_t k) {
    if (controlled && k % substeps == 0) {
      controller->Update(d.readings(), &input);
      keep_command();
    }
    if (controlled && controller->advances_amplifier()) {
      controller->Advance(&input);
      keep_command();
    }
    if ((!closed || lead_driven) && k < model.trigger_step) {
      measured_currents(t_start + static_cast<double>(k) * dt, false);
    }
    if (!controlled) keep_command();
    for (std::size_t a = 0; a < model.params.ambs.size(); ++a) {
      d.command()[a] = input.amb[a].current_A;
    }
  };
  hooks.before = [&](StepDriver& d) {
    const std::int64_t k = d.state().step_index;
    const double t_record = t_start + static_cast<double>(k) * dt;
    if (k >= model.trigger_step) {
      const double seconds = static_cast<double>(k - model.trigger_step) * dt;
      ControlInput& in = d.mutable_input();
      for (std::size_t a = 0; a < model.params.ambs.size(); ++a) {
        for (int axis = 0; axis < 2; ++axis) {
          const int c = driven_column[a][axis];
          if (c < 0) continue;
          const double recorded_A = ValueAt(r, c, t_record);
          if (d.power().powered(static_cast<int>(a), axis)) {
            in.amb[a].current_A[axis] = recorded_A;
            continue;
          }
          const UnpoweredDrive u =
              RecordedCurrentDrive(model.params.ambs[a], held_A[a][axis], recorded_A, seconds);
          in.amb[a].current_A[axis] = u.current_A;
          in.amb[a].force_scale[axis] = u.force_scale;
          in.amb[a].bias_scale[axis] = u.bias_scale;
        }
      }
    }
    // Rows on this step (the nearest step to their time) are predicted from this state, with
    // the currents applied over this step.
    while (row < total_rows && r.time_s[row] < t_record + 0.5 * dt) {
      if (r.time_s[row] >= t_record - 0.5 * dt) {
        record_row(d, row);
        ++out.rows;
      }
      ++row;
    }
    return row < total_rows;
  };
  const bool any_rows = row < total_rows;
  if (resumed) {
    const LevitatedPrefix& p = *resumed->prefix;
    StepDriver::Snapshot at_trigger = p.driver;
    // The rotor's part is the cached run's; each TDB's, in this model's layout, its own.
    at_trigger.state.y = StateVector::Zero(model.state_size);
    at_trigger.state.y.head(2 * n + 2) = p.driver.state.y.head(2 * n + 2);
    for (std::size_t i = 0; i < model.tdbs.size(); ++i) {
      at_trigger.state.y.segment(model.tdb_state_offset[i], model.tdbs[i]->StateSize()) =
          resumed->tdbs[i].state;
    }
    driver.Restore(at_trigger);
    sensors = *p.record_sensors;
    input = p.input;
    command_A = p.command;
    row = p.row;
    out.rows = p.rows;
    for (std::size_t c = 0; c < m.channels.size(); ++c) {
      std::copy(p.values[c].begin(), p.values[c].end(), out.values[c].begin());
    }
    if (options.keep_states) std::copy(p.states.begin(), p.states.end(), out.states.begin());
    model_tare = p.model_tare;
    // A changed TDB's channels as it reported them at the cached rows.
    for (std::size_t c = 0; c < m.channels.size(); ++c) {
      const MeasurementChannel& ch = m.channels[c];
      const bool of_a_tdb = ch.quantity == MeasuredQuantity::kTdbSupportForce ||
                            ch.quantity == MeasuredQuantity::kTdbNormalForce ||
                            ch.quantity == MeasuredQuantity::kTdbSpeed;
      if (!of_a_tdb || !resumed->tdbs[ch.index].changed) continue;
      model_tare[c] = kNaN;
      for (std::size_t j = 0; j < p.row; ++j) {
        if (p.row_step[j] >= 0) out.values[c][j] = tdb_value(c, resumed->tdbs[ch.index].at_row[j]);
      }
    }
  } else {
    driver.SetInput(input);
    driver.Start(state);
  }
  if (any_rows) {
    for (;;) {
      if (keeping && driver.state().step_index <= resume_step) {
        clearance.Watch(model, driver.state().y);
        if (driver.state().step_index == resume_step) {
          auto kept = std::make_shared<LevitatedPrefix>();
          kept->params = model.params;
          kept->measurement = m;
          kept->record_fingerprint = fingerprint;
          kept->keep_states = options.keep_states;
          for (std::size_t i = 0; i < model.tdbs.size(); ++i) {
            kept->tdb_free[i] =
                JournalFree(clearance.journal_reach_m[i], clearance.free_radius_m[i]);
          }
          kept->journal_reach_m = clearance.journal_reach_m;
          kept->settle_steps = settle_steps;
          kept->steps = resume_step;
          kept->tdb_state_offset = model.tdb_state_offset;
          kept->driver = driver.TakeSnapshot();
          kept->controller = controller;
          kept->record_sensors = sensors;
          kept->input = input;
          kept->command = command_A;
          kept->row = row;
          kept->rows = out.rows;
          for (const std::vector<double>& v : out.values) {
            kept->values.emplace_back(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(row));
          }
          if (options.keep_states) {
            kept->states.assign(out.states.begin(),
                                out.states.begin() + static_cast<std::ptrdiff_t>(row));
          }
          kept->model_tare = model_tare;
          kept->row_step.assign(row_step.begin(),
                                row_step.begin() + static_cast<std::ptrdiff_t>(row));
          options.prefix_cache->Insert(std::move(kept));
        }
      }
      // The lead window's fit runs between steps, outside the noexcept step: it may throw.
      if (driver.state().step_index == lead_step && !lead_driven) {
        fit_lead_window(driver.mutable_state(),
                        static_cast<double>(model.trigger_step - lead_step) * dt);
        lead_driven = true;
      }
      if (!driver.Step(hooks)) break;
    }
    if (!driver.stopped()) {
      out.status = driver.status();
      out.failure = DescribeFailure(model, driver.status(), driver.state());
    }
  }
  return out;
}

}  // namespace

SimulatedRecord SimulateOnRecord(const ModelParams& declared, const MeasurementParams& m,
                                 const MeasuredRecord& r, const RecordRunOptions& options) {
  SimulatedRecord out = RunOnRecord(declared, m, r, options);
  out.state_from_record = m.trigger_state_from_record;
  // A cost may run it again its own way: a part that takes the state at the trigger otherwise,
  // the levitated spectrum's noise draws (RecordCost::Residual).
  out.params = std::make_shared<const ModelParams>(declared);
  out.options = options;
  return out;
}

}  // namespace ambdrop
