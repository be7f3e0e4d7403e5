#include "tools/fit/record_trigger_detect.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <vector>

namespace ambdrop {
namespace {

// One channel's levitated level and how far from it a row must be to count.
struct Levitated {
  const std::vector<double>* values = nullptr;
  double mean = 0.0;
  double band = 0.0;  // within it, a row may still be levitated
  double far = 0.0;   // beyond it, the row is not
};

Levitated LevelOf(const std::vector<double>& v, std::size_t quiet, bool scaled_by_mean) {
  Levitated l;
  l.values = &v;
  for (std::size_t j = 0; j < quiet; ++j) l.mean += v[j];
  l.mean /= static_cast<double>(quiet);
  double var = 0.0;
  for (std::size_t j = 0; j < quiet; ++j) var += (v[j] - l.mean) * (v[j] - l.mean);
  double sigma = std::sqrt(var / static_cast<double>(quiet));
  // A noise-free or coarsely quantised channel may read one value throughout: a floor far below
  // anything the failure moves keeps "no change" from meaning "any change".
  double reach = 0.0;
  for (const double x : v) reach = std::max(reach, std::abs(x - l.mean));
  sigma = std::max(sigma, 1e-9 * reach);
  l.band = 3.0 * sigma;
  // A coil current's or command's level is a scale of its own (a slow drift of an integral
  // action is not a failure); a displacement's level is a place, not a scale.
  l.far = std::max(8.0 * sigma, scaled_by_mean ? 0.2 * std::abs(l.mean) : 0.0);
  return l;
}

// A powered amplifier makes its coil follow the controller, which answers its sensors' noise:
// the levitated currents jitter. Once the power fails they are held, cut, ramped or fading,
// smooth in every form, and their second differences fall to the channel's own measurement
// noise (3 to 10 times less on the truth rigs). Where the failure holds the currents before
// they fall, nothing else shows until the hold ends (rigid_hc_g: found 1.26 ms late).
//
// Each coil current's second difference in units of its levitated spread (1.4826 MAD over the
// record's first tenth), squared and summed over the C channels: z_k, about chi2_C while
// levitated. Over rows [q, stop - 1) the variance-change likelihood ratio is
// 2 ln LR = C n (r - 1 - ln r), r their mean z over C. `stop` starts at `end`, the first row the
// level rule takes as no longer levitated (row end - 1's second difference spans row end, where
// a cut current jumps), and runs on while the rows stay quiet, as a fading or ramping current's
// do. The onset is the q that maximises it with r < 1/2. Chance makes quiet stretches too (a
// controller whose commands barely move for a few samples): the most likely one ending at any
// row of the first tenth sets what chance reaches, and the onset counts only beyond 1.5 times
// that (and kQuietLikelihood). The first quiet second difference (row q) already spans a held
// row q - 1: the power failed between rows q - 2 and q - 1. On the six truth rigs' 252 battery
// records (docs/verification.md, session 53) 218 were dated within 1.5 samples, 62 before.
constexpr double kQuietLikelihood = 20.0;  // chi-square of 1 dof beyond p = 1e-5
constexpr double kChanceMargin = 1.5;

// Row k's second differences, each in units of its channel's levitated spread, squared and
// summed over the channels.
double PooledZ(const std::vector<const std::vector<double>*>& currents,
               const std::vector<double>& spread, std::size_t k) {
  double sum = 0.0;
  for (std::size_t c = 0; c < currents.size(); ++c) {
    const std::vector<double>& v = *currents[c];
    const double z = (v[k + 1] - 2.0 * v[k] + v[k - 1]) / spread[c];
    sum += z * z;
  }
  return sum;
}

// The largest 2 ln LR of a quiet stretch [q, end - 1) over q, and that q (0: none with r < 1/2).
struct QuietStretch {
  double likelihood = 0.0;
  std::size_t onset = 0;
};

QuietStretch MostLikelyQuiet(const std::vector<const std::vector<double>*>& currents,
                             const std::vector<double>& spread, std::size_t first,
                             std::size_t end) {
  QuietStretch out;
  const double channels = static_cast<double>(currents.size());
  double sum = 0.0;
  for (std::size_t k = end - 2; k >= first; --k) {
    sum += PooledZ(currents, spread, k);
    const double n = static_cast<double>(end - 1 - k);
    const double ratio = sum / (channels * n);
    // Past a stretch as loud as the levitated time on average no quieter one begins.
    if (ratio > 1.0) break;
    const double lr = channels * n * (ratio - 1.0 - std::log(std::max(ratio, 1e-300)));
    if (ratio < 0.5 && lr > out.likelihood) out = {lr, k};
    if (k == first) break;
  }
  return out;
}

std::size_t QuietOnset(const MeasurementParams& m, const MeasuredRecord& r, std::size_t quiet,
                       std::size_t end, std::size_t reach) {
  std::vector<const std::vector<double>*> currents;
  std::vector<double> spread;
  for (const MeasurementChannel& ch : m.channels) {
    if (ch.quantity != MeasuredQuantity::kCurrent) continue;
    const std::vector<double>& v = r.values[r.Column(ch.column)];
    std::vector<double> d2;
    for (std::size_t k = 1; k + 1 < quiet; ++k)
      d2.push_back(std::abs(v[k + 1] - 2.0 * v[k] + v[k - 1]));
    if (d2.size() < 16) continue;
    auto mid = d2.begin() + static_cast<std::ptrdiff_t>(d2.size() / 2);
    std::nth_element(d2.begin(), mid, d2.end());
    if (!(*mid > 0.0)) continue;  // a quantised or noise-free channel: no jitter to lose
    currents.push_back(&v);
    spread.push_back(1.4826 * *mid);
  }
  if (currents.empty() || end < quiet + 3) return 0;
  // What chance makes of it: the most likely quiet stretch ending at each levitated row.
  double chance = kQuietLikelihood;
  for (std::size_t e = 4; e < quiet; ++e) {
    chance = std::max(chance, MostLikelyQuiet(currents, spread, 1, e).likelihood);
  }
  // A current that fades or ramps stays smooth past `end`, where one cut jumps: the stretch
  // runs on while its rows stay quiet, up to `reach` rows.
  const auto loud = [&](std::size_t k) {
    return PooledZ(currents, spread, k) > 2.0 * static_cast<double>(currents.size());
  };
  std::size_t stop = end;
  while (stop < end + reach && stop + 1 < r.time_s.size() && !loud(stop - 1)) ++stop;
  const QuietStretch at = MostLikelyQuiet(currents, spread, quiet, stop);
  return at.likelihood > kChanceMargin * chance && at.onset >= 2 ? at.onset : 0;
}

}  // namespace

double RecordTriggerTime(const MeasurementParams& m, const MeasuredRecord& r) {
  if (m.trigger_time_s) return *m.trigger_time_s;
  const std::size_t rows = r.time_s.size();
  const std::size_t quiet = std::max<std::size_t>(rows / 10, 2);
  std::vector<Levitated> channels;
  for (const MeasurementChannel& ch : m.channels) {
    const bool electrical = ch.quantity == MeasuredQuantity::kCurrent ||
                            ch.quantity == MeasuredQuantity::kControllerCommand;
    if (!electrical && ch.quantity != MeasuredQuantity::kDisplacement) continue;
    channels.push_back(LevelOf(r.values[r.Column(ch.column)], quiet, electrical));
  }
  if (channels.empty()) {
    throw std::runtime_error(
        "measurement.trigger = \"detect\" needs a current, controller_command or displacement "
        "channel; give trigger_time_s");
  }
  const auto far = [&](std::size_t j) {
    return std::any_of(channels.begin(), channels.end(), [j](const Levitated& l) {
      return std::abs((*l.values)[j] - l.mean) > l.far;
    });
  };
  const auto within = [&](std::size_t j) {
    return std::all_of(channels.begin(), channels.end(), [j](const Levitated& l) {
      return std::abs((*l.values)[j] - l.mean) <= l.band;
    });
  };
  // A glitch is not a failure: far for half a millisecond (four rows at least) on end.
  const double dt = r.SampleInterval();
  const std::size_t sustained =
      std::max<std::size_t>(4, static_cast<std::size_t>(std::ceil(0.5e-3 / dt)));
  std::size_t run = 0, first_far = rows;
  for (std::size_t j = quiet; j < rows; ++j) {
    run = far(j) ? run + 1 : 0;
    if (run == sustained) {
      first_far = j + 1 - sustained;
      break;
    }
  }
  if (first_far >= rows) {
    throw std::runtime_error(
        "measurement.trigger = \"detect\": no current, command or displacement leaves its "
        "levitated level (the record's first tenth) for good; give trigger_time_s");
  }
  std::size_t j = first_far;
  while (j > quiet && !within(j)) --j;
  // Currents that stopped jittering before row j + 1 date the failure earlier (a hold).
  const std::size_t onset = QuietOnset(m, r, quiet, j + 1, 4 * sustained);
  if (onset >= 2 && onset - 1 < j) return 0.5 * (r.time_s[onset - 2] + r.time_s[onset - 1]);
  // The power went between row j (still levitated) and row j + 1: the middle of the interval
  // is the unbiased estimate, wrong by half a sample at most where either end may be a whole
  // one (a sampler that reads after the cut puts it on row j + 1, one before it on row j).
  return 0.5 * (r.time_s[j] + r.time_s[j + 1]);
}

}  // namespace ambdrop
