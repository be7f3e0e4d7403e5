#pragma once
// The screening pass of the selection (issue 23 item 3): with hundreds of "the declared value
// is off" candidates, a full fit of each would take hours. Each one-parameter candidate is run
// at three values instead: halfway from its declared value to either end of its range, where a
// quadratic through the three residual vectors (declared and the two) predicts how far the best
// value in the range would cut the error, and a sixteenth of the range away, whose slope
// predicts a Gauss-Newton step near the declared value. The better prediction counts. Only the
// most promising are then fitted in full.
#include <Eigen/Core>
#include <limits>

#include "io/config/config_variants.hpp"
#include "tools/fit/effect_library.hpp"
#include "tools/fit/record_cost.hpp"

namespace ambdrop {

struct Screening {
  /// Overall relative RMS by which the prediction moves at most over the range: the largest of
  /// the runs' moves and the quadratic's anywhere in the range (the candidate's reach, for
  /// the decidability test).
  double reach = 0.0;
  /// The squared norm of the residual the quadratic predicts at its best value in the range
  /// (never more than the best of the three runs'); +inf if no value was run.
  double predicted_sse = std::numeric_limits<double>::infinity();
  double best_value = std::numeric_limits<double>::quiet_NaN();  ///< where, in SI
  int runs = 0;
};

/// Screens a one-parameter effect (its first start is the declared value) against `cost`, whose
/// declared residual is `residual_before`. A value the config refuses (a station moved past a
/// neighbour) is left out of the quadratic.
Screening ScreenCandidate(const ConfigVariants& declared, const RecordCost& cost,
                          const Effect& effect, const Eigen::VectorXd& residual_before);

}  // namespace ambdrop
