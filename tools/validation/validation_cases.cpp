#include "tools/validation/validation_cases.hpp"

namespace ambdrop {

std::vector<ValidationCase> AllValidationCases() {
  return {
      {"seed000_table3", "Jarroux 2019 Table 3: TDB spin-up times, drop at 6500 rpm",
       Seed000SpinUpTable3},
      {"seed000_models", "Jarroux 2019 Sec. 6.1: TDB models #1, #2, #3, drop at rest",
       Seed000ModelsDropAtRest},
      {"seed001_trends",
       "Jarroux 2016 Sec. 3: clearance vs TDB load; rocking vs backward whirl (friction, support "
       "damping)",
       Seed001Trends},
      {"seed002_speeds",
       "Chen et al. (ITRI) Sec. IV: contact forces and displacements at 18 000-10 000 rpm; "
       "support Ks, Cs",
       Seed002DropSpeeds},
      {"seed003_ddcb",
       "Double-decker catcher bearing Sec. 3: DDCB vs SDCB force and amplitude; intermediate "
       "race speed",
       Seed003DoubleDecker},
      {"seed004_ring",
       "Zhu & Zhang Fig. 5(a): recommended metal rubber ring vs rigid mount and grid neighbours",
       Seed004MetalRubberRing},
  };
}

}  // namespace ambdrop
