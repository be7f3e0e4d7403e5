#include "tools/fit/spinup_fit.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <unsupported/Eigen/LevenbergMarquardt>

#include "controller_if/loop/offline_run.hpp"
#include "rt_core//model.hpp"
#include "rt_core/tdb_common.hpp"

namespace ambdrop {
namespace {

struct Knob {
  std::string name;
  std::string parameter;
  double lower, upper;
  std::function<double(const ModelParams&)> get;
  std::function<void(double, ModelParams*)> set;
};

TdbParams* Find(ModelParams* p, const std::string& name) {
  for (TdbParams& t : p->tdbs) {
    if (t.name == name) return &t;
  }
  return nullptr;
}
const TdbParams* Find(const ModelParams& p, const std::string& name) {
  for (const TdbParams& t : p.tdbs) {
    if (t.name == name) return &t;
  }
  return nullptr;
}

std::vector<Knob> Knobs(const ModelParams& rig) {
  std::vector<Knob> knobs;
  for (const TdbParams& t : rig.tdbs) {
    const std::string n = t.name;
    knobs.push_back({"tdb_drag_torque:" + n, "drag_torque_N_m", 0.0, 5.0,
                     [n](const ModelParams& p) { return Find(p, n)->spin.drag_torque_N_m; },
                     [n](double v, ModelParams* p) { Find(p, n)->spin.drag_torque_N_m = v; }});
    knobs.push_back({"tdb_inertia:" + n, "inertia_kg_m2", 0.25 * t.spin.inertia_kg_m2,
                     4.0 * t.spin.inertia_kg_m2,
                     [n](const ModelParams& p) { return Find(p, n)->spin.inertia_kg_m2; },
                     [n](double v, ModelParams* p) { Find(p, n)->spin.inertia_kg_m2 = v; }});
    knobs.push_back(
        {"tdb_rotational_damping:" + n, "rotational_damping_N_m_s", 0.0, 0.05,
         [n](const ModelParams& p) { return Find(p, n)->spin.rotational_damping_N_m_s; },
         [n](double v, ModelParams* p) { Find(p, n)->spin.rotational_damping_N_m_s = v; }});
    knobs.push_back({"friction_coefficient:" + n, "coefficient", 0.02, 0.8,
                     [n](const ModelParams& p) { return Find(p, n)->friction.coefficient; },
                     [n](double v, ModelParams* p) { Find(p, n)->friction.coefficient = v; }});
    // A vertical offset moves the rotor's weight between the TDBs, and with it the friction.
    knobs.push_back({"tdb_misalignment_y:" + n, "y_m", -0.5 * t.clearance_m, 0.5 * t.clearance_m,
                     [n](const ModelParams& p) {
                       const TdbParams* x = Find(p, n);
                       return x->misalignment.enabled ? x->misalignment.y_m : 0.0;
                     },
                     [n](double v, ModelParams* p) {
                       TdbParams* x = Find(p, n);
                       x->misalignment.enabled = true;
                       x->misalignment.y_m = v;
                     }});
  }
  knobs.push_back({"friction_coefficient", "coefficient", 0.02, 0.8,
                   [](const ModelParams& p) { return p.tdbs.front().friction.coefficient; },
                   [](double v, ModelParams* p) {
                     for (TdbParams& t : p->tdbs) t.friction.coefficient = v;
                   }});
  return knobs;
}

double RmsRelative(const std::map<std::string, double>& times,
                   const std::map<std::string, double>& measured) {
  double sum = 0.0;
  for (const auto& [name, target] : measured) {
    const auto it = times.find(name);
    // A TDB that never reaches speed is as far off as can be said: 100 %.
    const double e = it == times.end() || it->second < 0 ? 1.0 : (it->second - target) / target;
    sum += e * e;
  }
  return std::sqrt(sum / static_cast<double>(measured.size()));
}

// One parameter through p = lo + (hi - lo)(1 + sin z)/2: bounded, for the unconstrained LM.
struct OneKnob : Eigen::DenseFunctor<double> {
  OneKnob(const ModelParams& r, const Knob& k, const std::map<std::string, double>& m)
      : DenseFunctor<double>(1, static_cast<int>(m.size())), rig(r), knob(k), measured(m) {}
  double Value(double z) const {
    return knob.lower + (knob.upper - knob.lower) * 0.5 * (1.0 + std::sin(z));
  }
  Eigen::VectorXd Errors(double z) {
    ModelParams p = rig;
    knob.set(Value(z), &p);
    const std::map<std::string, double> t = TdbSpinUpTimes(p);
    Eigen::VectorXd e(static_cast<Eigen::Index>(measured.size()));
    Eigen::Index i = 0;
    for (const auto& [name, target] : measured) {
      const auto it = t.find(name);
      e(i++) = it == t.end() || it->second < 0 ? 1.0 : (it->second - target) / target;
    }
    if (e.squaredNorm() < best) {
      best = e.squaredNorm();
      best_z = z;
    }
    return e;
  }
  int operator()(const Eigen::VectorXd& z, Eigen::VectorXd& f) {
    f = Errors(z(0));
    return 0;
  }
  int df(const Eigen::VectorXd& z, Eigen::MatrixXd& j) {
    constexpr double kStep = 0.02;  // the times are read at the output interval
    j.col(0) = (Errors(z(0) + kStep) - Errors(z(0))) / kStep;
    return 0;
  }
  const ModelParams& rig;
  const Knob& knob;
  const std::map<std::string, double>& measured;
  double best = std::numeric_limits<double>::infinity();
  double best_z = 0.0;
};

}  // namespace

std::map<std::string, double> TdbSpinUpTimes(const ModelParams& params) {
  const Model model = BuildModel(params);
  std::map<std::string, double> spinup;
  const OfflineRunResult r = RunOffline(model, [&](const Observation& o) {
    if (o.time_s < params.trigger.time_s) return;
    for (std::size_t i = 0; i < params.tdbs.size(); ++i) {
      const TdbParams& t = params.tdbs[i];
      const double race_surface = o.tdb[i].tdb_spin_rad_s * InnerRaceRadius(t);
      const double journal_surface = o.spin_speed_rad_s * t.journal_radius_m;
      if (!spinup.count(t.name) && race_surface >= 0.95 * journal_surface) {
        spinup[t.name] = o.time_s - params.trigger.time_s;
      }
    }
  });
  for (const TdbParams& t : params.tdbs) {
    if (r.status != StepStatus::kOk || !spinup.count(t.name)) spinup[t.name] = -1.0;
  }
  return spinup;
}

std::vector<SpinUpCandidate> ExplainSpinUpTimes(const ModelParams& rig,
                                                const std::map<std::string, double>& measured) {
  const double before = RmsRelative(TdbSpinUpTimes(rig), measured);
  std::vector<SpinUpCandidate> out;
  for (const Knob& knob : Knobs(rig)) {
    OneKnob problem(rig, knob, measured);
    const double declared = knob.get(rig);
    // From the declared value and from the middle of each half of the range.
    const double u =
        std::clamp(2.0 * (declared - knob.lower) / (knob.upper - knob.lower) - 1.0, -1.0, 1.0);
    for (const double start : {std::asin(u), -0.5, 0.5}) {
      Eigen::VectorXd z(1);
      z(0) = start;
      Eigen::LevenbergMarquardt<OneKnob> lm(problem);
      lm.setMaxfev(15);
      lm.minimize(z);
    }
    SpinUpCandidate c;
    c.name = knob.name;
    c.parameter = knob.parameter;
    c.declared = declared;
    c.fitted = problem.Value(problem.best_z);
    ModelParams p = rig;
    knob.set(c.fitted, &p);
    c.times_s = TdbSpinUpTimes(p);
    c.rms_before = before;
    c.rms_after = RmsRelative(c.times_s, measured);
    out.push_back(c);
  }
  std::stable_sort(out.begin(), out.end(), [](const SpinUpCandidate& a, const SpinUpCandidate& b) {
    return a.rms_after < b.rms_after;
  });
  return out;
}

}  // namespace ambdrop
