#pragma once
#include <string>
#include <vector>

namespace ambdrop {

struct FitOptions {
  std::string config_path;  ///< the declared model, with a [measurement] table
  /// The measured records (CSV or run records). Several: records of one rig, each fitted into
  /// DIR/NN_<name>/, and DIR/shared.md, DIR/shared.json say what they share.
  std::vector<std::string> measured_paths;
  std::vector<std::string> overrides;  ///< --set, on the declared model
  std::string out_dir = "out";
  double lead_s = 2e-3;  ///< simulated time before the trigger
  int threads = 2;
  int max_runs_per_start = 40;
  double tolerance = 0.0;  ///< relative RMS within which model and record agree anyway
  /// Runs of the declared model with its rotor's jitter drawn (tools/fit/jitter_draws.hpp);
  /// 0: none.
  int jitter_draws = 16;
  bool quiet = false;
  /// Every run at the config's step (tools/fit/fit_step.hpp: otherwise the fit may coarsen it).
  bool declared_step = false;
  /// Instead of a record: measured TDB spin-up times ("de=0.11,nde=0.129", s after the
  /// trigger); which single parameter change explains them (tools/fit/spinup_fit.hpp).
  std::string spin_up_times;
};

/// `ambdrop fit CONFIG --measured FILE... --out DIR`: holds the declared model against a measured
/// record (tools/fit/): residual per channel and phase, the library's effects fitted and
/// chosen by error cut and BIC, and a verdict. Writes DIR/fit.json and DIR/report.md. With
/// spin_up_times: a table of single-parameter candidates, and DIR/spinup_fit.json.
int RunFitCommand(const FitOptions& options);

}  // namespace ambdrop
