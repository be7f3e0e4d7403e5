#include "rt_core/modal_analysis.hpp"

#include "rt_core/fe_rotor.hpp"
#include "rt_core/modal_reduction.hpp"
#include "rt_core/natural_frequencies.hpp"

namespace ambdrop {
namespace {

std::vector<double> FirstN(std::vector<double> v, int count) {
  if (static_cast<int>(v.size()) > count) v.resize(static_cast<std::size_t>(count));
  return v;
}

// The levitated rotor: linear bearings plus each AMB as the spring/damper it is while powered
// (equivalent law: k, c; linearised law: the negative stiffness -ks).
ModelParams WithAmbsAsSupports(const ModelParams& params) {
  ModelParams p = params;
  for (const AmbParams& a : params.ambs) {
    const bool equivalent = a.law == AmbForceLaw::kEquivalent;
    const double k = equivalent ? a.stiffness_N_per_m : -a.position_gain_N_per_m;
    const double c = equivalent ? a.damping_N_s_per_m : 0.0;
    p.bearings.push_back({"amb " + a.name, a.position_m, k, k, c, c});
  }
  return p;
}

}  // namespace

ModalAnalysis AnalyseModes(const ModelParams& config, double spin, int count) {
  const ModelParams params = WithAmbsAsSupports(config);
  ModalAnalysis out;
  const ReducedRotor reduced = BuildReducedRotor(params);
  const int n = reduced.size;
  out.reduced_supported_rad_s =
      FirstN(DampedNaturalFrequencies(Eigen::MatrixXd::Identity(n, n), reduced.damping,
                                      reduced.stiffness, reduced.gyroscopic, spin),
             count);
  if (params.rotor.kind == RotorKind::kRigid) {
    // The rigid form is already complete: its "full" model is the reduced one.
    out.free_free_rad_s = FirstN(std::vector<double>(4, 0.0), count);
    out.supported_rad_s = out.reduced_supported_rad_s;
    return out;
  }
  const FeRotor fe = AssembleFeRotor(params.rotor, StationPositions(params));
  Eigen::MatrixXd kb, cb;
  LinearBearingMatrices(fe, params.bearings, &kb, &cb);
  out.free_free_rad_s = FirstN(UndampedNaturalFrequencies(fe.mass, fe.stiffness), count);
  out.supported_rad_s =
      FirstN(DampedNaturalFrequencies(fe.mass, cb, fe.stiffness + kb, fe.gyroscopic, spin), count);
  return out;
}

}  // namespace ambdrop
