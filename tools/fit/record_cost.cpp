#include "tools/fit/record_cost.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <stdexcept>
#include <utility>

#include "tools/fit/noise_floor.hpp"
#include "tools/fit/synchronous_blocks.hpp"

namespace ambdrop {
namespace {

// Free fall across the smallest clearance, with margin, then a few milliseconds of the first
// impact: the part of the drop a model predicts sample by sample.
double EarlySeconds(const ModelParams& p) {
  double c = 1e-3;
  for (const TdbParams& t : p.tdbs) c = std::min(c, t.clearance_m);
  const double g = p.gravity.enabled ? p.gravity.acceleration_m_s2 : 0.0;
  const double fall = g > 0 ? std::sqrt(2.0 * c / g) : 5e-3;
  return 1.5 * fall + 5e-3;
}

// Where the measured rotor has fallen through 90 % of its way to where it settles (about its
// first contact), plus a few milliseconds of that impact; the free-fall estimate without
// displacement channels. A force that fades after power loss slows the fall, so the record
// is the better judge. Only the channels that fall: those whose way is at least half the
// clearance. At a quarter, a horizontal axis settling 91 um aside (its TDB off-centre by a
// third of the 300 um clearance) passed 90 % of its way while the rotor still fell, and the
// start ended 5 ms after the trigger, before the other TDB's first contact: no key of that TDB
// moved the start, and its friction could not be found.
double EarlyEnd(const MeasurementParams& m, const MeasuredRecord& r, double trigger_s,
                const ModelParams& declared) {
  const std::size_t rows = r.time_s.size();
  const std::size_t trigger_row = static_cast<std::size_t>(
      std::lower_bound(r.time_s.begin(), r.time_s.end(), trigger_s) - r.time_s.begin());
  const double settle_from = r.time_s.back() - std::min((r.time_s.back() - trigger_s) / 3.0, 0.1);
  double first = std::numeric_limits<double>::infinity();
  for (const MeasurementChannel& ch : m.channels) {
    if (ch.quantity != MeasuredQuantity::kDisplacement || trigger_row >= rows) continue;
    const std::vector<double>& v = r.values[r.Column(ch.column)];
    double settled = 0.0;
    int n = 0;
    for (std::size_t j = trigger_row; j < rows; ++j) {
      if (r.time_s[j] >= settle_from) {
        settled += v[j];
        ++n;
      }
    }
    if (n == 0) continue;
    settled /= n;
    const double way = settled - v[trigger_row];
    if (std::abs(way) < 0.5 * declared.tdbs.front().clearance_m) continue;
    for (std::size_t j = trigger_row; j < rows; ++j) {
      if ((v[j] - v[trigger_row]) / way >= 0.9) {
        first = std::min(first, r.time_s[j]);
        break;
      }
    }
  }
  if (!std::isfinite(first)) return trigger_s + EarlySeconds(declared);
  return first + 5e-3;
}

bool SpeedLike(MeasuredQuantity q) {
  return q == MeasuredQuantity::kTdbSpeed || q == MeasuredQuantity::kRotorSpeed;
}

bool Smooth(MeasuredQuantity q) {
  return q == MeasuredQuantity::kTdbSpeed || q == MeasuredQuantity::kRotorSpeed ||
         q == MeasuredQuantity::kCurrent;
}

// A controller's output answers its sensors' noise as the coil current does while levitated.
bool CurrentLike(MeasuredQuantity q) {
  return q == MeasuredQuantity::kCurrent || q == MeasuredQuantity::kControllerCommand;
}

bool ForceLike(MeasuredQuantity q) {
  return q == MeasuredQuantity::kTdbNormalForce || q == MeasuredQuantity::kTdbSupportForce;
}

// Rows [first, last) of the record inside [from, to) and the channel's window.
std::pair<std::size_t, std::size_t> RowsIn(const MeasuredRecord& r, const MeasurementChannel& ch,
                                           double trigger_s, std::size_t first, std::size_t last) {
  while (first < last && !ch.InWindow(r.time_s[first], trigger_s)) ++first;
  std::size_t end = first;
  while (end < last && ch.InWindow(r.time_s[end], trigger_s)) ++end;
  return {first, end};
}

}  // namespace

MeasurementParams MeasurementFor(const MeasurementParams& measurement, CostScope scope) {
  MeasurementParams m = measurement;
  if (m.trigger_state_for_start && scope == CostScope::kEarly) m.trigger_state_from_record = true;
  if (scope == CostScope::kLevitated || scope == CostScope::kSpectrum) {
    m.trigger_state_from_record = false;
    m.trigger_state_for_start = false;
  }
  return m;
}

RecordCost::RecordCost(const ModelParams& declared, const MeasurementParams& measurement,
                       const MeasuredRecord& record, const RecordRunOptions& run,
                       std::size_t max_samples_per_channel, CostScope scope,
                       const std::vector<bool>& compared)
    : declared_(declared),
      measurement_(MeasurementFor(measurement, scope)),
      record_(record),
      run_(run),
      scope_(scope) {
  trigger_s_ = RecordTriggerTime(measurement, record);
  if (!run_.rotor_cache) run_.rotor_cache = std::make_shared<ReducedRotorCache>();
  if (!run_.prefix_cache) run_.prefix_cache = std::make_shared<LevitatedPrefixCache>();
  // The displacement noise before the trigger, white or coloured: its bandwidth goes with
  // every jitter drawn on this cost's runs.
  {
    std::size_t last = 0;
    while (last < record.time_s.size() && record.time_s[last] < trigger_s_) ++last;
    std::vector<SensorNoise> each;
    std::vector<std::size_t> channel_of;
    for (std::size_t c = 0; c < measurement_.channels.size(); ++c) {
      const MeasurementChannel& ch = measurement_.channels[c];
      const int col = record.Column(ch.column);
      if (ch.quantity != MeasuredQuantity::kDisplacement || col < 0) continue;
      each.push_back(ChannelSensorNoise(record.time_s, record.values[col], 0, last,
                                        declared.simulation.spin_speed_rad_s));
      channel_of.push_back(c);
    }
    sensor_noise_ = MedianSensorNoise(each);
    run_.jitter_bandwidth_Hz = sensor_noise_.bandwidth_Hz;
    coloured_sigma_.assign(measurement_.channels.size(), 0.0);
    for (std::size_t k = 0; k < each.size() && sensor_noise_.bandwidth_Hz > 0.0; ++k) {
      if (each[k].bandwidth_Hz > 0.0) coloured_sigma_[channel_of[k]] = each[k].sigma_m;
    }
  }
  const bool closed = ClosedLoop(declared, measurement, run);
  const double t0 = record.time_s.front();
  const double t_end = record.time_s.back();
  compare_from_s_ = closed ? t0 : std::max(t0, trigger_s_ - run.lead_s);
  early_end_s_ = std::min(t_end, EarlyEnd(measurement, record, trigger_s_, declared));
  settled_from_s_ = t_end - std::min((t_end - trigger_s_) / 3.0, 0.1);
  const bool early_only = scope == CostScope::kEarly;
  if (early_only) run_.end_s = std::min(run_.end_s, early_end_s_);
  const bool spectrum = scope == CostScope::kSpectrum;
  const bool levitated = scope == CostScope::kLevitated || spectrum;
  // Open loop nothing levitates the model before the trigger: no levitated part.
  if (levitated && !closed) return;
  if (levitated) run_.end_s = std::min(run_.end_s, trigger_s_);
  const double spin = declared.simulation.spin_speed_rad_s;
  const std::size_t rows = record.time_s.size();
  const auto first_row_at = [&](double t) {
    return static_cast<std::size_t>(
        std::lower_bound(record.time_s.begin(), record.time_s.end(), t) - record.time_s.begin());
  };
  const std::size_t start_row = first_row_at(compare_from_s_);
  const std::size_t trigger_row = first_row_at(trigger_s_);
  const std::size_t settled_row = first_row_at(settled_from_s_);
  for (std::size_t c = 0; c < measurement.channels.size(); ++c) {
    const MeasurementChannel& ch = measurement.channels[c];
    const int col = record.Column(ch.column);
    const std::vector<double>& v = record.values[col];
    column_.push_back(col);
    range_.push_back(0.0);
    if (!compared.empty() && !(c < compared.size() && compared[c])) continue;
    if (scope == CostScope::kSpeeds && !SpeedLike(ch.quantity)) continue;
    if (levitated && ch.quantity != MeasuredQuantity::kDisplacement && !CurrentLike(ch.quantity)) {
      continue;
    }
    if (spectrum && (!CurrentLike(ch.quantity) || !(sensor_noise_.sigma_m > 0.0))) continue;
    // Open loop no controller runs, so nothing predicts its command: not compared.
    if (ch.quantity == MeasuredQuantity::kControllerCommand && !closed) continue;
    // power_loss = "from_record": the coil currents drive the model; they are its input.
    if (measurement.Drives(ch)) continue;
    const bool current = CurrentLike(ch.quantity);
    // Sample-by-sample rows; currents before the trigger are inputs (open loop) or compared
    // by their levitated mean and harmonics (closed loop).
    const double from = current ? trigger_s_ : compare_from_s_;
    const double to = Smooth(ch.quantity) && !early_only ? t_end + 1.0 : early_end_s_;
    // The rows the channel's window lets in; a window that holds none of the rows the cost
    // could compare is a mistake in the table, not a channel to drop quietly.
    const auto [window_first, window_end] =
        RowsIn(record, ch, trigger_s_, current && !closed ? trigger_row : start_row, rows);
    // (The levitated part leaves out a channel whose window holds too few levitated rows.)
    if (window_first == window_end && !levitated) {
      throw std::runtime_error(fmt::format(
          "{}: column '{}' ({}): its window ({}) holds no sample the fit can compare{}",
          record.source, ch.column, ch.Describe(declared), ch.DescribeWindow(),
          current && !closed ? " (open loop, the currents before the trigger drive the model)"
                             : ""));
    }
    std::vector<std::size_t> raw;
    for (std::size_t j = window_first; j < window_end && !levitated; ++j) {
      if (record.time_s[j] >= from && record.time_s[j] < to) raw.push_back(j);
    }
    std::vector<Block> blocks;
    const auto [lev_first, lev_end] = RowsIn(record, ch, trigger_s_, start_row, trigger_row);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    if (spectrum) {
      // Its blocks are the levitated part's.
    } else if (levitated) {
      const std::vector<double> noise =
          SynchronousBlockNoise(record.time_s, v, lev_first, lev_end, spin);
      if (noise.empty()) continue;  // too few turns or rows to tell noise from content
      std::vector<std::vector<double>> k =
          SynchronousBlockCoefficients(record.time_s, lev_first, lev_end, spin);
      for (std::size_t i = 0; i < k.size(); ++i) {
        blocks.push_back({c, lev_first, std::move(k[i]), 0.0, 0.0, 0.0, noise[i]});
      }
    } else if (current && closed && lev_end > lev_first + 4) {
      // Mean, then 1X and 2X cosine and sine over the levitated rows.
      for (std::vector<double>& k :
           SynchronousBlockCoefficients(record.time_s, lev_first, lev_end, spin)) {
        blocks.push_back({c, lev_first, std::move(k), 0.0, 0.0, 0.0, nan});
      }
    }
    if (early_only && ForceLike(ch.quantity)) {
      // Impact forces are spikes a few samples wide: sample by sample, a spike a sample early
      // is off by its whole height, and the cost turns from a bowl into a cusp that gradients
      // cannot descend. Their impulse over short windows moves smoothly with the timing.
      std::vector<std::size_t> window;
      const std::size_t per_block = std::max<std::size_t>(1, raw.size() / 8);
      for (std::size_t i = 0; i < raw.size(); ++i) {
        window.push_back(raw[i]);
        if (window.size() == per_block || i + 1 == raw.size()) {
          const double n = static_cast<double>(window.size());
          blocks.push_back(
              {c, window.front(), std::vector<double>(window.size(), 1.0 / n), 0.0, 0.0, 0.0, nan});
          window.clear();
        }
      }
      raw.clear();
    }
    const auto [settled_first, settled_end] = RowsIn(record, ch, trigger_s_, settled_row, rows);
    if (!early_only && !levitated && !Smooth(ch.quantity) && settled_end > settled_first &&
        settled_from_s_ > to) {
      const std::size_t n = settled_end - settled_first;
      blocks.push_back({c, settled_first, std::vector<double>(n, 1.0 / static_cast<double>(n)), 0.0,
                        0.0, 0.0, nan});
    }
    if (raw.empty() && blocks.empty() && !spectrum) continue;
    // Range and noise over the window alone: what lies outside it (a channel gone bad after
    // the trigger) must not set its weight.
    const std::size_t range_first = std::max(start_row, window_first);
    double lo = std::numeric_limits<double>::infinity();
    double hi = -lo;
    for (std::size_t j = range_first; j < window_end; ++j) {
      lo = std::min(lo, v[j]);
      hi = std::max(hi, v[j]);
    }
    // A channel that carries nothing but its noise (a coil current of an AMB law that takes
    // none, a sensor that never moves) tells the fit nothing: it is left out.
    if (!(hi - lo > 10.0 * NoiseSigma(v, range_first, window_end))) {
      ++uninformative_;
      left_out_.push_back(c);
      continue;
    }
    const double range = hi - lo;
    range_.back() = range;
    // The channel's weight is shared between its sample-by-sample part and its blocks.
    const double parts = (raw.empty() ? 0.0 : 1.0) + static_cast<double>(blocks.size());
    if (!raw.empty()) {
      const std::size_t stride = std::max<std::size_t>(
          1, (raw.size() + max_samples_per_channel - 1) / max_samples_per_channel);
      std::vector<std::size_t> kept;
      for (std::size_t i = 0; i < raw.size(); i += stride) kept.push_back(raw[i]);
      const double weight = std::sqrt(1.0 / (parts * static_cast<double>(kept.size()))) / range;
      for (const std::size_t j : kept) samples_.push_back({c, j, weight, range});
    }
    for (Block& b : blocks) {
      // Levitated blocks in units of their own noise (a millionth of the range at least: a
      // noise-free record), so that a fit there weighs each as the record resolves it.
      b.weight = std::isfinite(b.noise_var)
                     ? 1.0 / std::sqrt(parts * std::max(b.noise_var, std::pow(1e-6 * range, 2)))
                     : std::sqrt(1.0 / parts) / range;
      b.range = range;
      b.measured = Apply(b, v);
      blocks_.push_back(std::move(b));
    }
    if (!spectrum) {
      ++channels_;
    } else {
      auto plan = std::make_shared<const SpectrumPlan>(
          PlanSpectrum(record.time_s, lev_first, lev_end, spin));
      std::vector<double> measured = BandPowers(*plan, v);
      const bool positive =
          std::all_of(measured.begin(), measured.end(), [](double p) { return p > 0.0; });
      if (measured.size() >= 4 && positive) {
        const double weight = 1.0 / std::sqrt(static_cast<double>(measured.size()) - 2.0);
        spectrum_bands_ += measured.size();
        spectra_.push_back({c, std::move(plan), std::move(measured), weight});
        ++channels_;
      } else {
        range_.back() = 0.0;
      }
    }
  }
}

void RecordCost::SpectrumResidual(const std::shared_ptr<const ModelParams>& params,
                                  const RecordRunOptions& options, Eigen::VectorXd* r,
                                  Eigen::Index i) const {
  // The model's mean spectrum over its noise draws; none if a run did not reach the trigger.
  std::vector<std::vector<double>> mean(spectra_.size());
  bool reached = params != nullptr;
  for (int k = 1; reached && k <= kSpectrumRuns; ++k) {
    RecordRunOptions o = options;
    o.end_s = std::min(o.end_s, trigger_s_);
    o.jitter_sigma_m = sensor_noise_.sigma_m;
    o.jitter_seed = static_cast<std::uint64_t>(k);
    o.keep_states = false;
    const SimulatedRecord run = SimulateOnRecord(*params, measurement_, record_, o);
    for (std::size_t s = 0; s < spectra_.size() && reached; ++s) {
      const std::vector<double> p =
          run.values.size() == measurement_.channels.size()
              ? BandPowers(*spectra_[s].plan, run.values[spectra_[s].channel])
              : std::vector<double>{};
      if (p.size() != spectra_[s].measured.size()) {
        reached = false;
        break;
      }
      if (mean[s].empty()) mean[s].assign(p.size(), 0.0);
      for (std::size_t b = 0; b < p.size(); ++b) mean[s][b] += p[b] / kSpectrumRuns;
    }
  }
  for (std::size_t s = 0; s < spectra_.size(); ++s) {
    const Spectrum& sp = spectra_[s];
    const SpectrumMatch m =
        reached ? MatchSpectra(*sp.plan, sp.measured, mean[s], kSpectrumRuns) : SpectrumMatch{};
    for (std::size_t b = 0; b < sp.measured.size(); ++b) {
      // Not reached, or nothing to compare: ten standard deviations off in every band.
      (*r)(i++) = m.z.size() == sp.measured.size() ? m.z[b] * sp.weight : 10.0 * sp.weight;
    }
  }
}

double RecordCost::Apply(const Block& b, const std::vector<double>& values) const {
  double sum = 0.0;
  for (std::size_t i = 0; i < b.coefficients.size(); ++i) {
    sum += b.coefficients[i] * values[b.first + i];
  }
  return sum;
}

std::vector<double> RecordCost::ChannelNoiseSse() const {
  // White noise of sigma_c on channel c would leave, in expectation, (sigma_c * weight)^2 per
  // compared sample and (sigma_c * weight)^2 * sum(coefficient^2) per block.
  std::vector<std::vector<double>> rows(column_.size());
  for (const Sample& s : samples_)
    rows[s.channel].push_back(record_.values[column_[s.channel]][s.row]);
  std::vector<double> sigma(column_.size(), 0.0);
  for (std::size_t c = 0; c < column_.size(); ++c) {
    const std::vector<double>& all = record_.values[column_[c]];
    sigma[c] = rows[c].size() >= 10 ? NoiseSigma(rows[c], 0, rows[c].size())
                                    : NoiseSigma(all, 0, all.size());
    // Second differences understate a coloured noise; its levitated estimate holds throughout.
    if (c < coloured_sigma_.size() && coloured_sigma_[c] > 0.0) sigma[c] = coloured_sigma_[c];
  }
  std::vector<double> expected(column_.size(), 0.0);
  for (const Sample& s : samples_) expected[s.channel] += std::pow(sigma[s.channel] * s.weight, 2);
  for (const Block& b : blocks_) {
    if (std::isfinite(b.noise_var)) {
      expected[b.channel] += b.noise_var * b.weight * b.weight;
      continue;
    }
    double sum_sq = 0.0;
    for (const double k : b.coefficients) sum_sq += k * k;
    expected[b.channel] += std::pow(sigma[b.channel] * b.weight, 2) * sum_sq;
  }
  // A spectrum's z's, two numbers fitted away, over sqrt(bands - 2): noise alone leaves 1.
  for (const Spectrum& sp : spectra_) expected[sp.channel] += 1.0;
  return expected;
}

double RecordCost::NoiseFloor() const {
  double expected = 0.0;
  for (const double e : ChannelNoiseSse()) expected += e;
  return std::sqrt(expected / std::max(channels_, 1));
}

SimulatedRecord RecordCost::Simulate(const ModelParams& params) const {
  return SimulateOnRecord(params, measurement_, record_, run_);
}

Eigen::VectorXd RecordCost::Residual(const SimulatedRecord& sim) const {
  if (sim.params && sim.state_from_record != measurement_.trigger_state_from_record) {
    RecordRunOptions o = sim.options;
    o.end_s = run_.end_s;
    return Residual(SimulateOnRecord(*sim.params, measurement_, record_, o));
  }
  if (sim.values.size() != measurement_.channels.size()) return Unreached();
  Eigen::VectorXd r(static_cast<Eigen::Index>(size()));
  Eigen::Index i = 0;
  for (const Sample& s : samples_) {
    const double model = sim.values[s.channel][s.row];
    const double measured = record_.values[column_[s.channel]][s.row];
    // Not reached (the run stopped): as far off as the channel's whole range.
    r(i++) = std::isfinite(model) ? (measured - model) * s.weight : s.range * s.weight;
  }
  for (const Block& b : blocks_) {
    const double model = Apply(b, sim.values[b.channel]);
    r(i++) = std::isfinite(model) ? (b.measured - model) * b.weight : b.range * b.weight;
  }
  if (!spectra_.empty()) SpectrumResidual(sim.params, sim.options, &r, i);
  return r;
}

Eigen::VectorXd RecordCost::Unreached() const {
  Eigen::VectorXd r(static_cast<Eigen::Index>(size()));
  Eigen::Index i = 0;
  for (const Sample& s : samples_) r(i++) = s.range * s.weight;
  for (const Block& b : blocks_) r(i++) = b.range * b.weight;
  for (const Spectrum& sp : spectra_) {
    for (std::size_t b = 0; b < sp.measured.size(); ++b) r(i++) = 10.0 * sp.weight;
  }
  return r;
}

std::vector<double> RecordCost::ChannelSse(const Eigen::VectorXd& residual) const {
  std::vector<double> sse(measurement_.channels.size(), 0.0);
  Eigen::Index i = 0;
  for (const Sample& s : samples_) sse[s.channel] += residual(i) * residual(i), ++i;
  for (const Block& b : blocks_) sse[b.channel] += residual(i) * residual(i), ++i;
  for (const Spectrum& sp : spectra_) {
    for (std::size_t b = 0; b < sp.measured.size(); ++b) {
      sse[sp.channel] += residual(i) * residual(i), ++i;
    }
  }
  return sse;
}

Eigen::VectorXd RecordCost::Residual(const ModelParams& params) const {
  return Residual(Simulate(params));
}

}  // namespace ambdrop
