#pragma once
#include "rt_core/ball_row.hpp"
#include "rt_core/touchdown_bearing.hpp"

namespace ambdrop {

/// Catcher-bearing TDB of seed 003 (single- and double-decker, Sec. 2.2-2.3, Fig. 2, 4, 5,
/// Table 2) and seed 004 (auxiliary bearing on a metal rubber ring, Zhu & Zhang Sec. 2.2, Fig. 4,
/// Eq. (2)-(3), Table 1). One model, because seed 004's bearing is seed 003's single-decker with
/// a flexibly mounted housing:
///   - journal / inner race: the impact function, seed 003 Eq. (1)-(2), on the penetration
///     beyond the clearance; regularised Coulomb friction (Jarroux 2019 Eq. (11)) on the slip;
///   - inner race (mass, x, y, spin): decks = 1, one ball bearing to the housing (SDCB, seed 004's
///     AB); decks = 2, a ball bearing to the intermediate race (mass, x, y, spin) and a second
///     one from it to the housing (DDCB). Each bearing sums its balls' Hertz contacts (Eq. (1)
///     with e = 3/2, Table 2's stiffnesses and clearance), the balls carried round by the cage;
///   - race spin, seed 004 Eq. (3) generalised to two decks:
///       J_i w_i' = Ft Rb - T_1(w_i - w_m),   J_m w_m' = T_1(w_i - w_m) - T_2(w_m),
///     T the bearings' friction moments (viscous + Palmgren load moment);
///   - housing: rigid, or seed 004 Eq. (2): house mass m_o on the ring, m_o x_o'' = F_b - Krr x_o
///     - Crr x_o'.
/// Races and house carry their weight; misalignment moves the housing centre. Positions are
/// relative to the housing's (undeflected) centre.
class CatcherBearingTdb final : public TouchdownBearing {
 public:
  /// Layout of one race's block of states.
  enum RaceState : int {
    kSpin = 0,  ///< race speed (rad/s)
    kX,         ///< race centre x, y (m), vx, vy (m/s)
    kY,
    kVx,
    kVy,
    kCage,  ///< cage angle (rad) of the ball bearing outside this race
  };
  static constexpr int kRaceStates = 6;
  /// Layout of the house block (metal rubber ring): x, y (m), vx, vy (m/s).
  enum HouseState : int { kHouseX = 0, kHouseY, kHouseVx, kHouseVy };
  static constexpr int kHouseStates = 4;

  /// Derives the bearings' coefficients; throws std::invalid_argument on unusable parameters.
  explicit CatcherBearingTdb(const TdbParams& params);
  int StateSize() const noexcept override { return state_size_; }
  /// Races (and house) at rest in their static equilibrium under gravity, spins zero.
  void InitialState(double* state) const noexcept override;
  void Evaluate(const JournalMotion& journal, const double* state, double* state_rate,
                TdbForce* out) const noexcept override;

  /// Offsets of the blocks in the state: inner race 0; intermediate race and house, -1 if absent.
  int intermediate_offset() const noexcept { return intermediate_; }
  int house_offset() const noexcept { return house_; }
  const BallRow& inner_bearing() const noexcept { return inner_bearing_; }
  const BallRow& outer_bearing() const noexcept { return outer_bearing_; }

 private:
  BallRow inner_bearing_;
  BallRow outer_bearing_;  ///< decks = 2 only
  int intermediate_ = -1;
  int house_ = -1;
  int state_size_ = kRaceStates;
};

}  // namespace ambdrop
