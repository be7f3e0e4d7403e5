#pragma once
// The seed papers' published numbers and trends that `ambdrop validate` checks, case by case.
// Each case loads its rig from configs/ and returns its checks; the validation tests
// (tests/*_validation_test.cpp) run the same cases and assert them.
#include <functional>
#include <string>
#include <vector>

#include "tools/validation/validation_check.hpp"

namespace ambdrop {

struct ValidationCase {
  std::string name;         ///< e.g. "seed000_table3"
  std::string description;  ///< the paper and what is compared
  std::function<std::vector<ValidationCheck>(const std::string& configs_dir)> run;
};

/// Every case, in seed order.
std::vector<ValidationCase> AllValidationCases();

// Seed 000 (Jarroux 2019).
std::vector<ValidationCheck> Seed000SpinUpTable3(const std::string& configs_dir);
std::vector<ValidationCheck> Seed000ModelsDropAtRest(const std::string& configs_dir);

// Seed 001 (Jarroux 2016, Sec. 3): a larger rotor / inner-race clearance raises the TDB load;
// after the transient the rotor rocks, or whirls backward with high friction and low support
// damping.
std::vector<ValidationCheck> Seed001Trends(const std::string& configs_dir);

// Seed 002 (Chen et al., ITRI, Sec. IV): drops at 18 000, 14 000, 10 000 rpm: peak contact
// forces and their speed trend, displacements within the critical clearance, and the support
// Ks, Cs lowering the contact forces after 0.1 s.
std::vector<ValidationCheck> Seed002DropSpeeds(const std::string& configs_dir);

// Seed 003 (double-decker catcher bearing, Sec. 3): DDCB vs SDCB peak contact force and
// vibration amplitude; the intermediate race's share of the inner race speed.
std::vector<ValidationCheck> Seed003DoubleDecker(const std::string& configs_dir);

// Seed 004 (Zhu & Zhang, Fig. 5(a)): the recommended metal rubber ring against a rigid mount
// and its neighbours on the Krr / Crr decade grid, by peak impact force at 12 000 rpm.
std::vector<ValidationCheck> Seed004MetalRubberRing(const std::string& configs_dir);

}  // namespace ambdrop
