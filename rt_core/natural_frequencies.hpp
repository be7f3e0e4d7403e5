#pragma once
#include <Eigen/Core>
#include <vector>

namespace ambdrop {

/// Damped natural frequencies (rad/s, ascending) of M q'' + (C + Omega G) q' + K q = 0 from the
/// first-order state-space eigenvalues; only eigenvalues with a positive imaginary part count.
std::vector<double> DampedNaturalFrequencies(const Eigen::MatrixXd& mass,
                                             const Eigen::MatrixXd& damping,
                                             const Eigen::MatrixXd& stiffness,
                                             const Eigen::MatrixXd& gyroscopic,
                                             double spin_speed_rad_s);

/// Undamped frequencies of (K, M), rigid-body modes as 0.
std::vector<double> UndampedNaturalFrequencies(const Eigen::MatrixXd& mass,
                                               const Eigen::MatrixXd& stiffness);

}  // namespace ambdrop
