#include "tools/fit/synchronous_blocks.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <numbers>

namespace ambdrop {

std::vector<std::vector<double>> SynchronousBlockCoefficients(const std::vector<double>& time_s,
                                                              std::size_t first, std::size_t last,
                                                              double spin_rad_s) {
  const std::size_t n = last - first;
  std::vector<std::vector<double>> blocks(5, std::vector<double>(n));
  for (int k = 0; k <= 4; ++k) {
    for (std::size_t i = 0; i < n; ++i) {
      const double angle = spin_rad_s * time_s[first + i] * (k <= 2 ? 1.0 : 2.0);
      const double basis = k == 0 ? 1.0 : (k % 2 == 1 ? std::cos(angle) : std::sin(angle));
      blocks[static_cast<std::size_t>(k)][i] =
          (k == 0 ? 1.0 : 2.0) * basis / static_cast<double>(n);
    }
  }
  return blocks;
}

std::vector<double> SynchronousBlockNoise(const std::vector<double>& time_s,
                                          const std::vector<double>& values, std::size_t first,
                                          std::size_t last, double spin_rad_s) {
  if (last < first + 64) return {};
  const std::size_t n = last - first;
  const double t0 = time_s[first];
  const double window =
      time_s[last - 1] - t0 + (time_s[last - 1] - t0) / static_cast<double>(n - 1);
  const double turns = spin_rad_s * window / (2.0 * std::numbers::pi);
  if (!(turns >= 6.0)) return {};
  // What the record holds that both it and a noise-free model hold: removed before the
  // neighbours are read, else the mean alone leaks into them over a window of unwhole turns.
  Eigen::MatrixXd basis(static_cast<Eigen::Index>(n), 6);
  Eigen::VectorXd v(static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i) {
    const double t = time_s[first + i];
    const auto row = static_cast<Eigen::Index>(i);
    basis.row(row) << 1.0, (t - t0) / window, std::cos(spin_rad_s * t), std::sin(spin_rad_s * t),
        std::cos(2.0 * spin_rad_s * t), std::sin(2.0 * spin_rad_s * t);
    v(row) = values[first + i];
  }
  const Eigen::VectorXd left = v - basis * basis.colPivHouseholderQr().solve(v);
  const double bin_rad_s = 2.0 * std::numbers::pi / window;
  // Mean square of the cosine and sine projections (coefficients 2/n) at `rad_s`.
  const auto power_at = [&](double rad_s) {
    double c = 0.0;
    double s = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double angle = rad_s * (time_s[first + i] - t0);
      c += left(static_cast<Eigen::Index>(i)) * std::cos(angle);
      s += left(static_cast<Eigen::Index>(i)) * std::sin(angle);
    }
    const double scale = 2.0 / static_cast<double>(n);
    return 0.5 * (c * c + s * s) * scale * scale;
  };
  // A cosine block's variance at `centre`: the mean projection at its neighbours.
  const auto around = [&](double centre) {
    double sum = 0.0;
    int count = 0;
    for (const double bins : {2.0, 3.0}) {
      for (const double side : {-1.0, 1.0}) {
        const double at = centre + side * bins * bin_rad_s;
        if (at <= 0.0) continue;
        sum += power_at(at);
        ++count;
      }
    }
    return sum / count;
  };
  // The mean's coefficients (1/n) are half a cosine's (2/n), but the mean has no sine: half
  // of what one neighbour's cosine and sine carry together. Four neighbours, as the 1X and 2X
  // blocks have: from two (four numbers), the clean record of the 4-DOF truth rig's seed 2 had
  // its DE x current's mean noise read 21 times low (8.8e-5 A; 1.9e-3 from four), and a 2.8 mA
  // departure in it was "explained" by a sensor offset.
  double neighbours = 0.0;
  for (const double bins : {2.0, 3.0, 4.0, 5.0}) neighbours += power_at(bins * bin_rad_s);
  const double mean_var = 0.5 * neighbours / 4.0;
  const double one = around(spin_rad_s);
  const double two = around(2.0 * spin_rad_s);
  return {mean_var, one, one, two, two};
}

}  // namespace ambdrop
