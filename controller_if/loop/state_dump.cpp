#include "controller_if/loop/state_dump.hpp"

#include <iomanip>
#include <sstream>

namespace ambdrop {
namespace {

void DumpState(const Model& m, const State& s, std::ostringstream& o) {
  const int n = m.modes();
  o << "  step " << s.step_index << ", t = " << s.step_index * m.params.simulation.step_s << " s, "
    << (s.power_on ? "powered" : "after the power failure") << "\n";
  o << "  spin speed " << s.y(m.spin_index()) << " rad/s, spin angle " << s.y(m.spin_angle_index())
    << " rad\n  q  =";
  for (int i = 0; i < n; ++i) o << ' ' << s.y(i);
  o << "\n  q' =";
  for (int i = 0; i < n; ++i) o << ' ' << s.y(n + i);
  o << "\n";
  for (std::size_t i = 0; i < m.tdbs.size(); ++i) {
    const TdbParams& p = m.tdbs[i]->params();
    const Eigen::Vector2d xy = m.tdb_shapes[i] * s.y.head(n);
    o << "  tdb " << p.name << ": journal (" << xy(0) << ", " << xy(1)
      << ") m = " << xy.norm() / p.clearance_m << " clearances; states";
    for (int k = 0; k < m.tdbs[i]->StateSize(); ++k) o << ' ' << s.y(m.tdb_state_offset[i] + k);
    o << "\n";
  }
}

}  // namespace

std::string DescribeFailure(const Model& m, StepStatus status, const State& after) {
  std::ostringstream o;
  o << std::setprecision(17);
  o << "simulation diverged at t = " << after.step_index * m.params.simulation.step_s << " s: ";
  switch (status) {
    case StepStatus::kNonFinite:
      o << "a state became non-finite (NaN or infinite)";
      break;
    case StepStatus::kExcursionBound:
      o << "a journal left its touchdown bearing by more than "
        << m.params.simulation.max_excursion_over_clearance << " clearances";
      break;
    case StepStatus::kOk:
      o << "no failure";
      break;
  }
  o << " (try a smaller simulation.step_s, or check stiffness and clearance values)\n";
  o << "state after the failing step:\n";
  DumpState(m, after, o);
  return o.str();
}

}  // namespace ambdrop
