#pragma once
// One line of `ambdrop validate`: a quantity a seed paper publishes (a number or a trend), what
// ambdrop computes for it, and whether they agree by the stated criterion.
#include <cmath>
#include <limits>
#include <string>

namespace ambdrop {

struct ValidationCheck {
  std::string case_name;  ///< e.g. "seed000 Table 3"
  std::string quantity;   ///< e.g. "DE spin-up time (s)"
  std::string published;  ///< the paper's value or trend, as text
  std::string ambdrop;    ///< ambdrop's value, as text
  /// Relative deviation from a published number (NaN for a trend).
  double deviation = std::numeric_limits<double>::quiet_NaN();
  std::string criterion;  ///< e.g. "within 25 %"
  bool pass = false;
  /// A failure that is understood and open (the issue that tracks it); empty otherwise.
  std::string known_failure;
};

/// A check of ambdrop's `value` against a published number within a relative `tolerance`.
ValidationCheck NumberCheck(std::string case_name, std::string quantity, double published,
                            double value, double tolerance, const char* unit);
/// A check of a published trend or bound: `holds` says whether ambdrop reproduces it.
ValidationCheck TrendCheck(std::string case_name, std::string quantity, std::string published,
                           std::string ambdrop, bool holds);

}  // namespace ambdrop
