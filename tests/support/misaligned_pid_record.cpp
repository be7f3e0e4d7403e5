#include "misaligned_pid_record.hpp"

#include "test_configs.hpp"

namespace ambdrop::testing {

SyntheticMeasurement MisalignedPidRecord(const std::vector<std::string>& timing) {
  std::vector<std::string> truth = timing;
  for (const char* o : {"simulation.step_s=2.5e-6", "tdb.de.misalignment.enabled=true",
                        "tdb.de.misalignment.x_m=2e-5", "tdb.de.misalignment.y_m=-4e-5"}) {
    truth.push_back(o);
  }
  MeasureOptions noise;
  noise.current_noise_A = 0.005;
  return MakeMeasuredRecord(LoadTestConfig(kPidRig, truth), noise);
}

}  // namespace ambdrop::testing
