#include "tools/fit/start_sensitivity.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

#include "tools/fit/effect_selection.hpp"
#include "tools/fit/noise_floor.hpp"
#include "tools/fit/parallel_for.hpp"
#include "tools/fit/simulate_on_record.hpp"
#include "tools/fit/trigger_state_probes.hpp"

namespace ambdrop {

// How far the declared model's prediction moves when the rotor's levitated orbit is shifted by
// a third of the displacement noise: a synchronous runout on each measured sensor, at two
// phases, which the controller follows. The real rotor jitters at the trigger by about the
// sensors' noise (its controller answers that noise), which no model reproduces sample by
// sample: a drop whose bounces, rest or whirl depend on less than that cannot be fitted below
// this spread, whatever the effect. 0 without displacement channels.
double DisplacementNoiseMedian(const RecordCost& cost) {
  return cost.sensor_noise().sigma_m;
}

namespace {

// Median of `v` (0 when empty).
double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t h = v.size() / 2;
  return v.size() % 2 == 1 ? v[h] : 0.5 * (v[h - 1] + v[h]);
}

// The start term channel by channel (StartSensitivity's `per_channel`), from each run's squared
// moves per channel (runs [0, probes) the probes, [probes, fixed) the trigger state's axes in
// pairs, the rest the jitter's draws): the largest probe, the axes in quadrature and the widest
// draw. The widest, not the typical one: one channel alone follows a draw whose first impact
// turns another way by that impact's whole move, where the sum over every channel averages it.
// Empty without draws: the rule that reads it was measured where they run.
std::vector<double> ChannelStartSensitivity(const std::vector<std::vector<double>>& sse,
                                            std::size_t probes, std::size_t fixed) {
  if (sse.size() <= fixed) return {};
  const std::size_t channels = sse.front().size();
  std::vector<double> out(channels, 0.0);
  for (std::size_t c = 0; c < channels; ++c) {
    double widest = 0.0;
    for (std::size_t i = 0; i < probes; ++i) widest = std::max(widest, sse[i][c]);
    double along_axes = 0.0;
    for (std::size_t k = probes; k + 1 < fixed; k += 2) {
      along_axes += std::max(sse[k][c], sse[k + 1][c]);
    }
    widest = std::max(widest, along_axes);
    for (std::size_t i = fixed; i < sse.size(); ++i) widest = std::max(widest, sse[i][c]);
    out[c] = std::sqrt(widest);
  }
  return out;
}

}  // namespace

double StartSensitivity(const ConfigVariants& declared, const RecordCost& cost,
                        const Eigen::VectorXd& residual_before, int threads, int draws,
                        std::vector<double>* per_channel) {
  const MeasurementParams& m = cost.measurement();
  const MeasuredRecord& r = cost.record();
  const ModelParams& params = cost.declared();
  std::vector<int> sensors;
  for (const MeasurementChannel& ch : m.channels) {
    if (ch.quantity != MeasuredQuantity::kDisplacement || r.Column(ch.column) < 0) continue;
    if (std::find(sensors.begin(), sensors.end(), ch.index) == sensors.end()) {
      sensors.push_back(ch.index);
    }
  }
  const double amplitude = DisplacementNoiseMedian(cost) / 3.0;
  if (!(amplitude > 0.0)) return 0.0;
  std::vector<std::vector<std::string>> variants;
  for (const int index : sensors) {
    const SensorParams& sensor = params.sensors[static_cast<std::size_t>(index)];
    const std::string table = "sensor." + sensor.name + ".runout.";
    const double declared_1x = sensor.runout.enabled ? sensor.runout.amplitude_1x_m : 0.0;
    for (const double phase : {0.0, 3.14159265358979323846}) {
      std::vector<std::string> o = {
          table + "enabled=true",
          table + "amplitude_1x_m=" + OverrideNumber(declared_1x + amplitude),
          table + "phase_1x_rad=" + OverrideNumber(phase)};
      if (!sensor.runout.enabled) o.push_back(table + "amplitude_2x_m=0.0");
      variants.push_back(std::move(o));
    }
  }
  // Open loop the start state is fitted to a quadratic through each displacement channel near
  // the start: the noise leaves its value and slope uncertain (OpenLoopStartUncertainty). On a
  // plant that the held currents leave unstable that slope decides where the rotor drifts.
  std::vector<RecordRunOptions> starts;
  const bool closed = ClosedLoop(params, m, cost.run_options());
  if (!closed && !m.trigger_state_from_record) {
    const double sigma = 3.0 * amplitude;  // the channels' median noise
    const auto [value_per_sigma, slope_per_sigma] =
        OpenLoopStartUncertainty(r, cost.compare_from_s());
    for (const double sign : {1.0, -1.0}) {
      RecordRunOptions o = cost.run_options();
      o.start_position_shift_m = sign * sigma * value_per_sigma;
      starts.push_back(o);
      o.start_position_shift_m = 0.0;
      o.start_velocity_shift_m_s = sign * sigma * slope_per_sigma;
      starts.push_back(o);
    }
  }
  // A state fitted to a lead window of the record (measurement.trigger_state) is as uncertain
  // as that fit's covariance says: probes either way along its largest principal axes where the
  // sensors see them (the spread of most records: trigger_state_probes.hpp; a record whose
  // noise drew it further off is the state shift's, start_state_shift.hpp), and along each held
  // current's, whose moves add in quadrature (the errors along them are independent).
  const std::vector<RecordRunOptions> axes =
      m.trigger_state_from_record
          ? TriggerStateProbes(cost, SimulateOnRecord(params, m, r, cost.run_options()),
                               TriggerStateAxes::kSeen)
          : std::vector<RecordRunOptions>();
  // On the drop's start, closed loop from the model's own levitated state: runs of it with its
  // controller answering sensor noise of the record's level (the rotor's jitter at the trigger
  // drawn, jitter_draws.hpp). A synchronous orbit shift does not span that jitter where the
  // held currents leave the rotor on the magnets' negative stiffness: a clean record of the
  // 4-DOF truth rig started 0.4 mm/s off the model's rest (its controller's 0.1 A current
  // jitter), and its start departed 0.0140 against a limit of 0.0134 set by a runout probe's
  // 0.0018; exact records of the same rig's seeds depart from 0.0022 to 0.0098, the jitter
  // alone. A typical draw's move is the start's sensitivity to that jitter.
  const int jitter_draws =
      cost.scope() == CostScope::kEarly && closed && !m.trigger_state_from_record
          ? std::max(0, draws)
          : 0;
  const std::size_t fixed = variants.size() + starts.size() + axes.size();
  std::vector<double> moved(fixed + static_cast<std::size_t>(jitter_draws), 0.0);
  std::vector<std::vector<double>> moved_by_channel(moved.size());
  // A probe that stops scores its unreached samples a full range off: as the largest move, that
  // would widen the limit past any residual. A model a hair from the declared one that does not
  // run the record is as unfit to hold against it as the declared one that does not. (A drawn
  // jitter's run that stops is one large move among the draws, whose median is taken.)
  const auto residual = [&](const SimulatedRecord& sim) {
    if (sim.status != StepStatus::kOk) {
      throw DeclaredModelStopped(fmt::format(
          "{}: a run of the declared model a hair from it (a probe of its sensitivity to its "
          "start) does not run to the record's end: {}",
          r.source, sim.failure));
    }
    return cost.Residual(sim);
  };
  ParallelFor(moved.size(), threads, [&](std::size_t i) {
    Eigen::VectorXd r_i;
    if (i < variants.size()) {
      r_i = residual(cost.Simulate(declared.With(variants[i]).params));
    } else if (i < variants.size() + starts.size()) {
      r_i = residual(SimulateOnRecord(params, m, r, starts[i - variants.size()]));
    } else if (i < fixed) {
      r_i = residual(SimulateOnRecord(params, m, r, axes[i - variants.size() - starts.size()]));
    } else {
      RecordRunOptions o = cost.run_options();
      o.jitter_sigma_m = 3.0 * amplitude;  // the displacement channels' median noise
      o.jitter_seed = static_cast<std::uint64_t>(i - fixed) + 1;
      r_i = cost.Residual(SimulateOnRecord(params, m, r, o));
    }
    moved[i] = OverallRms(cost, (r_i - residual_before).squaredNorm());
    if (per_channel != nullptr) moved_by_channel[i] = cost.ChannelSse(r_i - residual_before);
  });
  if (per_channel != nullptr) {
    *per_channel =
        ChannelStartSensitivity(moved_by_channel, variants.size() + starts.size(), fixed);
  }
  // A typical draw's move: a few draws whose first impact turns another way move the
  // impact-force channels by their whole impulse, and an RMS over eight draws followed them
  // (0.0075 against a median of 0.0028 on the rigid truth rig, where it hid a TDB offset).
  const double jitter =
      Median(std::vector<double>(moved.begin() + static_cast<std::ptrdiff_t>(fixed), moved.end()));
  double worst = 0.0;
  for (std::size_t i = 0; i < variants.size() + starts.size(); ++i) {
    worst = std::max(worst, moved[i]);
  }
  double along_axes = 0.0;
  for (std::size_t k = 0; k + 1 < axes.size(); k += 2) {
    const std::size_t i = variants.size() + starts.size() + k;
    along_axes += std::pow(std::max(moved[i], moved[i + 1]), 2);
  }
  return std::max({worst, std::sqrt(along_axes), jitter});
}

}  // namespace ambdrop
