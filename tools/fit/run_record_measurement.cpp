#include "tools/fit/run_record_measurement.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <set>
#include <stdexcept>
#include <vector>

#include "tools/fit/current_sampler.hpp"

namespace ambdrop {
namespace {

/// The columns in `ambdrop measure`'s order and with its names.
std::vector<MeasurementChannel> Channels(const ModelParams& p, bool with_states,
                                         bool with_commands) {
  std::vector<MeasurementChannel> out;
  for (std::size_t i = 0; i < p.sensors.size(); ++i) {
    for (int axis = 0; axis < 2; ++axis) {
      out.push_back(
          MeasurementChannel::Of(fmt::format("{}_{}", MeasurementAxisName(axis), p.sensors[i].name),
                                 MeasuredQuantity::kDisplacement, static_cast<int>(i), axis));
    }
  }
  for (std::size_t a = 0; a < p.ambs.size(); ++a) {
    for (int axis = 0; axis < 2; ++axis) {
      out.push_back(
          MeasurementChannel::Of(fmt::format("i_{}_{}", p.ambs[a].name, MeasurementAxisName(axis)),
                                 MeasuredQuantity::kCurrent, static_cast<int>(a), axis));
    }
  }
  if (with_states) {
    for (std::size_t t = 0; t < p.tdbs.size(); ++t) {
      out.push_back(MeasurementChannel::Of("f_" + p.tdbs[t].name, MeasuredQuantity::kTdbNormalForce,
                                           static_cast<int>(t), -1));
    }
    for (std::size_t t = 0; t < p.tdbs.size(); ++t) {
      out.push_back(MeasurementChannel::Of("w_" + p.tdbs[t].name, MeasuredQuantity::kTdbSpeed,
                                           static_cast<int>(t), -1));
    }
    out.push_back(MeasurementChannel::Of("w_rotor", MeasuredQuantity::kRotorSpeed, -1, -1));
  }
  if (with_commands) {
    for (std::size_t a = 0; a < p.ambs.size(); ++a) {
      for (int axis = 0; axis < 2; ++axis) {
        out.push_back(MeasurementChannel::Of(
            fmt::format("cmd_{}_{}", p.ambs[a].name, MeasurementAxisName(axis)),
            MeasuredQuantity::kControllerCommand, static_cast<int>(a), axis));
      }
    }
  }
  std::set<std::string> seen;
  for (const MeasurementChannel& c : out) {
    if (!seen.insert(c.column).second) {
      throw std::invalid_argument("two channels would both be named '" + c.column +
                                  "': rename a sensor, AMB or TDB");
    }
  }
  return out;
}

double StateValue(const MeasurementChannel& c, const RecordedStateSample& s) {
  switch (c.quantity) {
    case MeasuredQuantity::kTdbNormalForce:
      return s.tdb_normal_force_N[c.index];
    case MeasuredQuantity::kTdbSpeed:
      return s.tdb_race_speed_rad_s[c.index];
    case MeasuredQuantity::kRotorSpeed:
      return s.spin_speed_rad_s;
    case MeasuredQuantity::kDisplacement:
    case MeasuredQuantity::kCurrent:
    case MeasuredQuantity::kControllerCommand:
    case MeasuredQuantity::kTdbSupportForce:  // not in a record's state events
      break;
  }
  return 0.0;
}

}  // namespace

RecordAsMeasurement MeasurementFromRunRecord(const RunRecordFile& file, const ModelParams& params,
                                             bool with_commands) {
  const std::vector<RecordedSensors>& samples = file.sensors;
  const double step_s = file.header.step_s;
  if (!(step_s > 0.0)) throw std::invalid_argument("the record's step_s is not positive");
  if (samples.size() < 2) {
    throw std::invalid_argument(fmt::format(
        "the record holds {} sensor samples: a measurement needs at least two (a run without a "
        "controller sends none)",
        samples.size()));
  }
  if (params.sensors.size() > static_cast<std::size_t>(kMaxSensors) ||
      params.ambs.size() > static_cast<std::size_t>(kMaxAmbs) ||
      params.tdbs.size() > static_cast<std::size_t>(kMaxTdbs)) {
    throw std::invalid_argument("the rig has more sensors, AMBs or TDBs than a record carries");
  }
  for (const RecordedStateSample& s : file.states) {
    if (s.tdb_count != static_cast<int>(params.tdbs.size())) {
      throw std::invalid_argument(
          fmt::format("the record's state at step {} has {} TDBs; the rig has {}", s.step,
                      s.tdb_count, params.tdbs.size()));
    }
  }
  // A live run's recorder may have dropped samples: the period is the smallest gap.
  std::int64_t period_steps = 0;
  for (std::size_t j = 1; j < samples.size(); ++j) {
    const std::int64_t gap = samples[j].step - samples[j - 1].step;
    if (gap <= 0) {
      throw std::invalid_argument(fmt::format(
          "the record's sensor samples at step {} are not in step order", samples[j].step));
    }
    period_steps = period_steps == 0 ? gap : std::min(period_steps, gap);
  }

  RecordAsMeasurement out;
  MeasurementParams& m = out.measurement;
  m.sample_rate_Hz = 1.0 / (static_cast<double>(period_steps) * step_s);
  const auto failure = std::find_if(file.run.power.begin(), file.run.power.end(),
                                    [](const RecordedPower& p) { return !p.event.restore; });
  if (failure != file.run.power.end()) {
    m.trigger_time_s = static_cast<double>(failure->step) * step_s;
  } else {
    m.detect_trigger = true;
  }
  m.channels = Channels(params, !file.states.empty(), with_commands);

  MeasuredRecord& r = out.record;
  r.source = "run record";
  const std::size_t rows = samples.size();
  r.time_s.reserve(rows);
  for (const MeasurementChannel& c : m.channels) r.columns.push_back(c.column);
  r.values.assign(m.channels.size(), std::vector<double>(rows, 0.0));

  // The coil currents: the recorded events replayed through the sampler, power events before
  // the inputs of their step (as the run applied them).
  CurrentSampler currents(params, step_s);
  for (const RecordedSensors& s : samples) currents.AddSample(s.step);
  currents.OnStart(file.run.start);
  std::size_t next_power = 0;
  for (const RecordedInput& in : file.run.inputs) {
    for (; next_power < file.run.power.size() && file.run.power[next_power].step <= in.step;
         ++next_power) {
      currents.OnPower(file.run.power[next_power]);
    }
    currents.OnInput(in);
  }
  for (; next_power < file.run.power.size(); ++next_power) {
    currents.OnPower(file.run.power[next_power]);
  }
  const std::vector<CurrentSampler::Currents>& current_A = currents.Finish();
  const std::vector<CurrentSampler::Currents>& command_A = currents.Commanded();

  std::size_t state = 0;  // the last state at or before the row (the first before any)
  for (std::size_t row = 0; row < rows; ++row) {
    const RecordedSensors& s = samples[row];
    r.time_s.push_back(s.time_s);
    while (state + 1 < file.states.size() && file.states[state + 1].step <= s.step) ++state;
    for (std::size_t c = 0; c < m.channels.size(); ++c) {
      const MeasurementChannel& ch = m.channels[c];
      double& v = r.values[c][row];
      switch (ch.quantity) {
        case MeasuredQuantity::kDisplacement:
          v = s.readings.reading_m[ch.index][ch.axis];
          break;
        case MeasuredQuantity::kCurrent:
          v = current_A[row][ch.index][ch.axis];
          break;
        case MeasuredQuantity::kControllerCommand:
          v = command_A[row][ch.index][ch.axis];
          break;
        case MeasuredQuantity::kTdbSupportForce:
        case MeasuredQuantity::kTdbNormalForce:
        case MeasuredQuantity::kTdbSpeed:
        case MeasuredQuantity::kRotorSpeed:
          v = StateValue(ch, file.states[state]);
          break;
      }
    }
  }
  return out;
}

}  // namespace ambdrop
