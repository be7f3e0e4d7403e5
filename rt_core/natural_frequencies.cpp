#include "rt_core/natural_frequencies.hpp"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace ambdrop {

std::vector<double> DampedNaturalFrequencies(const Eigen::MatrixXd& m, const Eigen::MatrixXd& c,
                                             const Eigen::MatrixXd& k, const Eigen::MatrixXd& g,
                                             double spin) {
  const Eigen::Index n = m.rows();
  const Eigen::LDLT<Eigen::MatrixXd> m_ldlt(m);
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  a.topRightCorner(n, n).setIdentity();
  a.bottomLeftCorner(n, n) = -m_ldlt.solve(k);
  a.bottomRightCorner(n, n) = -m_ldlt.solve(c + spin * g);
  const Eigen::EigenSolver<Eigen::MatrixXd> eig(a, false);
  // Rigid-body and overdamped roots sit on the real axis; the scale sets what "real" means.
  const double scale = std::max(1.0, eig.eigenvalues().cwiseAbs().maxCoeff());
  std::vector<double> w;
  for (Eigen::Index i = 0; i < eig.eigenvalues().size(); ++i) {
    const double im = eig.eigenvalues()(i).imag();
    if (im > 1e-9 * scale) w.push_back(im);
  }
  std::sort(w.begin(), w.end());
  return w;
}

std::vector<double> UndampedNaturalFrequencies(const Eigen::MatrixXd& m, const Eigen::MatrixXd& k) {
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(k, m, Eigen::EigenvaluesOnly);
  const double scale = std::max(1.0, eig.eigenvalues().cwiseAbs().maxCoeff());
  std::vector<double> w;
  for (Eigen::Index i = 0; i < eig.eigenvalues().size(); ++i) {
    const double lambda = eig.eigenvalues()(i);
    w.push_back(lambda < 1e-12 * scale ? 0.0 : std::sqrt(lambda));
  }
  return w;
}

}  // namespace ambdrop
