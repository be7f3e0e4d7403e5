#pragma once
// The `declared_off` effect (issue 23): one number of the rig sheet is off in the truth run, the
// model form is right. Every entry is a number of the sheet with its ambdrop key: the rotor's
// mass, inertias and centre of mass (a flexible shaft: each disc's mass, inertias and station,
// each segment's diameter, the material's modulus and density); per AMB its constant, bias,
// nominal gap and station; per sensor its station and each axis's gain and offset; the
// controller's gains, filter and delay (a firmware controller: each section's numbers, the
// current loop's bandwidth and slew limit); the power-loss ramp's slew rate and the windage;
// per TDB its station, clearance, journal radius, friction, race and contact numbers.
// What the sheet has and this list leaves out is said in README.md (and why).
//
// A draw: sizes by a factor 1 +- (0.15 .. 0.4); offsets (declared 0) by +-(5 .. 30) um;
// stations by +-(0.15 .. 0.4) of the distance to the nearest other station (so each stays
// between its neighbours); the computation delay from one period to two (ambdrop delays in
// whole samples). A draw whose truth rig does not levitate (below) is drawn again.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "effects.hpp"
#include "rig.hpp"

namespace ambdrop_truth {

/// How an entry's true value is drawn from its declared one.
enum class OffKind {
  kFactor,   ///< x (1 +- 0.15..0.4)
  kOffset,   ///< declared 0: +-(5..30) um
  kStation,  ///< +-(0.15..0.4) of the distance to the nearest other station
  kDelay,    ///< one controller period more
  /// A radius that sits a small gap from another (the inner race's from the journal's): the
  /// gap x (1 +- 0.15..0.4), so that the race's bore still surrounds the journal.
  kGapTo,
};

struct DeclaredEntry {
  std::string name;  ///< the generator's field path, as `--effect declared_off:NAME` takes it
  OffKind kind = OffKind::kFactor;
  std::function<double*(Rig*)> field;         ///< the rig field it changes
  std::function<double(const Rig&)> partner;  ///< kGapTo: the other radius (m)
  /// What moves with it in the generator (may be empty): the inner-race radius, which the
  /// sheet does not give, stays the journal radius.
  std::function<void(Rig*)> follow;
  std::string ambdrop_key;  ///< the `--set` key that carries it in ambdrop's terms
  /// Further keys that carry the same value (a rig-wide number that ambdrop declares per AMB).
  std::vector<std::string> also_ambdrop_keys;
  /// The ambdrop value for a generator value (identity unless the translation converts).
  std::function<std::string(const Rig&, double)> ambdrop_value;
  std::string mapping = "exact";  ///< "exact" or "approximate"
  std::string mapping_note;
};

/// Every entry for this rig (its AMB, sensor and TDB names), in a fixed order.
std::vector<DeclaredEntry> DeclaredOffEntries(const Rig& rig);

/// One draw, before the levitation check: which entry, its declared and true values.
struct DeclaredOffDraw {
  std::size_t entry = 0;
  double declared = 0.0;
  double value = 0.0;
};

/// The draw for `seed` at `attempt` (0, 1, ...: each attempt its own stream); `entry` < 0 draws
/// the entry too, uniformly. Clamped to what stays physical. Pure: the same inputs, the same
/// draw.
DeclaredOffDraw DrawDeclaredOff(const Rig& declared, const std::vector<DeclaredEntry>& entries,
                                int entry, std::uint64_t seed, int attempt);

/// How many draws an effect gets before its generator gives up on a rig that levitates.
inline constexpr int kMaxLevitationDraws = 20;

/// Whether `rig`'s loop holds its rotor: levitated without power loss (the record's noise, seed
/// `seed`) for its trigger time and at least 0.3 s, the run stays finite, the journal never
/// comes within half a clearance of a TDB, and the rotor's motion at the sensors about its set
/// point, rms over the last quarter, is below 5 um and at most twice the second quarter's (an
/// unstable loop's oscillation grows out of the noise, a slow one still small at the trigger).
bool Levitates(const Rig& rig, std::uint64_t seed);

/// A draw applied to `rig` (its field, and what follows it), and its truth; `attempt` > 0 says
/// that earlier draws did not levitate. No levitation check.
Truth ApplyDraw(const std::vector<DeclaredEntry>& entries, const DeclaredOffDraw& draw, int attempt,
                Rig* rig);

/// The effect: `entry_name` empty draws the entry. Redraws (attempt 1, 2, ...) while the truth
/// rig does not levitate (Levitates); throws std::runtime_error after 20 attempts,
/// std::invalid_argument for an unknown entry.
Truth ApplyDeclaredOff(const std::string& entry_name, std::uint64_t seed, Rig* rig);

}  // namespace ambdrop_truth
