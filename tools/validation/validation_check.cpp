#include "tools/validation/validation_check.hpp"

#include <fmt/format.h>

namespace ambdrop {

ValidationCheck NumberCheck(std::string case_name, std::string quantity, double published,
                            double value, double tolerance, const char* unit) {
  ValidationCheck c;
  c.case_name = std::move(case_name);
  c.quantity = std::move(quantity);
  c.published = fmt::format("{:.4g} {}", published, unit);
  c.ambdrop = fmt::format("{:.4g} {}", value, unit);
  c.deviation = (value - published) / published;
  c.criterion = fmt::format("within {:.0f} %", tolerance * 100.0);
  c.pass = std::isfinite(c.deviation) && std::abs(c.deviation) <= tolerance;
  return c;
}

ValidationCheck TrendCheck(std::string case_name, std::string quantity, std::string published,
                           std::string ambdrop, bool holds) {
  ValidationCheck c;
  c.case_name = std::move(case_name);
  c.quantity = std::move(quantity);
  c.published = std::move(published);
  c.ambdrop = std::move(ambdrop);
  c.criterion = "trend";
  c.pass = holds;
  return c;
}

}  // namespace ambdrop
