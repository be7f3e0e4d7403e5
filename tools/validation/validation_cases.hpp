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

}  // namespace ambdrop
