#include "rt_core/tdb_factory.hpp"

#include <stdexcept>

#include "rt_core/ball_bearing_tdb.hpp"
#include "rt_core/catcher_bearing_tdb.hpp"
#include "rt_core/contact_law_tdb.hpp"
#include "rt_core/four_dof_tdb.hpp"

namespace ambdrop {

std::unique_ptr<TouchdownBearing> MakeTouchdownBearing(const TdbParams& params) {
  switch (params.model()) {
    case TdbModelKind::kContactLaw:
      return std::make_unique<ContactLawTdb>(params);
    case TdbModelKind::kFourDof:
      return std::make_unique<FourDofTdb>(params);
    case TdbModelKind::kBallBearing:
      return std::make_unique<BallBearingTdb>(params);
    case TdbModelKind::kCatcherBearing:
      return std::make_unique<CatcherBearingTdb>(params);
  }
  throw std::invalid_argument("tdb '" + params.name + "': unknown model");
}

}  // namespace ambdrop
