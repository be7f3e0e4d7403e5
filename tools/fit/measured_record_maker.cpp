#include "tools/fit/measured_record_maker.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include "controller_if/boundary/portable_random.hpp"
#include "controller_if/boundary/sensor_emulator.hpp"
#include "controller_if/loop/offline_run.hpp"
#include "rt_core/model.hpp"
#include "tools/fit/current_sampler.hpp"

namespace ambdrop {
namespace {

using Currents = CurrentSampler::Currents;

/// The columns in a fixed order (groups as listed in MeasureChannelGroups), whatever order the
/// groups were asked for in, so one set of groups always gives one file.
std::vector<MeasurementChannel> Channels(const ModelParams& p, const MeasureChannelGroups& g) {
  std::vector<MeasurementChannel> out;
  if (g.displacement) {
    for (std::size_t i = 0; i < p.sensors.size(); ++i) {
      for (int axis = 0; axis < 2; ++axis) {
        out.push_back(MeasurementChannel::Of(
            fmt::format("{}_{}", MeasurementAxisName(axis), p.sensors[i].name),
            MeasuredQuantity::kDisplacement, static_cast<int>(i), axis));
      }
    }
  }
  if (g.current) {
    for (std::size_t a = 0; a < p.ambs.size(); ++a) {
      for (int axis = 0; axis < 2; ++axis) {
        out.push_back(MeasurementChannel::Of(
            fmt::format("i_{}_{}", p.ambs[a].name, MeasurementAxisName(axis)),
            MeasuredQuantity::kCurrent, static_cast<int>(a), axis));
      }
    }
  }
  if (g.tdb_normal_force) {
    for (std::size_t t = 0; t < p.tdbs.size(); ++t) {
      out.push_back(MeasurementChannel::Of("f_" + p.tdbs[t].name, MeasuredQuantity::kTdbNormalForce,
                                           static_cast<int>(t), -1));
    }
  }
  if (g.tdb_speed) {
    for (std::size_t t = 0; t < p.tdbs.size(); ++t) {
      out.push_back(MeasurementChannel::Of("w_" + p.tdbs[t].name, MeasuredQuantity::kTdbSpeed,
                                           static_cast<int>(t), -1));
    }
  }
  if (g.rotor_speed)
    out.push_back(MeasurementChannel::Of("w_rotor", MeasuredQuantity::kRotorSpeed, -1, -1));
  // The later groups come last, so that records without them keep their columns.
  if (g.controller_command) {
    for (std::size_t a = 0; a < p.ambs.size(); ++a) {
      for (int axis = 0; axis < 2; ++axis) {
        out.push_back(MeasurementChannel::Of(
            fmt::format("cmd_{}_{}", p.ambs[a].name, MeasurementAxisName(axis)),
            MeasuredQuantity::kControllerCommand, static_cast<int>(a), axis));
      }
    }
  }
  if (g.tdb_support_force) {
    for (std::size_t t = 0; t < p.tdbs.size(); ++t) {
      for (int axis = 0; axis < 2; ++axis) {
        out.push_back(MeasurementChannel::Of(
            fmt::format("fs_{}_{}", p.tdbs[t].name, MeasurementAxisName(axis)),
            MeasuredQuantity::kTdbSupportForce, static_cast<int>(t), axis));
      }
    }
  }
  // A TDB named "rotor" would collide with the rotor's speed column.
  std::set<std::string> seen;
  for (const MeasurementChannel& c : out) {
    if (!seen.insert(c.column).second) {
      throw std::invalid_argument("two channels would both be named '" + c.column +
                                  "': rename a sensor, AMB or TDB");
    }
  }
  if (out.empty()) throw std::invalid_argument("no channels to record");
  return out;
}

double ObservedValue(const MeasurementChannel& c, const Observation& obs,
                     const SensorReadings& readings) {
  switch (c.quantity) {
    case MeasuredQuantity::kDisplacement:
      return readings.reading_m[c.index][c.axis];
    case MeasuredQuantity::kTdbNormalForce:
      return obs.tdb[c.index].normal_force_N;
    case MeasuredQuantity::kTdbSpeed:
      return obs.tdb[c.index].tdb_spin_rad_s;
    case MeasuredQuantity::kRotorSpeed:
      return obs.spin_speed_rad_s;
    case MeasuredQuantity::kTdbSupportForce:
      // What a load cell under the TDB reads, untared (io/config/config_measurement.hpp).
      return c.axis == 0 ? obs.tdb[c.index].support_x_N : obs.tdb[c.index].support_y_N;
    case MeasuredQuantity::kCurrent:
    case MeasuredQuantity::kControllerCommand:
      break;  // filled after the run (CurrentSampler)
  }
  return 0.0;
}

double NoiseStdDev(const MeasurementChannel& c, const MeasureOptions& o) {
  switch (c.quantity) {
    case MeasuredQuantity::kCurrent:
    case MeasuredQuantity::kControllerCommand:
      return o.current_noise_A;
    case MeasuredQuantity::kTdbNormalForce:
    case MeasuredQuantity::kTdbSupportForce:
      return o.force_noise_N;
    case MeasuredQuantity::kTdbSpeed:
    case MeasuredQuantity::kRotorSpeed:
      return o.speed_noise_rad_s;
    case MeasuredQuantity::kDisplacement:
      break;  // the truth config's own sensor noise
  }
  return 0.0;
}

/// One noise stream per channel, keyed by what it measures rather than by its column position,
/// so leaving a group out (--channels) does not change the noise on the others.
std::uint64_t StreamSeed(std::uint64_t seed, const MeasurementChannel& c) {
  constexpr std::uint64_t kStreams = 64;
  std::uint64_t id = 0;
  switch (c.quantity) {
    case MeasuredQuantity::kCurrent:
      id = 1 + 2 * static_cast<std::uint64_t>(c.index) + static_cast<std::uint64_t>(c.axis);
      break;
    case MeasuredQuantity::kTdbNormalForce:
      id = 16 + static_cast<std::uint64_t>(c.index);
      break;
    case MeasuredQuantity::kTdbSpeed:
      id = 32 + static_cast<std::uint64_t>(c.index);
      break;
    case MeasuredQuantity::kRotorSpeed:
      id = 48;
      break;
    case MeasuredQuantity::kControllerCommand:
      id = 49 + 2 * static_cast<std::uint64_t>(c.index) + static_cast<std::uint64_t>(c.axis);
      break;
    case MeasuredQuantity::kTdbSupportForce:
      // After the normal forces' ids, below the speeds'.
      id = 16 + kMaxTdbs + 2 * static_cast<std::uint64_t>(c.index) +
           static_cast<std::uint64_t>(c.axis);
      break;
    case MeasuredQuantity::kDisplacement:
      break;
  }
  static_assert(2 * kMaxAmbs < 16 && 3 * kMaxTdbs <= 16 && 49 + 2 * kMaxAmbs <= kStreams,
                "stream ids overlap");
  return seed * kStreams + id;
}

/// A TOML float that reads back to the same double ("{}" is the shortest round trip; TOML needs
/// a point or an exponent to make it a float).
std::string TomlFloat(double value) {
  std::string text = fmt::format("{}", value);
  if (text.find_first_of(".eEn") == std::string::npos) text += ".0";
  return text;
}

std::string TomlString(const std::string& value) {
  std::string out = "\"";
  for (const char ch : value) {
    if (ch == '"' || ch == '\\') {
      out += '\\';
      out += ch;
    } else if (static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f) {
      out += fmt::format("\\u{:04X}", static_cast<unsigned char>(ch));
    } else {
      out += ch;
    }
  }
  return out + "\"";
}

}  // namespace

std::int64_t StepsPerSample(const SimulationParams& simulation, double rate_Hz) {
  const double ratio = 1.0 / (rate_Hz * simulation.step_s);
  const std::int64_t n = std::isfinite(ratio) ? std::llround(ratio) : 0;
  // Same tolerance as the controller rate (ControllerSubsteps).
  if (!(rate_Hz > 0.0) || n < 1 || std::abs(ratio - static_cast<double>(n)) > 1e-6 * ratio) {
    throw std::invalid_argument(
        fmt::format("sample rate {} Hz: the sample period must be a whole number of physics "
                    "steps ({} s), e.g. {} Hz",
                    rate_Hz, simulation.step_s,
                    1.0 / (static_cast<double>(std::max<std::int64_t>(n, 1)) * simulation.step_s)));
  }
  return n;
}

SyntheticMeasurement MakeMeasuredRecord(const ModelParams& truth, const MeasureOptions& options) {
  const double rate_Hz = options.rate_Hz > 0.0 ? options.rate_Hz : truth.controller.rate_Hz;
  const std::int64_t every = StepsPerSample(truth.simulation, rate_Hz);
  const double dt = truth.simulation.step_s;
  const double period_s = static_cast<double>(every) * dt;

  ModelParams params = truth;
  // Observations then arrive exactly at the sample times.
  params.simulation.output_interval_s = period_s;
  const Model model = BuildModel(params);

  SyntheticMeasurement out;
  out.measurement.sample_rate_Hz = rate_Hz;
  if (truth.trigger.enabled) {
    out.measurement.trigger_time_s = truth.trigger.time_s;
  } else {
    out.measurement.detect_trigger = true;
  }
  out.measurement.channels = Channels(truth, options.channels);
  const std::vector<MeasurementChannel>& channels = out.measurement.channels;

  MeasuredRecord& record = out.record;
  record.source = "truth run of " + (truth.name.empty() ? std::string("the rig") : truth.name);
  for (const MeasurementChannel& c : channels) record.columns.push_back(c.column);
  record.values.resize(channels.size());
  const std::size_t expected_rows = static_cast<std::size_t>(model.total_steps / every) + 1;
  record.time_s.reserve(expected_rows);
  for (std::vector<double>& v : record.values) v.reserve(expected_rows);

  // The emulator's own sensor model at the record's rate: a second instance beside the one the
  // internal controller reads, with the same parameters (so the same statistics and seeds).
  SensorEmulator sensors(truth.sensors, period_s);
  SensorReadings readings;
  CurrentSampler currents(model.params, dt);
  std::int64_t sample = 0;
  const auto on_output = [&](const Observation& obs) {
    sensors.Sample(obs, &readings);
    record.time_s.push_back(obs.time_s);
    for (std::size_t c = 0; c < channels.size(); ++c) {
      record.values[c].push_back(ObservedValue(channels[c], obs, readings));
    }
    currents.AddSample(sample * every);
    ++sample;
  };
  const OfflineRunResult result = RunOffline(model, on_output, options.on_progress, &currents);
  if (result.status != StepStatus::kOk) {
    // The message names the time and the cause, with a state dump.
    throw TruthRunDiverged("the truth run failed: " + result.failure_message);
  }

  const std::vector<Currents>& current_A = currents.Finish();
  const std::vector<Currents>& command_A = currents.Commanded();
  for (std::size_t c = 0; c < channels.size(); ++c) {
    const MeasurementChannel& ch = channels[c];
    if (ch.quantity == MeasuredQuantity::kCurrent) {
      for (std::size_t row = 0; row < current_A.size(); ++row) {
        record.values[c][row] = current_A[row][ch.index][ch.axis];
      }
    }
    if (ch.quantity == MeasuredQuantity::kControllerCommand) {
      for (std::size_t row = 0; row < command_A.size(); ++row) {
        record.values[c][row] = command_A[row][ch.index][ch.axis];
      }
    }
    // Noise over every sample, before rows are dropped: a later --from-s cuts the same record.
    const double sigma = NoiseStdDev(ch, options);
    if (sigma > 0.0) {
      PortableRandom noise(StreamSeed(options.seed, ch));
      for (double& v : record.values[c]) v += sigma * noise.StandardNormalApprox();
    }
  }

  // Half a physics step of slack: T0 given in decimal lands on the sample it names.
  const auto first =
      std::lower_bound(record.time_s.begin(), record.time_s.end(), options.from_s - 0.5 * dt);
  const auto drop = first - record.time_s.begin();
  if (first == record.time_s.end()) {
    throw std::invalid_argument(fmt::format("no sample at or after {} s (the run ends at {} s)",
                                            options.from_s,
                                            record.time_s.empty() ? 0.0 : record.time_s.back()));
  }
  record.time_s.erase(record.time_s.begin(), first);
  for (std::vector<double>& v : record.values) v.erase(v.begin(), v.begin() + drop);
  return out;
}

std::string MeasurementTableToml(const ModelParams& truth, const MeasurementParams& m) {
  std::string out = "[measurement]\n";
  out += "sample_rate_Hz = " + TomlFloat(m.sample_rate_Hz) + "\n";
  if (m.time_column != "t") out += "time_column = " + TomlString(m.time_column) + "\n";
  if (m.time_unit != "s") out += "time_unit = " + TomlString(m.time_unit) + "\n";
  if (m.trigger_time_s) {
    out += "trigger_time_s = " + TomlFloat(*m.trigger_time_s) + "\n";
  } else {
    out += "trigger = \"detect\"\n";
  }
  if (m.power_loss == PowerLossSource::kFromRecord) out += "power_loss = \"from_record\"\n";
  for (const MeasurementChannel& c : m.channels) {
    out += "\n[[measurement.channel]]\n";
    out += "column = " + TomlString(c.column) + "\n";
    out += fmt::format("quantity = \"{}\"\n", MeasuredQuantityName(c.quantity));
    switch (c.quantity) {
      case MeasuredQuantity::kDisplacement:
        out += "sensor = " + TomlString(truth.sensors.at(c.index).name) + "\n";
        break;
      case MeasuredQuantity::kCurrent:
      case MeasuredQuantity::kControllerCommand:
        out += "amb = " + TomlString(truth.ambs.at(c.index).name) + "\n";
        break;
      case MeasuredQuantity::kTdbNormalForce:
      case MeasuredQuantity::kTdbSupportForce:
      case MeasuredQuantity::kTdbSpeed:
        out += "tdb = " + TomlString(truth.tdbs.at(c.index).name) + "\n";
        break;
      case MeasuredQuantity::kRotorSpeed:
        break;
    }
    if (c.axis >= 0) out += fmt::format("axis = \"{}\"\n", MeasurementAxisName(c.axis));
    if (!c.unit.empty()) {
      out += "unit = " + TomlString(c.unit) + "\n";
    } else if (c.scale != 1.0) {
      out += "scale = " + TomlFloat(c.scale) + "\n";
    }
    if (c.window == ChannelWindow::kBeforeTrigger) out += "window = \"before_trigger\"\n";
    if (c.window == ChannelWindow::kAfterTrigger) out += "window = \"after_trigger\"\n";
    if (c.from_s) out += "from_s = " + TomlFloat(*c.from_s) + "\n";
    if (c.to_s) out += "to_s = " + TomlFloat(*c.to_s) + "\n";
  }
  return out;
}

}  // namespace ambdrop
