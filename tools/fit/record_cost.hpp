#pragma once
// The fit's cost: the residual of a model against the record as one vector. A drop is chaotic
// after its first impacts: two runs a hair apart bounce differently, so comparing the bouncing
// sample by sample measures chaos, not the model. The cost compares what is deterministic:
//  - sample by sample, everything before the trigger and up to just after the first impact
//    (free fall and first contact: `early_s` after the trigger), and speeds and currents
//    throughout (spin-up and the flux's decay are smooth);
//  - except currents before the trigger: a controller answers its sensors' noise, which no
//    model predicts sample by sample, so there their mean and synchronous (1X, 2X) content over
//    the levitated time are compared;
//  - for displacements and forces after the first impact, their mean over the settled phase
//    (where the rotor rests on its TDBs).
// Each channel's part is divided by its measured range and by the square root of its count, so
// that the squared norm is the sum over channels of relative mean-square errors: channels in
// different units weigh alike, and the vector's length is the same for every model tried.
#include <Eigen/Core>
#include <cstddef>
#include <memory>
#include <vector>

#include "io/config/config_measurement.hpp"
#include "io/files/measured_csv.hpp"
#include "rt_core/model_params.hpp"
#include "tools/fit/levitated_spectrum.hpp"
#include "tools/fit/sensor_noise_colour.hpp"
#include "tools/fit/simulate_on_record.hpp"

namespace ambdrop {

/// What a cost compares.
enum class CostScope {
  kWhole,  ///< everything above
  /// Only up to the end of the first impact (RecordCost::early_end_s), every channel sample by
  /// sample there (levitated currents by their blocks), and the run stops there. After the
  /// first impacts a drop can be so chaotic that a hair's change of a parameter moves the whole
  /// cost (a flexible rotor whirling on ball-bearing TDBs): this part stays smooth in the
  /// parameters, so the fit searches on it first.
  kEarly,
  /// Only the speeds (rotor and races), sample by sample from the trigger to the end. What
  /// spins the races up or slows them (a drag, a heavier race, a viscous loss) shows there
  /// after the first impacts, where the whole cost's bouncing hides it: the speeds integrate
  /// the contact's friction and stay smooth where the displacements are chaotic.
  kSpeeds,
  /// Only the levitated time before the trigger, closed loop, from the model's own levitated
  /// state whatever measurement.trigger_state says, and the run stops at the trigger: each
  /// displacement and current by its mean, 1X and 2X content there (blocks, as the levitated
  /// currents of the other parts). What a synchronous effect (an unbalance, a runout) or a
  /// declared number the levitated machine shows (a bias, a sensor's offset) does there is
  /// plain, while the drop's start, whose limit the estimate of the state at the trigger
  /// widens, sees it hardly: the static unbalance of the flexible truth rig's seed 206 moved
  /// the levitated 1X of every sensor 30 times the clean records' departure, and fitted the
  /// start hardly worse than a couple unbalance half a turn off. Each block is weighed by its
  /// own noise, the record's neighbouring content (synchronous_blocks.hpp), not white noise (the
  /// rotor's jitter, answered by the controller, puts 3 to 9 times more there): the part's noise
  /// floor is 1, and a fit there weighs each block as the record resolves it. Weighed by their
  /// ranges as the other parts are, the currents' 1X (a tenth of their range) outweighed the
  /// displacements' (a thousandth) and pulled that unbalance's phase 0.13 rad off.
  kLevitated,
  /// Only each current's noise spectrum over the levitated time (levitated_spectrum.hpp), where
  /// the record's sensors are noisy: the model's controller answers noise of the record's level
  /// (RecordCost::kSpectrumRuns draws of it), and each band departs in units of its own spread,
  /// each current's spectrum weighing as one channel. What the loop does with its noise (a lag
  /// in the acquisition chain, a computation delay, a sensor's gain) shows there and nowhere
  /// else before the trigger. A part of its own: beside the levitated blocks its departure
  /// drowned (a chain lag that took its bands 1.8 standard deviations off left the levitated
  /// part at 1.3 against its limit of 1.5).
  kSpectrum,
};

/// The measurement a cost of `scope` runs its model with: with trigger_state = "record_start"
/// the drop's start (kEarly) from the lead window's estimate of the state at the trigger (as
/// "record"), every other part from the model's own levitated state.
MeasurementParams MeasurementFor(const MeasurementParams& measurement, CostScope scope);

class RecordCost {
 public:
  /// `max_samples_per_channel` thins the compared rows evenly (the cost of the linear algebra,
  /// not of the simulation, grows with it).
  /// `compared`, if not empty, says which measurement channels the cost compares (the others
  /// are run, not compared).
  RecordCost(const ModelParams& declared, const MeasurementParams& measurement,
             const MeasuredRecord& record, const RecordRunOptions& run,
             std::size_t max_samples_per_channel = 3000, CostScope scope = CostScope::kWhole,
             const std::vector<bool>& compared = {});

  /// The residual vector of `params` (a copy of the declared ones with effects applied). A run
  /// that stops early scores every sample it did not reach as a full range off.
  Eigen::VectorXd Residual(const ModelParams& params) const;
  /// The same for a run already made; one whose state at the trigger was taken otherwise than
  /// this cost takes it (MeasurementFor) is run again this cost's way, with its own options.
  Eigen::VectorXd Residual(const SimulatedRecord& sim) const;
  /// The residual of a run that never started (a config the readers refused): every sample a
  /// full range off, as a run that stopped at once scores.
  Eigen::VectorXd Unreached() const;
  SimulatedRecord Simulate(const ModelParams& params) const;
  /// A residual vector's squared norm split by measurement channel (0 for one not compared):
  /// which channels the overall residual comes from.
  std::vector<double> ChannelSse(const Eigen::VectorXd& residual) const;

  /// The overall relative RMS a perfect model would leave: each channel's measurement noise
  /// (tools/fit/noise_floor.hpp, over its compared samples) through the cost's weights; on
  /// CostScope::kLevitated 1, each block weighed by its own noise (synchronous_blocks.hpp).
  double NoiseFloor() const;
  /// Its parts per measurement channel: the squared residual each channel's noise alone would
  /// leave (0 for one not compared). Their sum over channels, divided by channels(), is
  /// NoiseFloor() squared.
  std::vector<double> ChannelNoiseSse() const;

  std::size_t size() const { return samples_.size() + blocks_.size() + spectrum_bands_; }
  int channels() const { return channels_; }
  /// Channels left out because their range is within ten times their noise.
  int uninformative_channels() const { return uninformative_; }
  /// Their indices in the measurement's channels.
  const std::vector<std::size_t>& left_out() const { return left_out_; }
  double compare_from_s() const { return compare_from_s_; }
  double early_end_s() const { return early_end_s_; }
  double settled_from_s() const { return settled_from_s_; }
  const ModelParams& declared() const { return declared_; }
  const MeasurementParams& measurement() const { return measurement_; }
  const MeasuredRecord& record() const { return record_; }
  const RecordRunOptions& run_options() const { return run_; }
  double trigger_time_s() const { return trigger_s_; }
  CostScope scope() const { return scope_; }
  /// CostScope::kSpectrum: the currents whose noise spectrum is compared, and the sensor noise
  /// (m) the model's controller answers for it (0: none compared).
  std::size_t spectra() const { return spectra_.size(); }
  double spectrum_noise_m() const {
    return scope_ == CostScope::kSpectrum ? sensor_noise_.sigma_m : 0.0;
  }
  /// The record's displacement noise before the trigger, white or coloured (the median over
  /// its displacement channels, tools/fit/sensor_noise_colour.hpp); its bandwidth goes with
  /// every jitter drawn on this cost's runs (run_options().jitter_bandwidth_Hz).
  const SensorNoise& sensor_noise() const { return sensor_noise_; }
  /// Noise draws of the model whose mean spectrum is compared.
  static constexpr int kSpectrumRuns = 4;

 private:
  struct Sample {
    std::size_t channel;
    std::size_t row;
    double weight;
    double range;
  };
  struct Block {  // sum over rows [first, first + coefficients.size()) of coefficient * value
    std::size_t channel;
    std::size_t first;
    std::vector<double> coefficients;
    double weight;
    double range;
    double measured;
    /// Its variance from the record's noise and jitter where measured (kLevitated), else NaN:
    /// white noise through the coefficients.
    double noise_var;
  };
  struct Spectrum {  // a current's levitated noise spectrum: a channel of its own
    std::size_t channel;
    std::shared_ptr<const SpectrumPlan> plan;
    std::vector<double> measured;  // band powers
    double weight;                 // 1 / sqrt(bands - 2): noise alone leaves it 1
  };
  double Apply(const Block& b, const std::vector<double>& values) const;
  /// The spectra's part of the residual for `params` run with `options` (noise drawn).
  void SpectrumResidual(const std::shared_ptr<const ModelParams>& params,
                        const RecordRunOptions& options, Eigen::VectorXd* r, Eigen::Index i) const;
  const ModelParams& declared_;
  MeasurementParams measurement_;  ///< MeasurementFor(the caller's, scope)
  const MeasuredRecord& record_;
  RecordRunOptions run_;
  CostScope scope_ = CostScope::kWhole;
  double trigger_s_ = 0.0;
  double compare_from_s_ = 0.0;
  double early_end_s_ = 0.0;
  double settled_from_s_ = 0.0;
  int channels_ = 0;
  int uninformative_ = 0;
  std::vector<std::size_t> left_out_;
  std::vector<Sample> samples_;
  std::vector<Block> blocks_;
  std::vector<Spectrum> spectra_;
  std::size_t spectrum_bands_ = 0;
  SensorNoise sensor_noise_;
  /// Per measurement channel: a coloured displacement channel's noise sigma (m), which its
  /// second differences understate; 0: NoiseSigma's, as for white noise.
  std::vector<double> coloured_sigma_;
  std::vector<int> column_;    // record column per measurement channel
  std::vector<double> range_;  // per measurement channel; 0 if not compared
};

}  // namespace ambdrop
