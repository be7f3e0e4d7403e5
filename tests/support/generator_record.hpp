#pragma once
// A record of the independent truth generator (tools/truth, no code shared with ambdrop), read
// as `ambdrop fit` reads it: for the tests that link ambdrop::truth.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include "drop_run.hpp"
#include "effects.hpp"
#include "io/files/measured_record_si.hpp"
#include "record_files.hpp"
#include "rig.hpp"
#include "scratch_directory.hpp"

namespace ambdrop::testing {

/// The record of `effect` drawn from `seed` on the generator's rig `rig` (tools/truth/rigs/
/// RIG.json), in acquisition units through `m`; `truth`, if given, receives what was hidden;
/// `adjust`, if given, changes the rig sheet first (e.g. its acquisition).
inline MeasuredRecord GeneratorRecord(const std::string& rig_name, const std::string& effect,
                                      std::uint64_t seed, const MeasurementParams& m,
                                      ambdrop_truth::Truth* truth = nullptr,
                                      const std::function<void(ambdrop_truth::Rig*)>& adjust = {}) {
  ambdrop_truth::Rig rig = ambdrop_truth::ReadRig(std::string(AMBDROP_SOURCE_DIR) +
                                                  "/tools/truth/rigs/" + rig_name + ".json");
  if (adjust) adjust(&rig);
  const ambdrop_truth::Truth hidden = ambdrop_truth::ApplyEffect(effect, seed, &rig);
  if (truth != nullptr) *truth = hidden;
  const ambdrop_truth::RunResult run = ambdrop_truth::RunDrop(rig, seed, {});
  EXPECT_TRUE(run.finite);
  const ScratchDirectory dir("generator_record");
  const std::filesystem::path csv = dir.path() / "record.csv";
  ambdrop_truth::WriteRecordCsv(csv, rig, run, ambdrop_truth::CsvUnits::kAcquisition);
  return ReadMeasuredRecord(csv, m);
}

/// The rigid rig's (rigid_rotor_a).
inline MeasuredRecord RigidGeneratorRecord(const std::string& effect, std::uint64_t seed,
                                           const MeasurementParams& m,
                                           ambdrop_truth::Truth* truth = nullptr) {
  return GeneratorRecord("rigid_rotor_a", effect, seed, m, truth);
}

}  // namespace ambdrop::testing
